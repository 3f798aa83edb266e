// SPDX-License-Identifier: MIT
// cifs — the server of `cifs view`: the request handler as a pure function of the session and the
// request (tested without sockets), the HTTP server around it (cpp-httplib, 127.0.0.1 by default),
// and the static export of the page with its geometry baked in.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>

#include "cifs/view/document.hpp"

namespace cifs::view {

struct Request {
  std::string method;  // "GET", "POST"
  std::string target;  // the raw request target: path and query, still percent-encoded
  std::string host;    // the Host header
  std::string body;
};

struct Response {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
};

/// What a server holds: the opened document, the page's token, the hosts it answers to.
struct Session {
  Document document;
  std::filesystem::path folder;    // the document's folder: the only one read (open) and written (save)
  std::string token;               // random, in the URL: every /api/ request carries it
  std::vector<std::string> hosts;  // Host headers accepted ("127.0.0.1:8765", "localhost:8765")
  Limits limits;
  std::size_t max_body = std::size_t{1} << 20;
  /// Geometry requests are numbered; one evaluates at a time, and one that a newer one has overtaken
  /// while it waited is answered 409 without evaluating (the page has moved on).
  std::atomic<std::uint64_t> latest{0};
  std::mutex evaluating;
  std::mutex document_mutex;  // open replaces the document
  /// What geometry requests keep for the next one (under `evaluating`): the automaton, a perturbed
  /// shape's system, the surface mesh, and the last geometry's buffers, written over by the next.
  EditCache cache;
  Geometry geometry;
};

/// A session for `path`: the document opened, a fresh random token, the hosts of `host`:`port`.
void open_session(Session& session, const std::filesystem::path& path, const std::string& host, int port);

/// A 32-hex-digit token from std::random_device.
std::string random_token();

/// Answers one request (routes: docs/view.md). Never throws: refusals are 4xx with a one-line
/// "cifs view: <where>: <what>" body; 403 for a foreign Host or a missing token, 404 for an unknown
/// path, 400 for bad JSON or parameters, 413 for a body above max_body, 422 for an edit that makes the
/// system non-contractive (the library's message, with δ).
Response handle(Session& session, const Request& request);

struct ServeOptions {
  std::string host = "127.0.0.1";
  int port = 8765;    // 0: any free port
  bool open = false;  // xdg-open the URL
  /// Called with the URL once the server listens (the CLI prints it).
  std::function<void(const std::string&)> listening;
};

/// Serves `path` until the process is stopped. IoError when the port cannot be bound.
void serve(const std::filesystem::path& path, const ServeOptions& options);

/// Writes the page of `path` with default_params's geometry baked in (index.html, view.js, three.js,
/// geometry.js) into `folder`, each file atomically. Opens from file:// without a server.
void export_page(const std::filesystem::path& path, const std::filesystem::path& folder);

}  // namespace cifs::view
