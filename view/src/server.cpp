// SPDX-License-Identifier: MIT
// The HTTP server of `cifs view` (cpp-httplib: header-only, MIT, in Debian) around the pure handler,
// and the static export.
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/view/server.hpp"
#include "web_files.hpp"

// Last: <resolv.h>, which httplib includes, defines the macro _res, a parameter name in Eigen.
#include <httplib.h>

namespace cifs::view {

namespace {

void answer(Session& session, const httplib::Request& req, httplib::Response& res) {
  const auto begun = std::chrono::steady_clock::now();
  Response r = handle(
      session,
      {.method = req.method, .target = req.target, .host = req.get_header_value("Host"), .body = req.body});
  // The page's timing of an edit tells cifs's share (waiting for a running evaluation included) from HTTP's.
  const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - begun;
  res.set_header("Server-Timing", "cifs;dur=" + std::to_string(took.count()));
  res.status = r.status;
  res.body = std::move(r.body);  // what set_content does, without copying megabytes of geometry
  res.set_header("Content-Type", r.content_type);
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Content-Type-Options", "nosniff");
}

/// xdg-open the URL in the background; a missing xdg-open is a warning, the URL is printed anyway.
void open_url(const std::string& url) {
  const std::string command = "xdg-open '" + url + "' >/dev/null 2>&1 &";
  if (std::system(command.c_str()) != 0) std::cerr << "cifs: warning: xdg-open failed; open " << url << "\n";
}

}  // namespace

void serve(const std::filesystem::path& path, const ServeOptions& options) {
  Session session;
  httplib::Server server;
  // httplib's default also sets SO_REUSEPORT: a second cifs view on the port would share it silently.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  int port = options.port;
  if (port == 0) {
    port = server.bind_to_any_port(options.host);
  } else if (!server.bind_to_port(options.host, port)) {
    port = -1;
  }
  if (port < 0)
    throw IoError("cifs view: cannot listen on " + options.host + ":" + std::to_string(options.port) +
                  " (in use? try another --port)");
  open_session(session, path, options.host, port);
  server.set_payload_max_length(session.max_body);
  server.set_keep_alive_max_count(100);
  const auto handler = [&session](const httplib::Request& req, httplib::Response& res) {
    answer(session, req, res);
  };
  server.Get(".*", handler);
  server.Post(".*", handler);
  const std::string url = "http://" + options.host + ":" + std::to_string(port) + "/?token=" + session.token;
  if (options.listening) options.listening(url);
  if (options.open) open_url(url);
  server.listen_after_bind();
}

void export_page(const std::filesystem::path& path, const std::filesystem::path& folder) {
  const Document document = open_document(path);
  const Params params = default_params(document);
  const Geometry g = geometry(document, params);
  std::filesystem::create_directories(folder);
  // Session's document description, and the geometry as base64 (a classic script: file:// allows no fetch).
  Session session;
  session.document = document;
  session.folder = std::filesystem::absolute(path).parent_path();
  session.token = random_token();
  session.hosts = {"export"};
  session.limits.max_files = 0;  // a page to share does not list the folder's other files
  const Response description = handle(
      session,
      {.method = "GET", .target = "/api/document?token=" + session.token, .host = "export", .body = {}});
  if (description.status != 200) throw InvalidInput(description.body);
  // The automaton beside the geometry; none for a mesh or an experiment the runner draws (404).
  const Response automaton = handle(
      session,
      {.method = "GET", .target = "/api/automaton.svg?token=" + session.token, .host = "export", .body = {}});
  const std::string svg = automaton.status == 200 ? automaton.body : "";
  const std::string bytes = encode_geometry(g);
  static constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  b64.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    b64 += kBase64[(v >> 18) & 63];
    b64 += kBase64[(v >> 12) & 63];
    b64 += i + 1 < bytes.size() ? kBase64[(v >> 6) & 63] : '=';
    b64 += i + 2 < bytes.size() ? kBase64[v & 63] : '=';
  }
  std::string svg_json;  // the SVG as a JSON string
  for (const char c : svg) {
    if (c == '"' || c == '\\') svg_json += '\\';
    if (c == '\n') {
      svg_json += "\\n";
      continue;
    }
    if (c == '<') {
      svg_json += "\\u003c";
      continue;
    }  // no "</script>" inside the script
    svg_json += c;
  }
  const std::string baked = "window.cifsBaked = {document: " + description.body + ", automaton: \"" +
                            svg_json + "\", geometry: \"" + b64 + "\"};\n";
  write_file_atomically(folder / "index.html", web::kIndexHtml);
  write_file_atomically(folder / "view.js", web::kViewJs);
  write_file_atomically(folder / "geometry.js", baked);
  std::filesystem::create_directories(folder / "three");
  write_file_atomically(folder / "three/three.min.js", read_file(web::three_file("three.min.js")));
  write_file_atomically(folder / "three/OrbitControls.js", read_file(web::three_file("OrbitControls.js")));
}

}  // namespace cifs::view
