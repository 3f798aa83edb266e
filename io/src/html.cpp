// SPDX-License-Identifier: MIT
// cifs — the gallery's index page.
#include "cifs/io/html.hpp"

#include <algorithm>
#include <cctype>

#include "cifs/errors.hpp"

namespace cifs::io {
namespace {

bool is_image(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".svg";
}

// The page's only style: a grid of cards that wraps to the window's width, images scaled to fit.
constexpr const char* kStyle =
    R"(body { font-family: sans-serif; margin: 1.5em; background: #fafafa; color: #222; }
h1 { font-size: 1.6em; }
section { margin: 1.5em 0; padding: 1em; background: #fff; border: 1px solid #ddd; border-radius: 6px; }
section h2 { margin: 0 0 0.3em; font-size: 1.2em; }
section p { margin: 0 0 0.8em; }
.figures { display: flex; flex-wrap: wrap; gap: 1em; }
figure { margin: 0; max-width: 360px; }
figure img { max-width: 100%; max-height: 260px; border: 1px solid #eee; background: #fff; }
figcaption { font-size: 0.85em; color: #555; }
ul.files { margin: 0.6em 0 0; padding-left: 1.2em; font-size: 0.9em; }
)";

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
  for (const GallerySection& s : sections) {
    out += "<section>\n<h2>" + html_escape(s.name) + "</h2>\n";
    if (!s.description.empty()) out += "<p>" + html_escape(s.description) + "</p>\n";
    std::string figures, links;
    for (std::size_t i = 0; i < s.files.size(); ++i) {
      const std::string href = relative_href(s.files[i]), name = html_escape(s.files[i].generic_string());
      if (is_image(s.files[i])) {
        const std::string caption = i < s.captions.size() && !s.captions[i].empty() ? s.captions[i] : "";
        figures.append("<figure><a href=\"").append(href).append("\"><img src=\"").append(href);
        figures.append("\" alt=\"").append(name).append("\"></a><figcaption>").append(name);
        if (!caption.empty()) figures.append(": ").append(html_escape(caption));
        figures += "</figcaption></figure>\n";
      } else {
        links.append("<li><a href=\"").append(href).append("\">").append(name).append("</a></li>\n");
      }
    }
    if (!figures.empty()) out.append("<div class=\"figures\">\n").append(figures).append("</div>\n");
    if (!links.empty()) out.append("<ul class=\"files\">\n").append(links).append("</ul>\n");
    out += "</section>\n";
  }
  out += "</body>\n</html>\n";
  return out;
}

}  // namespace cifs::io
