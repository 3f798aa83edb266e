// SPDX-License-Identifier: MIT
// cifs — face-varying channels refined under OpenSubdiv's face-varying interpolation rules. The
// rules are OpenSubdiv's (documentation/subdivision_surfaces.rst, "Face-varying Interpolation
// Rules", and the behaviour of Far::PrimvarRefiner::InterpolateFaceVarying, which the tests compare
// against); the code is this project's.
#include "face_varying.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>

#include "cifs/errors.hpp"
#include "cifs/subdivision/rules.hpp"

namespace cifs::subdivision::detail {
namespace {

using std::size_t;

/// What a face-varying rule and the boundary rule ask of the values (OpenSubdiv's names in
/// FVarLevel: _hasLinearBoundaries, _hasDependentSharpness, sharpenBothIfOneCorner, sharpenDarts,
/// fvarCornersAreSharp, makeSmoothCornersSharp).
struct Options {
  bool linear_boundaries = false;       // `boundaries`, `all`: seams and boundaries linear
  bool dependent = false;               // corners+1, corners+2: a seam vertex's two values sharpen together
  bool sharpen_both = false;            // corners+2: one of them on a single face makes both corners
  bool sharpen_darts = false;           // a seam ending inside the mesh makes its last vertex a corner
  bool sharp_corners = false;           // a value on a single face is a corner (all rules but `none`)
  bool sharp_boundary_corners = false;  // …also where the boundary rule leaves the geometry smooth
};

Options options_of(const MeshTags& tags) {
  using R = FaceVaryingRule;
  const R r = tags.face_varying;
  Options o;
  o.linear_boundaries = r == R::all || r == R::boundaries;
  o.dependent = r == R::corners_plus1 || r == R::corners_plus2;
  o.sharpen_both = r == R::corners_plus2;
  o.sharpen_darts = o.sharpen_both || o.linear_boundaries;
  o.sharp_corners = r != R::none;
  o.sharp_boundary_corners = o.sharp_corners && tags.boundary != BoundaryRule::edge_and_corner;
  return o;
}

bool semi_sharp(double s) {
  return s > 0 && s < kInfiniteSharpness;
}
bool follows_semi_sharpness(ValueRule r) {
  return r == ValueRule::semi_sharp || r == ValueRule::dependent;
}

int next_corner(const MeshTopology& t, int f, int h) {
  return h + 1 == t.face_offsets[static_cast<size_t>(f) + 1] ? t.face_offsets[static_cast<size_t>(f)] : h + 1;
}
int prev_corner(const MeshTopology& t, int f, int h) {
  return h == t.face_offsets[static_cast<size_t>(f)] ? t.face_offsets[static_cast<size_t>(f) + 1] - 1 : h - 1;
}

/// Per side of every edge (2e + k, k = 0 for edge_faces[e][0]): the corner whose outgoing edge it is.
std::vector<int> edge_corners(const MeshTopology& t) {
  std::vector<int> out(2 * t.edges.size(), -1);
  for (size_t f = 0; f < face_count(t); ++f)
    for (int h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h) {
      const auto e = static_cast<size_t>(t.face_edges[static_cast<size_t>(h)]);
      out[2 * e + (t.edge_faces[e][0] == static_cast<int>(f) ? 0 : 1)] = h;
    }
  return out;
}

/// The seams: edges whose two faces give either end different values.
std::vector<char> seams(const MeshTopology& t, const std::vector<int>& by_edge, const std::vector<int>& idx) {
  std::vector<char> out(t.edges.size(), 0);
  for (size_t e = 0; e < t.edges.size(); ++e) {
    const int f0 = t.edge_faces[e][0], f1 = t.edge_faces[e][1];
    if (f1 < 0) continue;
    const int h0 = by_edge[2 * e], h1 = by_edge[2 * e + 1];
    const auto at = [&](int h) { return idx[static_cast<size_t>(h)]; };
    out[e] = at(h0) != at(next_corner(t, f1, h1)) || at(next_corner(t, f0, h0)) != at(h1) ? 1 : 0;
  }
  return out;
}

/// Vertex v's faces as the channel sees them, in topology.hpp's ring order (face k between edges k
/// and k + 1, edge k its outgoing edge at v): v's corner in each face.
struct Ring {
  std::span<const int> edges, faces;
  std::vector<int> corners;
  bool boundary = false;
};

void ring_of(const MeshTopology& t, const std::vector<int>& by_edge, int v, Ring& r) {
  r.edges = vertex_edges(t, static_cast<size_t>(v));
  r.faces = vertex_faces(t, static_cast<size_t>(v));
  r.boundary = t.boundary_vertex[static_cast<size_t>(v)] != 0;
  r.corners.clear();
  for (size_t k = 0; k < r.faces.size(); ++k) {
    const auto e = static_cast<size_t>(r.edges[k]);
    r.corners.push_back(by_edge[2 * e + (t.edge_faces[e][0] == r.faces[k] ? 0 : 1)]);
  }
}

/// The value at the far end of ring edge k, read in face k (the last edge of a boundary vertex: in
/// the face before it). Only for edges that are not seams.
int far_value(const MeshTopology& t, const Ring& r, const std::vector<int>& idx, size_t k) {
  if (k < r.faces.size()) return idx[static_cast<size_t>(next_corner(t, r.faces[k], r.corners[k]))];
  return idx[static_cast<size_t>(prev_corner(t, r.faces[k - 1], r.corners[k - 1]))];
}

/// The faces around a vertex that share one of its values (OpenSubdiv's value span).
struct Span {
  int value = -1;                     // the channel row
  int start = 0, size = 0;            // first face in ring order, number of faces
  int runs = 0;                       // runs of faces between seams: more than one, no span (a corner)
  int inf_edges = 0, semi_edges = 0;  // infinitely and semi-sharp edges inside the span
};

/// The spans of a vertex's values, in order of first appearance from face 0, and each face's span.
void value_spans(const Ring& r, const std::vector<int>& idx, const std::vector<char>& seam,
                 const LevelFeatures& L, std::vector<Span>& spans, std::vector<int>& span_of) {
  const auto n = r.faces.size();
  spans.clear();
  span_of.assign(n, -1);
  for (size_t k = 0; k < n; ++k) {
    const int value = idx[static_cast<size_t>(r.corners[k])];
    std::size_t i = 0;
    while (i < spans.size() && spans[i].value != value) ++i;
    if (i == spans.size()) spans.push_back({.value = value});
    span_of[k] = static_cast<int>(i);
  }
  // Runs are cut at seams and, on the boundary, at edge 0; the edges inside a run count its sharpness.
  const auto cut = [&](size_t k) {
    return (r.boundary && k == 0) || seam[static_cast<size_t>(r.edges[k])] != 0;
  };
  const auto count_edge = [&](Span& s, size_t k) {
    const double x = edge_sharpness(L, r.edges[k % r.edges.size()]);
    s.inf_edges += x >= kInfiniteSharpness ? 1 : 0;
    s.semi_edges += semi_sharp(x) ? 1 : 0;
  };
  size_t first = 0;
  while (first < n && !cut(first)) ++first;
  if (first == n) {  // inside the mesh and no seam: one value all around
    Span& s = spans[0];
    s.runs = 1;
    s.size = static_cast<int>(n);
    for (size_t k = 0; k < n; ++k) count_edge(s, k);
    return;
  }
  for (size_t i = 0; i < n;) {
    const size_t start = (first + i) % n;
    size_t length = 1;
    while (i + length < n && !cut((first + i + length) % n)) ++length;
    Span& s = spans[static_cast<size_t>(span_of[start])];
    ++s.runs;
    s.start = static_cast<int>(start);
    s.size += static_cast<int>(length);
    for (size_t j = 1; j < length; ++j) count_edge(s, start + j);
    i += length;
  }
}

/// The values across a span's two bounding edges, read inside the span.
std::array<int, 2> crease_ends(const MeshTopology& t, const Ring& r, const std::vector<int>& idx,
                               const Span& s) {
  const auto first = static_cast<size_t>(s.start);
  const auto last = (first + static_cast<size_t>(s.size) - 1) % r.faces.size();
  return {idx[static_cast<size_t>(next_corner(t, r.faces[first], r.corners[first]))],
          idx[static_cast<size_t>(prev_corner(t, r.faces[last], r.corners[last]))]};
}

/// The sharpness after the step of edge e's half at v.
double half_at(const MeshTopology& t, const std::vector<double>& halves, int e, int v) {
  if (halves.empty()) return 0;
  const auto u = static_cast<size_t>(e);
  return halves[2 * u + (t.edges[u][0] == v ? 0 : 1)];
}

}  // namespace

void check_channels(const Mesh& mesh, MeshScheme scheme, const std::string& who, bool non_manifold) {
  if (mesh.face_varying.empty()) return;
  const std::string channel = "face-varying channel '" + mesh.face_varying.front().name + "'";
  if (traits(scheme).split == Split::dual || traits(scheme).split == Split::sqrt3)
    throw InvalidInput(who + ": the mesh has a " + channel +
                       "; this scheme does not split faces, so face-varying data has no rule under it " +
                       "(catmull-clark, loop, bilinear and butterfly refine it; or drop the channel)");
  if (mesh.tags.face_varying == FaceVaryingRule::all || scheme == MeshScheme::bilinear) return;
  const std::string rule = "the " + channel + " asks for the face-varying rule '" +
                           std::string(option_name(mesh.tags.face_varying)) + "'";
  if (scheme == MeshScheme::butterfly)
    throw InvalidInput(who + ": " + rule +
                       "; butterfly interpolates face-varying data linearly only (--fvar-interpolation all)");
  if (mesh.tags.rules == RuleSet::blz)
    throw InvalidInput(who + ": " + rule + ", which is OpenSubdiv's and not built under the rule set 'blz' " +
                       "(--fvar-interpolation all, or --rules opensubdiv)");
  if (non_manifold)
    throw InvalidInput(
        who + ": the mesh is not manifold and " + rule +
        "; non-manifold face-varying data is refined linearly only (--fvar-interpolation all)");
}

void check_limit_channels(const Mesh& mesh, MeshScheme scheme, const std::string& who) {
  check_channels(mesh, scheme, who, false);
  if (!mesh.face_varying.empty() && mesh.tags.face_varying != FaceVaryingRule::all &&
      scheme != MeshScheme::bilinear)
    throw InvalidInput(
        who + ": the limit of face-varying channel '" + mesh.face_varying.front().name +
        "' under the rule '" + std::string(option_name(mesh.tags.face_varying)) +
        "' is not built (the values would be the last level's, not their limit); subdivide " +
        "instead, or ask for the rule 'all' (--fvar-interpolation all: linear values are their " +
        "own limit)");
}

FaceVaryingChannel linear_channel(const MeshRefinement& r, const FaceVaryingChannel& channel) {
  ChannelLevel level = analyse_channel(r.levels.front(), r.features.front(), r.tags.front(), channel);
  for (std::size_t k = 0; k + 1 < r.levels.size(); ++k)
    level =
        refine_channel(r.scheme, r.levels[k], r.features[k], {}, r.tags[k], level);  // linear: no sharpness
  return std::move(level.channel);
}

ChannelLevel analyse_channel(const MeshTopology& t, const LevelFeatures& features, const MeshTags& tags,
                             FaceVaryingChannel channel) {
  const Options o = options_of(tags);
  const std::vector<int>& idx = channel.indices;
  const std::vector<int> by_edge = edge_corners(t);
  const std::vector<char> seam = seams(t, by_edge, idx);
  ChannelLevel out;
  out.rules.assign(idx.size(), ValueRule::smooth);
  Ring r;
  std::vector<Span> spans;
  std::vector<int> span_of;
  std::vector<ValueRule> rule;
  for (int v = 0; v < t.vertex_count; ++v) {
    ring_of(t, by_edge, v, r);
    if (r.faces.empty()) continue;
    bool split =
        std::any_of(r.edges.begin(), r.edges.end(), [&](int e) { return seam[static_cast<size_t>(e)] != 0; });
    if (!split && r.boundary) {
      // Under `boundaries` every boundary vertex is a corner. (OpenSubdiv also tags its boundary edges
      // linear, which changes no value: between corners a boundary's values lie evenly on straight
      // lines, which the boundary's own rule, ¾ + ⅛ + ⅛, keeps.)
      split = o.linear_boundaries || (r.faces.size() == 1 && o.sharp_boundary_corners);
    }
    if (!split) continue;
    value_spans(r, idx, seam, features, spans, span_of);
    const double vs = vertex_sharpness(features, v);
    bool all_sharp = o.linear_boundaries || vs >= kInfiniteSharpness || (o.dependent && spans.size() > 2) ||
                     (o.sharpen_darts && spans.size() == 1 && !r.boundary);
    bool dependent = false;
    if (!all_sharp && o.dependent && spans.size() == 2) {
      for (const Span& s : spans)
        all_sharp = all_sharp || s.inf_edges > 0 || s.runs > 1 || (o.sharpen_both && s.size == 1);
      dependent = (spans[0].semi_edges > 0) != (spans[1].semi_edges > 0);
    }
    rule.clear();
    for (const Span& s : spans) {
      if (s.runs > 1 || all_sharp || s.inf_edges > 0 || (s.size == 1 && o.sharp_corners))
        rule.push_back(ValueRule::corner);
      else if (s.semi_edges > 0 || semi_sharp(vs))
        rule.push_back(ValueRule::semi_sharp);
      else
        rule.push_back(dependent ? ValueRule::dependent : ValueRule::crease);
    }
    for (size_t k = 0; k < r.faces.size(); ++k)
      out.rules[static_cast<size_t>(r.corners[k])] = rule[static_cast<size_t>(span_of[k])];
  }
  out.channel = std::move(channel);
  return out;
}

ChannelLevel refine_channel(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& features,
                            const std::vector<double>& halves, const MeshTags& tags,
                            const ChannelLevel& level) {
  const Options o = options_of(tags);
  // OpenSubdiv interpolates linearly under `all` and for the bilinear scheme; Butterfly (interpolating,
  // no OpenSubdiv counterpart) takes the rule `all` only (check_channels).
  const bool linear_all = tags.face_varying == FaceVaryingRule::all ||
                          (scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop);
  const bool quads = traits(scheme).split == Split::quads;
  const Points& P = level.channel.values;
  const std::vector<int>& idx = level.channel.indices;
  const Eigen::Index d = P.cols();
  const size_t E = t.edges.size(), F = face_count(t), H = idx.size();
  const std::vector<int> by_edge = edge_corners(t);
  const std::vector<char> seam = seams(t, by_edge, idx);

  // Child rows: vertex values, then edge values, then face values (the child vertices' order).
  std::vector<double> rows;
  int count = 0;
  const auto begin_row = [&] {
    rows.resize(rows.size() + static_cast<size_t>(d), 0.0);
    return count++;
  };
  const auto add = [&](const double* source, double w) {
    double* out = rows.data() + rows.size() - static_cast<size_t>(d);
    for (Eigen::Index k = 0; k < d; ++k) out[k] += w * source[k];
  };
  const auto value = [&](int i) { return P.data() + static_cast<Eigen::Index>(i) * d; };
  Points face_values(quads ? static_cast<Eigen::Index>(F) : 0, d);
  if (quads)
    for (size_t f = 0; f < F; ++f) {
      const auto corners = face(t, f);
      face_values.row(static_cast<Eigen::Index>(f)).setZero();
      for (size_t i = 0; i < corners.size(); ++i)
        face_values.row(static_cast<Eigen::Index>(f)) +=
            P.row(idx[static_cast<size_t>(t.face_offsets[f]) + i]);
      face_values.row(static_cast<Eigen::Index>(f)) /= static_cast<double>(corners.size());
    }
  const auto face_value = [&](int f) { return face_values.data() + static_cast<Eigen::Index>(f) * d; };

  std::vector<int> vertex_value(H, -1);
  std::vector<ValueRule> vertex_rule(H, ValueRule::smooth);
  Ring r;
  std::vector<Span> spans;
  std::vector<int> span_of;
  std::vector<ValueRule> parent_rule, child_rule;
  std::vector<double> pe, ce;
  for (int v = 0; v < t.vertex_count; ++v) {
    ring_of(t, by_edge, v, r);
    if (r.faces.empty()) continue;
    value_spans(r, idx, seam, features, spans, span_of);
    const double vs = vertex_sharpness(features, v), cvs = decremented_sharpness(vs);
    const auto around = [&](std::span<const int> edges) {  // parent and child sharpness of these edges at v
      pe.clear();
      ce.clear();
      for (const int e : edges) {
        pe.push_back(edge_sharpness(features, e));
        ce.push_back(half_at(t, halves, e, v));
      }
    };
    if (spans.size() == 1 && level.rules[static_cast<size_t>(r.corners[0])] == ValueRule::smooth &&
        !linear_all) {
      // No seam here: the vertex's own mask on the values, as primal_step on the positions.
      VertexNeighbourhood n;
      n.faces = static_cast<int>(r.faces.size());
      if (!halves.empty()) {
        around(r.edges);
        n.edges = pe;
        n.child_edges = ce;
        n.sharpness = vs;
        n.child_sharpness = cvs;
      }
      const VertexMask m = vertex_mask(scheme, tags.crease_method, n);
      const int id = begin_row();
      if (m.face != 0)
        for (const int f : r.faces) add(face_value(f), m.face);
      if (m.edge != 0)
        for (size_t k = 0; k < r.edges.size(); ++k) add(value(far_value(t, r, idx, k)), m.edge);
      if (m.crease_ends[0] >= 0)
        for (const int k : m.crease_ends) add(value(far_value(t, r, idx, static_cast<size_t>(k))), m.crease);
      add(value(idx[static_cast<size_t>(r.corners[0])]), m.vertex);
      for (const int h : r.corners) vertex_value[static_cast<size_t>(h)] = id;
      continue;
    }
    // Seams here: each value by its own rule. The child's rules first (OpenSubdiv reclassifies
    // semi-sharp values once their sharpness is gone), since a value is interpolated by the pair.
    parent_rule.clear();
    for (size_t i = 0; i < spans.size(); ++i) {
      size_t k = 0;
      while (static_cast<size_t>(span_of[k]) != i) ++k;
      parent_rule.push_back(level.rules[static_cast<size_t>(r.corners[k])]);
    }
    child_rule = parent_rule;
    const bool parent_semi = semi_sharp(vs) || std::any_of(r.edges.begin(), r.edges.end(), [&](int e) {
                               return semi_sharp(edge_sharpness(features, e));
                             });
    if (parent_semi && !halves.empty() && !semi_sharp(cvs) && cvs < kInfiniteSharpness) {
      const bool child_semi_edges = std::any_of(r.edges.begin(), r.edges.end(),
                                                [&](int e) { return semi_sharp(half_at(t, halves, e, v)); });
      for (size_t i = 0; i < spans.size(); ++i) {
        if (!follows_semi_sharpness(child_rule[i])) continue;
        bool still = false;
        if (child_semi_edges && child_rule[i] == ValueRule::semi_sharp)
          for (int j = 1; j < spans[i].size; ++j)
            still = still ||
                    semi_sharp(half_at(
                        t, halves, r.edges[(static_cast<size_t>(spans[i].start + j)) % r.edges.size()], v));
        if (!child_semi_edges || (child_rule[i] == ValueRule::semi_sharp && !still))
          child_rule[i] = ValueRule::crease;
      }
      if (spans.size() == 2 && o.dependent) {
        if (child_rule[0] == ValueRule::dependent && !follows_semi_sharpness(child_rule[1]))
          child_rule[0] = ValueRule::semi_sharp;
        else if (child_rule[1] == ValueRule::dependent && !follows_semi_sharpness(child_rule[0]))
          child_rule[1] = ValueRule::semi_sharp;
      }
    }
    // The weight of the corner rule when a semi-sharp span turns into a crease.
    const auto corner_weight = [&](const Span& s) {
      std::vector<int> inside;
      for (int j = 1; j < s.size; ++j)
        inside.push_back(r.edges[static_cast<size_t>(s.start + j) % r.edges.size()]);
      around(inside);
      VertexNeighbourhood n;
      n.edges = pe;
      n.child_edges = ce;
      n.sharpness = vs;
      n.child_sharpness = cvs;
      return fractional_weight(tags.crease_method, n);
    };
    std::vector<int> ids;
    for (size_t i = 0; i < spans.size(); ++i) {
      const Span& s = spans[i];
      ids.push_back(begin_row());
      if (linear_all || child_rule[i] != ValueRule::crease) {  // a corner, or still sharp
        add(value(s.value), 1);
        continue;
      }
      double w = 0;  // a crease all along
      if (parent_rule[i] == ValueRule::semi_sharp) w = corner_weight(s);
      if (parent_rule[i] == ValueRule::dependent && spans.size() == 2) w = corner_weight(spans[1 - i]);
      const auto ends = crease_ends(t, r, idx, s);
      add(value(ends[0]), (1 - w) * 0.125);
      add(value(ends[1]), (1 - w) * 0.125);
      add(value(s.value), (1 - w) * 0.75 + w);
    }
    for (size_t k = 0; k < r.faces.size(); ++k) {
      const auto h = static_cast<size_t>(r.corners[k]), i = static_cast<size_t>(span_of[k]);
      vertex_value[h] = ids[i];
      vertex_rule[h] = child_rule[i];
    }
  }

  std::vector<int> edge_value(2 * E, -1);
  std::vector<ValueRule> edge_rule(E, ValueRule::smooth);
  for (size_t e = 0; e < E; ++e) {
    const int f0 = t.edge_faces[e][0], f1 = t.edge_faces[e][1], h0 = by_edge[2 * e];
    const bool split = seam[e] != 0;
    if (split) edge_rule[e] = o.linear_boundaries ? ValueRule::corner : ValueRule::crease;
    for (int side = 0; side < (split ? 2 : 1); ++side) {
      const int f = t.edge_faces[e][static_cast<size_t>(side)],
                h = by_edge[2 * e + static_cast<size_t>(side)];
      const int id = begin_row();
      edge_value[2 * e + static_cast<size_t>(side)] = edge_value[2 * e + 1] = id;
      if (split || linear_all) {  // the midpoint of this side's two values
        add(value(idx[static_cast<size_t>(h)]), 0.5);
        add(value(idx[static_cast<size_t>(next_corner(t, f, h))]), 0.5);
        continue;
      }
      const auto size = [&](int g) {
        return g < 0 ? 0 : static_cast<int>(face(t, static_cast<size_t>(g)).size());
      };
      const EdgeMask m = edge_mask(
          scheme, tags.triangles,
          {.sharpness = edge_sharpness(features, e),
           .child_sharpness = {halves.empty() ? 0 : halves[2 * e], halves.empty() ? 0 : halves[2 * e + 1]},
           .face_sizes = {size(f0), size(f1)}});
      if (m.face != 0)
        for (int k = 0; k < 2; ++k) {
          const int g = t.edge_faces[e][static_cast<size_t>(k)];
          if (g < 0) continue;
          if (quads)
            add(face_value(g), m.face);
          else  // Loop: the triangle's corner opposite the edge
            add(value(idx[static_cast<size_t>(prev_corner(t, g, by_edge[2 * e + static_cast<size_t>(k)]))]),
                m.face);
        }
      add(value(idx[static_cast<size_t>(h0)]), m.end);
      add(value(idx[static_cast<size_t>(next_corner(t, f0, h0))]), m.end);
    }
  }

  ChannelLevel out;
  const int face_base = count;
  for (size_t f = 0; quads && f < F; ++f) {
    begin_row();
    add(face_value(static_cast<int>(f)), 1);
  }
  out.channel.name = level.channel.name;
  out.channel.values = Points(count, d);
  std::copy(rows.begin(), rows.end(), out.channel.values.data());
  const auto side_of = [&](int e, size_t f) {
    return 2 * static_cast<size_t>(e) +
           (t.edge_faces[static_cast<size_t>(e)][0] == static_cast<int>(f) ? 0 : 1);
  };
  const auto erule = [&](int e) { return edge_rule[static_cast<size_t>(e)]; };
  auto& ci = out.channel.indices;
  ci.reserve(4 * H);
  out.rules.reserve(4 * H);
  for (size_t f = 0; f < F; ++f) {
    const auto b = static_cast<size_t>(t.face_offsets[f]), k = face(t, f).size();
    if (quads) {
      for (size_t i = 0; i < k; ++i) {  // split_polygons: (vertex i, edge i, face, edge i − 1)
        const size_t h = b + i, p = b + (i + k - 1) % k;
        const int eh = t.face_edges[h], ep = t.face_edges[p];
        ci.insert(ci.end(), {vertex_value[h], edge_value[side_of(eh, f)], face_base + static_cast<int>(f),
                             edge_value[side_of(ep, f)]});
        out.rules.insert(out.rules.end(), {vertex_rule[h], erule(eh), ValueRule::smooth, erule(ep)});
      }
    } else {  // split_triangles: the corner triangles, then the middle one
      const int e0 = t.face_edges[b], e1 = t.face_edges[b + 1], e2 = t.face_edges[b + 2];
      const int ab = edge_value[side_of(e0, f)], bc = edge_value[side_of(e1, f)],
                ca = edge_value[side_of(e2, f)];
      ci.insert(ci.end(), {vertex_value[b], ab, ca, ab, vertex_value[b + 1], bc, ca, bc, vertex_value[b + 2],
                           ab, bc, ca});
      out.rules.insert(out.rules.end(),
                       {vertex_rule[b], erule(e0), erule(e2), erule(e0), vertex_rule[b + 1], erule(e1),
                        erule(e2), erule(e1), vertex_rule[b + 2], erule(e0), erule(e1), erule(e2)});
    }
  }
  return out;
}

}  // namespace cifs::subdivision::detail
