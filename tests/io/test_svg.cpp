// SPDX-License-Identifier: MIT
#include "cifs/io/svg.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"

using namespace cifs;
using namespace cifs::io;
using automata::StateId;

namespace {

std::size_t count_in_svg(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("SVG of segment sets: runs joined, branches restarted", "[io][svg]") {
  Segments s;
  s.vertices.resize(4, 2);
  s.vertices << 0, 0, 1, 0, 1, 1, 2, 2;
  s.segments = {{0, 1}, {1, 2}, {1, 3}};
  const std::string svg = segments_svg(s);
  CHECK_THAT(svg, Catch::StartsWith("<svg"));
  // Two runs: M a L b L c, then M b L d.
  const std::size_t d = svg.find(" d=\"");
  REQUIRE(d != std::string::npos);
  const std::string path = svg.substr(d + 4, svg.find('"', d + 4) - d - 4);
  CHECK(std::count(path.begin(), path.end(), 'M') == 2);
  CHECK(std::count(path.begin(), path.end(), 'L') == 3);
  // Framing: x from 40 to 760 (5 % margins of 800), y up.
  CHECK_THAT(path, Catch::StartsWith("M40.000,760.000 L400.000,760.000 L400.000,400.000 M400.000,760.000"));
  // The polyline SVG is the same writer.
  Points p(3, 2);
  p << 0, 0, 1, 0, 1, 1;
  CHECK_THAT(polyline_svg(p), Catch::Contains("M40.000,760.000 L760.000,760.000 L760.000,40.000\""));
}

TEST_CASE("SVG writers refuse bad segments", "[io][svg]") {
  Segments s;
  s.vertices = Points::Zero(2, 2);
  s.segments = {{0, 1}};
  CHECK_THROWS_AS(segments_svg(s, SvgOptions{.width = 10, .stroke = 1.5, .color = "black"}), InvalidInput);
}

TEST_CASE("Multi-stroke SVG: one element per stroke, fitted together, a legend of the labelled ones",
          "[io][svg]") {
  Points square(4, 2), segment(2, 2);
  square << 0, 0, 2, 0, 2, 1, 0, 1;
  segment << 0, 0, 1, 1;
  const std::vector<Stroke> strokes{{square, true, "#ff0000", 2, "4 3", "the square"},
                                    {segment, false, "#00ff00", 1, "", ""}};
  const std::string svg = strokes_svg(strokes, "Title", 420);
  CHECK_THAT(svg, Catch::StartsWith("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"420\"") &&
                      Catch::EndsWith("</svg>\n"));
  CHECK(count_in_svg(svg, "<polygon ") == 1);
  CHECK(count_in_svg(svg, "<polyline ") == 1);
  CHECK(count_in_svg(svg, "<line ") == 1);  // only the labelled stroke is in the legend
  CHECK_THAT(svg, Catch::Contains(">Title</text>") && Catch::Contains(">the square</text>") &&
                      Catch::Contains("stroke-dasharray=\"4 3\""));
  // Width 420 with 20 px margins: 2 units of x span 380 px, so the scale is 190 px per unit; y is
  // flipped below a 26 px title band: (x, y) → (20 + 190·x, 26 + 20 + 190·(1 − y)).
  CHECK_THAT(svg, Catch::Contains("points=\"20,236 400,236 400,46 20,46\""));
  CHECK_THAT(svg, Catch::Contains("points=\"20,236 210,46\""));
}

TEST_CASE("Automaton SVG: one circle per state, one arrow per connected pair", "[io][svg]") {
  const nurbs::Curve c = nurbs::make_curve(3, {0, 0, 0, 0, 1, 3, 3.5, 6, 6, 6, 6}, Points::Random(7, 2));
  const nurbs::KnotAutomaton ka = nurbs::knot_automaton(c);
  const automata::Automaton& a = ka.automaton;
  const std::string svg = to_svg(a);
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  std::set<std::pair<StateId, StateId>> pairs;
  for (const automata::TransitionId e : edges(a.graph))
    pairs.insert({source(e, a.graph), target(e, a.graph)});
  CHECK_THAT(svg, Catch::StartsWith("<svg ") && Catch::EndsWith("</svg>\n"));
  CHECK(count("<circle ") == num_vertices(a.graph));
  CHECK(count("marker-end=") == pairs.size());
  CHECK(count("stroke-width=\"2.5\"") == a.initial.size());  // initial states in bold
}

TEST_CASE("SVG of coordinates near the largest double: finite pixels, non-finite points refused",
          "[io][svg]") {
  // Found by fuzz_writers: the span hi − lo overflowed to inf, the scale became 0 and every pixel
  // coordinate 0 · inf = nan, written without a word.
  Points P(3, 2);
  P << -1.7e308, 0, 1.7e308, 1, 0, 1.7e308;
  for (const std::string& svg :
       {polyline_svg(P, true),
        strokes_svg(
            {Stroke{.points = P, .closed = true, .colour = "#000", .width = 1, .dash = "", .label = "huge"}},
            "huge")}) {
    CHECK(svg.find("nan") == std::string::npos);
    CHECK(svg.find("inf") == std::string::npos);
  }
  // The same picture as at a moderate scale: pixels depend on the shape, not on its size.
  CHECK(polyline_svg(P, true) == polyline_svg(P * std::ldexp(1.0, -1000), true));
  P(1, 0) = NAN;
  CHECK_THROWS_AS(polyline_svg(P), InvalidInput);
  CHECK_THROWS_WITH(
      strokes_svg(
          {Stroke{.points = P, .closed = true, .colour = "#000", .width = 1, .dash = "", .label = ""}},
          "nan"),
      Catch::Contains("not a finite number"));
  // A figure without points, or narrower than its margins, had an infinite or negative height.
  CHECK_THROWS_WITH(strokes_svg({Stroke{}}, "empty"), Catch::Contains("none is given"));
  P(1, 0) = 0;
  CHECK_THROWS_WITH(
      strokes_svg(
          {Stroke{.points = P, .closed = true, .colour = "#000", .width = 1, .dash = "", .label = ""}},
          "narrow", 16),
      Catch::Contains("outside [64, 100000]"));
}
