// SPDX-License-Identifier: MIT
// The gallery page's writer: escaped text, relative percent-encoded links, images shown, files linked.
#include <catch2/catch.hpp>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/io/html.hpp"

using namespace cifs;

namespace {

std::size_t count_in_html(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

}  // namespace

TEST_CASE("html_escape replaces the five characters of markup", "[io][html]") {
  CHECK(io::html_escape(R"(a<b>&"c"'d')") == "a&lt;b&gt;&amp;&quot;c&quot;&#39;d&#39;");
  CHECK(io::html_escape("plain text, é") == "plain text, é");
  CHECK(io::html_escape("&amp;") == "&amp;amp;");  // escaped again: the text is not markup
}

TEST_CASE("relative_href percent-encodes and refuses paths outside the folder", "[io][html]") {
  CHECK(io::relative_href("hills.png") == "hills.png");
  CHECK(io::relative_href("schemes/lr_bone_degree3.svg") == "schemes/lr_bone_degree3.svg");
  // Hand-encoded: space 0x20, '#' 0x23, '&' 0x26, '%' 0x25, '?' 0x3F, '"' 0x22, 'é' C3 A9.
  CHECK(io::relative_href("a b#1&c%?\".png") == "a%20b%231%26c%25%3F%22.png");
  CHECK(io::relative_href("é.exr") == "%C3%A9.exr");
  CHECK_THROWS_WITH(io::relative_href("/tmp/out/hills.png"), Catch::Contains("not a path relative"));
  CHECK_THROWS_WITH(io::relative_href("../hills.png"), Catch::Contains("leaves the page's folder"));
  CHECK_THROWS_WITH(io::relative_href("a/../../b.png"), Catch::Contains("leaves"));
  CHECK_THROWS_AS(io::relative_href(""), InvalidInput);
}

TEST_CASE("gallery_html shows images, links the other files, escapes every text", "[io][html]") {
  const std::vector<io::GallerySection> sections{
      {.name = "hills <3",
       .description = R"(A "bicubic" surface & <b>its</b> mesh)",
       .files = {"hills.exr", "hills.png", "hills.ply", "hills mesh.SVG"}},
      {.name = "schemes",
       .description = "",
       .files = {"schemes/a.svg", "schemes/b.svg"},
       .captions = {"Chaikin <open>", ""}},
  };
  const std::string page = io::gallery_html(sections, "My <gallery>");
  CHECK(page.starts_with("<!DOCTYPE html>"));
  CHECK_THAT(page, Catch::Contains("<title>My &lt;gallery&gt;</title>"));
  CHECK_THAT(page, Catch::Contains("<h2>hills &lt;3</h2>"));
  CHECK_THAT(page, Catch::Contains("<p>A &quot;bicubic&quot; surface &amp; &lt;b&gt;its&lt;/b&gt; mesh</p>"));
  CHECK(page.find("<b>") == std::string::npos);
  // Four images (PNG, SVG of either case), each a captioned thumbnail and a viewer that links to the file;
  // the EXR and PLY are links.
  CHECK(count_in_html(page, "<img ") == 8);
  for (const char* src : {"hills.png", "hills%20mesh.SVG", "schemes/a.svg", "schemes/b.svg"}) {
    CHECK(count_in_html(page, std::string("src=\"") + src + "\"") == 2);
    CHECK(count_in_html(page, std::string("href=\"") + src + "\"") == 1);
  }
  CHECK_THAT(page, Catch::Contains("<a href=\"hills.exr\">hills.exr</a>"));
  CHECK_THAT(page, Catch::Contains("<a href=\"hills.ply\">hills.ply</a>"));
  CHECK(count_in_html(page, "href=") ==
        2 + 4 * 5);  // files; per image: thumbnail, previous, close, file, next
  CHECK_THAT(page, Catch::Contains("schemes/a.svg: Chaikin &lt;open&gt;</figcaption>"));
  // The grid, and the viewers numbered through the page: thumbnail k opens #v<k>, whose links wrap around.
  CHECK_THAT(page, Catch::Contains(".figures { display: grid;"));
  CHECK_THAT(page, Catch::Contains(".viewer:target { display: flex; }"));
  CHECK_THAT(page, Catch::Contains("<figure id=\"f2\"><a href=\"#v2\"><img src=\"schemes/a.svg\""));
  CHECK_THAT(page, Catch::Contains("<a class=\"previous\" href=\"#v3\">previous</a><a class=\"close\" "
                                   "href=\"#f0\">close</a><a class=\"file\" href=\"hills.png\">the file</a>"
                                   "<a class=\"next\" href=\"#v1\">next</a>"));
  CHECK_THAT(page, Catch::Contains("<a class=\"next\" href=\"#v0\">next</a>"));
  CHECK(count_in_html(page, "class=\"viewer\"") == 4);
  // A section without a description has no empty paragraph; self-contained: no script, no URL scheme.
  CHECK(count_in_html(page, "<p>") == 1);
  CHECK(page.find("<script") == std::string::npos);
  CHECK(page.find("://") == std::string::npos);
  CHECK(count_in_html(page, "<section>") == 2);
  CHECK_THROWS_WITH(io::gallery_html({{.name = "x", .description = "", .files = {"../x.png"}}}, "t"),
                    Catch::Contains("../x.png"));
}
