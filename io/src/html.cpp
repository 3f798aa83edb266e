// SPDX-License-Identifier: MIT
// cifs — the gallery's index page.
#include "cifs/io/html.hpp"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"

namespace cifs::io {
namespace {

bool is_image(const std::filesystem::path& file) {
  const std::string ext = extension_of(file);
  return ext == ".png" || ext == ".svg";
}

// The page's only style. Each section's images are a grid of cards (thumbnails on white, captioned), each a
// link to its viewer: an overlay shown by CSS alone while the page's address names it (:target), with the
// image as large as the window allows, its caption, the file, and links to the previous and next image and
// back to the card. Links are the whole interaction, so Tab, Shift+Tab and Enter reach everything (focus
// outlined).
constexpr const char* kStyle =
    R"(body { font-family: sans-serif; margin: 1.5em; background: #eceff1; color: #1d2327; }
h1 { font-size: 1.6em; }
section { margin: 1.5em 0; padding: 1em 1.2em; background: #fff; border: 1px solid #c9d0d5;
  border-radius: 8px; }
section h2 { margin: 0 0 0.3em; font-size: 1.25em; }
section p { margin: 0 0 0.9em; color: #3c454c; }
.figures { display: grid; grid-template-columns: repeat(auto-fill, minmax(220px, 1fr)); gap: 1em; }
figure { margin: 0; padding: 0.5em; border: 1px solid #c9d0d5; border-radius: 6px; background: #f7f9fa; }
figure img { display: block; width: 100%; height: 200px; object-fit: contain; background: #fff;
  border: 1px solid #dde2e5; }
figure a:hover img { border-color: #2a6df4; }
figcaption { margin-top: 0.4em; font-size: 0.9em; color: #1d2327; overflow-wrap: anywhere; }
ul.files { margin: 0.8em 0 0; padding-left: 1.2em; font-size: 0.9em; }
a:focus-visible { outline: 3px solid #2a6df4; outline-offset: 2px; }
.viewer { display: none; position: fixed; inset: 0; z-index: 1; background: rgba(16, 20, 24, 0.92);
  color: #f2f4f5; flex-direction: column; align-items: center; justify-content: center; gap: 0.6em; }
.viewer:target { display: flex; }
.viewer img { max-width: 92vw; max-height: 80vh; object-fit: contain; background: #fff; }
.viewer nav { display: flex; gap: 1.5em; font-size: 1.1em; }
.viewer a { color: #9cc3ff; }
)";

/// An image of the page: its card's and its viewer's ids come from its number.
struct Shown {
  std::string href, caption;  // caption: escaped text
};

}  // namespace

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string relative_href(const std::filesystem::path& file) {
  if (file.empty() || file.is_absolute() || file.has_root_path())
    throw InvalidInput("gallery page: " + file.string() + " is not a path relative to the page's folder");
  for (const auto& part : file)
    if (part == "..")
      throw InvalidInput("gallery page: " + file.string() + " leaves the page's folder (\"..\")");
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const char ch : file.generic_string()) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += ch;
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

std::string gallery_html(const std::vector<GallerySection>& sections, const std::string& title) {
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                    html_escape(title) + "</title>\n<style>\n" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
                    html_escape(title) + "</h1>\n";
  std::vector<Shown> images;  // in page order: card k has id "f<k>", its viewer "v<k>"
  for (const GallerySection& s : sections) {
    out += "<section>\n<h2>" + html_escape(s.name) + "</h2>\n";
    if (!s.description.empty()) out += "<p>" + html_escape(s.description) + "</p>\n";
    std::string figures, links;
    for (std::size_t i = 0; i < s.files.size(); ++i) {
      const std::string href = relative_href(s.files[i]), name = html_escape(s.files[i].generic_string());
      if (is_image(s.files[i])) {
        std::string caption = name;
        if (i < s.captions.size() && !s.captions[i].empty()) caption += ": " + html_escape(s.captions[i]);
        const std::string k = std::to_string(images.size());
        figures.append("<figure id=\"f")
            .append(k)
            .append("\"><a href=\"#v")
            .append(k)
            .append("\"><img src=\"");
        figures.append(href)
            .append("\" alt=\"")
            .append(caption)
            .append("\"></a><figcaption>")
            .append(caption);
        figures += "</figcaption></figure>\n";
        images.push_back({href, std::move(caption)});
      } else {
        links.append("<li><a href=\"").append(href).append("\">").append(name).append("</a></li>\n");
      }
    }
    if (!figures.empty()) out.append("<div class=\"figures\">\n").append(figures).append("</div>\n");
    if (!links.empty()) out.append("<ul class=\"files\">\n").append(links).append("</ul>\n");
    out += "</section>\n";
  }
  const std::size_t n = images.size();
  for (std::size_t k = 0; k < n; ++k) {  // the viewers, previous and next wrapping around
    const std::string id = std::to_string(k), previous = std::to_string((k + n - 1) % n),
                      next = std::to_string((k + 1) % n);
    out.append("<div class=\"viewer\" id=\"v").append(id).append("\" role=\"dialog\" aria-label=\"");
    out.append(images[k].caption).append("\">\n<img src=\"").append(images[k].href).append("\" alt=\"");
    out.append(images[k].caption).append("\">\n<div class=\"caption\">").append(images[k].caption);
    out.append("</div>\n<nav><a class=\"previous\" href=\"#v").append(previous).append("\">previous</a>");
    out.append("<a class=\"close\" href=\"#f").append(id).append("\">close</a>");
    out.append("<a class=\"file\" href=\"").append(images[k].href).append("\">the file</a>");
    out.append("<a class=\"next\" href=\"#v").append(next).append("\">next</a></nav>\n</div>\n");
  }
  out += "</body>\n</html>\n";
  return out;
}

}  // namespace cifs::io
