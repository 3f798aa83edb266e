// SPDX-License-Identifier: MIT
// cifs — the gallery's index page (HTML, written only).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace cifs::io {

/// One section of the page: an experiment (or a group of figures) and the files it wrote.
struct GallerySection {
  std::string name;
  std::string description;
  /// Paths relative to the page's folder ("hills.png", "schemes/compare_bone.svg"), in the order shown.
  std::vector<std::filesystem::path> files{};
  /// Per file (same order; may be shorter): a caption under its image, e.g. an SVG figure's title.
  std::vector<std::string> captions{};
};

/// `text` with &, <, >, " and ' replaced by their character references: safe in element content
/// and in quoted attribute values.
std::string html_escape(std::string_view text);

/// A relative link to `file` for an href or src: its generic form ('/' separators) with every byte
/// outside the URL's unreserved characters and '/' percent-encoded (a space is %20, '#' %23).
/// Throws InvalidInput for an empty, absolute or rooted path, or one with a ".." component: the
/// page links only to files in its folder or below, so that the folder can be moved whole.
std::string relative_href(const std::filesystem::path& file);

/// A self-contained page (inline CSS, no script, nothing fetched from the network): per section its
/// name, description, its images (PNG, SVG) as a grid of captioned thumbnails, and a link to every other
/// file (EXR, OBJ, PLY, JSON, DOT, …) by its name. A thumbnail opens its image full size over the page
/// (a CSS :target viewer, `#v<k>` for the k-th image of the page) with links to the previous and next
/// image, the file, and back to the thumbnail (`#f<k>`): links only, so the keyboard (Tab, Enter) reaches
/// everything. Text is escaped (html_escape), links are relative (relative_href).
std::string gallery_html(const std::vector<GallerySection>& sections, const std::string& title);

}  // namespace cifs::io
