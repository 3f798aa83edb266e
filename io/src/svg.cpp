// SPDX-License-Identifier: MIT
// cifs — SVG pictures: segment sets and polylines, multi-stroke figures, automata.
#include "cifs/io/svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "points_format.hpp"

namespace cifs::io {
namespace {

// The automaton drawing: state circles of radius kRadius on a grid of kColumn × kRow pixels, at
// most kMaxRows states per column.
constexpr double kRadius = 26, kColumn = 150, kRow = 78, kMargin = 40;
constexpr int kMaxRows = 7;

std::string fixed(double x) {
  return fixed_text(x, 1);
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string svg_dropped_coordinates(const Eigen::Ref<const Points>& points) {
  if (points.cols() <= 2 || points.rows() == 0) return {};
  const auto rest = points.rightCols(points.cols() - 2);
  if ((rest.array() == 0).all()) return {};
  const std::string axes = points.cols() == 3 ? "z" : "the coordinates after x and y";
  return "the SVG is a top view (x, y): " + axes + " (from " + number_text(rest.minCoeff(), 6) + " to " +
         number_text(rest.maxCoeff(), 6) + ") is dropped; write json, npy, ply or obj to keep it";
}

void segments_svg(const Segments& segments, const SvgOptions& options, ByteSink& sink) {
  check_segments(segments, "the segments to draw as SVG");
  const Points& P = segments.vertices;
  if (P.rows() == 0) throw InvalidInput("an SVG needs at least one vertex to draw, none is given");
  const int width = options.width;
  if (width < 16 || width > 100000)
    throw InvalidInput("the SVG width " + std::to_string(width) + " is outside [16, 100000]");
  if (!(options.stroke > 0) || !std::isfinite(options.stroke))
    throw InvalidInput("the SVG stroke width must be a positive finite number");
  // Halves: hi − lo overflows for coordinates near ±1.7e308, x/2 − lo/2 never does, and in the
  // normal range the pixels are bit for bit those of (x − lo) · scale.
  const Eigen::Vector2d lo = P.leftCols(2).colwise().minCoeff().transpose() / 2;
  const Eigen::Vector2d hi = P.leftCols(2).colwise().maxCoeff().transpose() / 2;
  const double half_span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 0.5e-300});
  const double margin = 0.05 * width, scale = (width - 2 * margin) / half_span;  // pixels per half unit
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) * scale + 2 * margin));
  ChunkBuffer buffer(sink);
  std::string& out = buffer.text;
  out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" +
        std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
        "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<path fill=\"none\" stroke=\"" +
        options.color + "\" stroke-linecap=\"round\" stroke-linejoin=\"round\" stroke-width=\"";
  append_number(out, options.stroke, 6);
  out += "\" d=\"";
  const auto point = [&](int i) {
    append_fixed(out, margin + (P(i, 0) / 2 - lo.x()) * scale, 3);
    out += ',';
    append_fixed(out, height - margin - (P(i, 1) / 2 - lo.y()) * scale, 3);
  };
  int previous = -1;
  for (const auto& s : segments.segments) {
    // A segment that starts where the previous one ended continues the run (a proper join).
    if (s[0] != previous) {
      if (previous != -1) out += ' ';
      out += 'M';
      point(s[0]);
    }
    out += " L";
    point(s[1]);
    previous = s[1];
    buffer.spill();
  }
  out += "\"/>\n</svg>\n";
  buffer.flush();
}

std::string segments_svg(const Segments& segments, const SvgOptions& options) {
  StringSink out;
  segments_svg(segments, options, out);
  return std::move(out.bytes);
}

std::string polyline_svg(const Points& points, bool closed, int width, double stroke) {
  if (points.cols() < 2) throw InvalidInput("an SVG needs points of at least 2 coordinates (x, y)");
  Segments s = polyline_segments(points.leftCols(2), closed);
  s.states.clear();
  SvgOptions options;
  options.width = width;
  options.stroke = stroke;
  return segments_svg(s, options);
}

std::string strokes_svg(const std::vector<Stroke>& strokes, const std::string& title, int width) {
  if (width < 64 || width > 100000)
    throw InvalidInput("the SVG figure's width " + std::to_string(width) + " is outside [64, 100000]");
  if (std::all_of(strokes.begin(), strokes.end(), [](const Stroke& s) { return s.points.rows() == 0; }))
    throw InvalidInput("an SVG figure needs at least one point to draw, none is given");
  // Halved coordinates, as in segments_svg: no overflow of the spans near ±1.7e308.
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (std::size_t k = 0; k < strokes.size(); ++k) {
    const Stroke& s = strokes[k];
    detail::check_finite(s.points, "the figure's stroke " + std::to_string(k + 1));
    for (Eigen::Index i = 0; i < s.points.rows(); ++i) {
      x0 = std::min(x0, s.points(i, 0) / 2), x1 = std::max(x1, s.points(i, 0) / 2);
      y0 = std::min(y0, s.points(i, 1) / 2), y1 = std::max(y1, s.points(i, 1) / 2);
    }
  }
  const double margin = 20, span = std::max({x1 - x0, y1 - y0, 0.5e-12});
  const double scale = (width - 2 * margin) / std::max(x1 - x0, 1e-12 * span);  // pixels per half unit
  const double legend =
      22.0 * static_cast<double>(std::count_if(strokes.begin(), strokes.end(),
                                               [](const Stroke& s) { return !s.label.empty(); }));
  const double height = std::max(2 * margin + (y1 - y0) * scale, 2 * margin + 10) + legend + 26;
  const auto n = [](double x) { return number_text(x, 6); };  // six significant digits: pixels
  std::string o = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) +
                  "\" height=\"" + n(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + n(height) +
                  "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o += "<text x=\"" + n(margin) + "\" y=\"18\" font-family=\"sans-serif\" font-size=\"14\">" + title +
       "</text>\n";
  for (const Stroke& s : strokes) {
    o += std::string("<") + (s.closed ? "polygon" : "polyline") + " fill=\"none\" stroke=\"" + s.colour +
         "\" stroke-width=\"" + n(s.width) + "\" stroke-linejoin=\"round\"";
    if (!s.dash.empty()) o += " stroke-dasharray=\"" + s.dash + "\"";
    o += " points=\"";
    for (Eigen::Index i = 0; i < s.points.rows(); ++i)
      o += (i ? " " : "") + n(margin + (s.points(i, 0) / 2 - x0) * scale) + "," +
           n(26 + margin + (y1 - s.points(i, 1) / 2) * scale);
    o += "\"/>\n";
  }
  double y = height - legend + 4;
  for (const Stroke& s : strokes) {
    if (s.label.empty()) continue;
    o += "<line x1=\"" + n(margin) + "\" y1=\"" + n(y) + "\" x2=\"" + n(margin + 40) + "\" y2=\"" + n(y) +
         "\" stroke=\"" + s.colour + "\" stroke-width=\"" + n(s.width) + "\"" +
         (s.dash.empty() ? "" : " stroke-dasharray=\"" + s.dash + "\"") + "/>\n<text x=\"" + n(margin + 50) +
         "\" y=\"" + n(y + 5) + "\" font-family=\"sans-serif\" font-size=\"13\">" + s.label + "</text>\n";
    y += 22;
  }
  o += "</svg>\n";
  return o;
}

namespace {

/// Where each state is drawn: its column and row on the grid.
struct Layout {
  std::vector<int> column, row;
  int columns = 0, tallest = 0;
};

double x_of(const Layout& l, automata::StateId s) {
  return kMargin + kRadius + kColumn * l.column[s];
}

double y_of(const Layout& l, automata::StateId s) {
  return kMargin + kRadius + kRow * l.row[s] + 20;
}

Layout layout_states(const automata::Automaton& a) {
  const std::size_t n = num_vertices(a.graph);
  // Layers: breadth-first distance from the initial states; unreachable states go last.
  std::vector<int> layer(n, -1);
  std::deque<automata::StateId> queue;
  for (const automata::Initial& i : a.initial)
    if (layer[i.state] < 0) {
      layer[i.state] = 0;
      queue.push_back(i.state);
    }
  std::vector<automata::StateId> order;
  while (!queue.empty()) {
    const automata::StateId s = queue.front();
    queue.pop_front();
    order.push_back(s);
    for (auto [e, end] = out_edges(s, a.graph); e != end; ++e) {
      const automata::StateId t = target(*e, a.graph);
      if (layer[t] < 0) {
        layer[t] = layer[s] + 1;
        queue.push_back(t);
      }
    }
  }
  const int deepest = order.empty() ? 0 : layer[order.back()];
  for (automata::StateId s = 0; s < n; ++s)
    if (layer[s] < 0) {
      layer[s] = deepest + 1;
      order.push_back(s);
    }
  // Tall layers wrap into several columns of at most kMaxRows states.
  std::vector<int> in_layer(static_cast<std::size_t>(deepest + 2), 0), first_column(in_layer.size() + 1, 0);
  Layout out{std::vector<int>(n, 0), std::vector<int>(n, 0)};
  for (const automata::StateId s : order) ++in_layer[static_cast<std::size_t>(layer[s])];
  for (std::size_t l = 0; l < in_layer.size(); ++l)
    first_column[l + 1] = first_column[l] + (in_layer[l] + kMaxRows - 1) / kMaxRows;
  std::vector<int> seen(in_layer.size(), 0);
  for (const automata::StateId s : order) {
    const auto l = static_cast<std::size_t>(layer[s]);
    out.column[s] = first_column[l] + seen[l] / kMaxRows;
    out.row[s] = seen[l]++ % kMaxRows;
  }
  out.columns = first_column.back();
  out.tallest = std::min(kMaxRows, *std::max_element(in_layer.begin(), in_layer.end()));
  return out;
}

/// The transitions as arrows. Parallel transitions (e.g. G and D both to the uniform state)
/// share one arrow, "G,D".
void append_arrows(std::string& svg, const automata::Automaton& a, const Layout& layout) {
  std::map<std::pair<automata::StateId, automata::StateId>, std::string> arrows;
  for (const automata::TransitionId e : edges(a.graph)) {
    std::string& label = arrows[{source(e, a.graph), target(e, a.graph)}];
    label += (label.empty() ? "" : ",") + xml_escape(a.graph[e].label);
  }
  for (const auto& [ends, label] : arrows) {
    const auto [s, t] = ends;
    const double x0 = x_of(layout, s), y0 = y_of(layout, s), x1 = x_of(layout, t), y1 = y_of(layout, t);
    if (s == t) {  // self-loop above the state
      svg += "<path d=\"M" + fixed(x0 - 10) + "," + fixed(y0 - kRadius + 2) + " C" + fixed(x0 - 30) + "," +
             fixed(y0 - kRadius - 38) + " " + fixed(x0 + 30) + "," + fixed(y0 - kRadius - 38) + " " +
             fixed(x0 + 10) + "," + fixed(y0 - kRadius + 2) +
             "\" fill=\"none\" stroke=\"#444\" marker-end=\"url(#arrow)\"/>\n";
      svg += "<text x=\"" + fixed(x0) + "\" y=\"" + fixed(y0 - kRadius - 32) + "\">" + label + "</text>\n";
      continue;
    }
    // Edges bend to the left of their direction, so a pair s→t, t→s shows two arrows.
    const double dx = x1 - x0, dy = y1 - y0, len = std::hypot(dx, dy);
    const double ux = dx / len, uy = dy / len, bend = 0.18 * len;
    const double cx = (x0 + x1) / 2 + uy * bend, cy = (y0 + y1) / 2 - ux * bend;
    const auto towards = [&](double px, double py, double qx, double qy) {
      const double l = std::hypot(qx - px, qy - py);
      return std::pair{px + (qx - px) * kRadius / l, py + (qy - py) * kRadius / l};
    };
    const auto [sx, sy] = towards(x0, y0, cx, cy);
    const auto [tx, ty] = towards(x1, y1, cx, cy);
    svg += "<path d=\"M" + fixed(sx) + "," + fixed(sy) + " Q" + fixed(cx) + "," + fixed(cy) + " " +
           fixed(tx) + "," + fixed(ty) + "\" fill=\"none\" stroke=\"#444\" marker-end=\"url(#arrow)\"/>\n";
    const double lx = 0.25 * x0 + 0.5 * cx + 0.25 * x1, ly = 0.25 * y0 + 0.5 * cy + 0.25 * y1;
    svg += "<text x=\"" + fixed(lx) + "\" y=\"" + fixed(ly - 3) + "\" fill=\"#a33\">" + label + "</text>\n";
  }
}

/// The states as circles (recurrent ones tinted, initial ones with a thick outline) and names.
void append_states(std::string& svg, const automata::Automaton& a, const Layout& layout) {
  const std::size_t n = num_vertices(a.graph);
  std::vector<bool> is_initial(n, false);
  for (const automata::Initial& i : a.initial) is_initial[i.state] = true;
  for (automata::StateId s = 0; s < n; ++s) {
    const automata::State& st = a.graph[s];
    const std::string fill = st.recurrent ? "#dfe9f7" : "#f4f4f4";
    svg += "<circle cx=\"" + fixed(x_of(layout, s)) + "\" cy=\"" + fixed(y_of(layout, s)) + "\" r=\"" +
           fixed(kRadius) + "\" fill=\"" + fill + "\" stroke=\"#222\" stroke-width=\"" +
           (is_initial[s] ? "2.5" : "1") + "\"/>\n";
    const std::string name = st.name.empty() ? "s" + std::to_string(s) : xml_escape(st.name);
    svg += "<text x=\"" + fixed(x_of(layout, s)) + "\" y=\"" + fixed(y_of(layout, s) + 4) + "\">" + name +
           "</text>\n";
  }
}

}  // namespace

std::string to_svg(const automata::Automaton& a) {
  const Layout layout = layout_states(a);
  const double width = 2 * (kMargin + kRadius) + kColumn * std::max(layout.columns - 1, 0);
  const double height = 2 * (kMargin + kRadius) + kRow * std::max(layout.tallest - 1, 0) + 20;
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fixed(width) + "\" height=\"" +
                    fixed(height) + "\" viewBox=\"0 0 " + fixed(width) + " " + fixed(height) + "\">\n";
  svg +=
      "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"7\" "
      "markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#444\"/>"
      "</marker></defs>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += "<g font-family=\"sans-serif\" font-size=\"12\" text-anchor=\"middle\">\n";
  append_arrows(svg, a, layout);
  append_states(svg, a, layout);
  svg += "</g>\n</svg>\n";
  return svg;
}

}  // namespace cifs::io
