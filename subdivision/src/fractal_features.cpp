// SPDX-License-Identifier: MIT
// cifs — fractal feature curves of a fractal subdivision surface: an infinitely sharp crease or a
// boundary made fractal on its own, the surface watertight across it (cifs/subdivision/limit.hpp,
// FractalFeatures; docs/subdivision-surfaces.md, "Fractal crease lines").
#include "fractal_features.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"

namespace cifs::subdivision {
namespace {

/// The BC-IFS of one segment of a uniform cubic B-spline (4 control points, knots 0 … 7): every
/// segment of a feature curve is one, its net the four polygon points around it.
ifs::Bcifs cubic_segment_bcifs() {
  nurbs::Knots knots(8);
  std::iota(knots.begin(), knots.end(), 0.0);
  return ifs::curve_bcifs(nurbs::make_curve(3, knots, Points::Zero(4, 1)));
}

/// What the smooth surface's feature curves are made of at a vertex (level 0, under the mesh's tags).
struct FeatureVertex {
  std::vector<int> sharp;  // the infinitely sharp edges (boundary edges included)
  bool corner = false;     // a corner tag, or three sharp edges or more: the curves end here
  bool semi = false;       // a semi-sharp edge or corner tag: the rules change with the level
};

FeatureVertex feature_vertex(const MeshTopology& t, const LevelFeatures& f, const MeshTags& tags, int v) {
  FeatureVertex out;
  for (const int e : vertex_edges(t, static_cast<std::size_t>(v))) {
    const double s = edge_sharpness(f, e);
    if (s >= kInfiniteSharpness)
      out.sharp.push_back(e);
    else if (s > 0)
      out.semi = true;
  }
  const double c = vertex_sharpness(f, v);
  if (c > 0 && c < kInfiniteSharpness) out.semi = true;
  const bool boundary_corner = tags.boundary == BoundaryRule::edge_and_corner &&
                               t.boundary_vertex[static_cast<std::size_t>(v)] != 0 &&
                               vertex_faces(t, static_cast<std::size_t>(v)).size() == 1;
  out.corner = c >= kInfiniteSharpness || out.sharp.size() >= 3 || boundary_corner;
  return out;
}

/// The polygon point before `v` seen from `w` along the feature curve: the far end of v's other sharp
/// edge, or the phantom point 2v − w at a corner (where the curve ends, interpolating v).
Eigen::RowVectorXd beyond(const Mesh& mesh, const MeshTopology& t, const FeatureVertex& fv, int v, int w) {
  if (fv.corner) return 2 * mesh.vertices.row(v) - mesh.vertices.row(w);
  for (const int e : fv.sharp) {
    const auto& ab = t.edges[static_cast<std::size_t>(e)];
    const int other = ab[0] == v ? ab[1] : ab[0];
    if (other != w) return mesh.vertices.row(other);
  }
  throw std::logic_error("fractal features: a crease vertex without its second sharp edge");
}

/// `smooth` must be built from `mesh`: every initial entry's corners are corners of its face.
void check_same_mesh(const Mesh& mesh, const MeshTopology& t, const SurfaceAutomaton& smooth) {
  const std::string who = "fractal features: the mesh is not the surface automaton's";
  if (smooth.nets.size() != smooth.automaton.initial.size() || smooth.corners.size() != smooth.nets.size())
    throw InvalidInput(who + " (its nets and corners do not match its initial entries)");
  for (std::size_t k = 0; k < smooth.corners.size(); ++k) {
    const int f = smooth.automaton.initial[k].segment;
    if (f < 0 || static_cast<std::size_t>(f) >= face_count(t))
      throw InvalidInput(who + ": entry " + std::to_string(k) + " is face " + std::to_string(f) +
                         ", the mesh has " + std::to_string(face_count(t)) + " faces");
    const auto corners = face(t, static_cast<std::size_t>(f));
    for (const int c : smooth.corners[k])
      if (c >= 0 && std::find(corners.begin(), corners.end(), c) == corners.end())
        throw InvalidInput(who + ": vertex " + std::to_string(c) + " is no corner of face " +
                           std::to_string(f));
    if (smooth.nets[k].cols() != mesh.vertices.cols())
      throw InvalidInput(who + ": its nets have " + std::to_string(smooth.nets[k].cols()) +
                         " columns, the mesh " + std::to_string(mesh.vertices.cols()));
  }
}

}  // namespace

FractalSurface fractal_surface(const Mesh& mesh, const SurfaceAutomaton& smooth,
                               const ifs::PerturbOptions& options, const FractalFeatureOptions& features) {
  if (!features.creases && !features.boundaries) return fractal_surface(smooth, options);
  Mesh shape;  // topology and tags only
  shape.vertices = Points::Zero(mesh.vertices.rows(), 3);
  shape.face_offsets = mesh.face_offsets;
  shape.face_vertices = mesh.face_vertices;
  shape.tags = mesh.tags;
  const MeshRefinement r = refine_topology(shape, smooth.scheme, 0);
  const MeshTopology& t = r.levels[0];
  const LevelFeatures& f = r.features[0];
  check_same_mesh(mesh, t, smooth);
  // The edges asked for, and which of them can be: both ends crease, boundary or corner vertices
  // without semi-sharp tags, a face beside it in the surface.
  int asked_creases = 0, asked_boundaries = 0, made_creases = 0, made_boundaries = 0;
  std::map<std::array<int, 2>, Points> nets;
  for (std::size_t e = 0; e < edge_count(t); ++e) {
    if (edge_sharpness(f, e) < kInfiniteSharpness) continue;
    const auto& faces = t.edge_faces[e];
    const bool boundary = faces[1] < 0;
    if (boundary ? !features.boundaries : !features.creases) continue;
    ++(boundary ? asked_boundaries : asked_creases);
    if (is_hole(f, faces[0]) && (boundary || is_hole(f, faces[1]))) continue;
    const int lo = std::min(t.edges[e][0], t.edges[e][1]), hi = std::max(t.edges[e][0], t.edges[e][1]);
    const FeatureVertex a = feature_vertex(t, f, r.tags[0], lo), b = feature_vertex(t, f, r.tags[0], hi);
    const auto ends_curve = [](const FeatureVertex& v) {
      return !v.semi && (v.corner || v.sharp.size() == 2);
    };
    if (!ends_curve(a) || !ends_curve(b)) continue;
    Points net(4, mesh.vertices.cols());
    net.row(0) = beyond(mesh, t, a, lo, hi);
    net.row(1) = mesh.vertices.row(lo);
    net.row(2) = mesh.vertices.row(hi);
    net.row(3) = beyond(mesh, t, b, hi, lo);
    nets.emplace(std::array{lo, hi}, std::move(net));
    ++(boundary ? made_boundaries : made_creases);
  }
  const auto refuse = [&](const char* kind, int asked, const char* none) {
    const std::string who = std::string("fractal ") + kind + ": ";
    if (asked == 0) throw InvalidInput(who + none);
    throw InvalidInput(
        who + "every one of the mesh's " + std::to_string(asked) +
        " edges ends at a dart or at a semi-sharp tag (or lies next to holes), where the smooth "
        "curve is no cubic B-spline of its polygon");
  };
  if (features.creases && made_creases == 0)
    refuse(
        "creases", asked_creases,
        "the mesh has no infinitely sharp crease (semi-sharp creases stay smooth: their sharpness runs out)");
  if (features.boundaries && made_boundaries == 0)
    refuse("boundaries", asked_boundaries, "the mesh has no boundary");
  // The curves first: their refusals come before the surface's perturbation (the longer work).
  FractalFeatures curves;
  curves.smooth = cubic_segment_bcifs();
  try {
    curves.perturbation = ifs::perturb(curves.smooth, features.perturbation);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("fractal feature curves: ") + e.what());
  }
  curves.nets = std::move(nets);
  FractalSurface out = fractal_surface(smooth, options);
  out.features = std::move(curves);
  return out;
}

Points feature_curve_nodes(const FractalFeatures& features, std::array<int, 2> edge, int depth) {
  const auto it = features.nets.find(edge);
  if (it == features.nets.end())
    throw InvalidInput("fractal features: the edge " + std::to_string(edge[0]) + " " +
                       std::to_string(edge[1]) + " is no fractal feature edge (lower vertex first)");
  const ifs::EdgePieces pieces =
      ifs::edge_pieces(features.perturbation.system, std::span(&it->second, 1), depth);
  Points out(pieces.start.rows() + 1, pieces.start.cols());
  out.topRows(pieces.start.rows()) = pieces.start;
  out.bottomRows(1) = pieces.end.bottomRows(1);
  return out;
}

namespace detail {

namespace {

/// φ: 1 on the feature edge, 0 with zero slope on the face's opposite side.
double blend(double d) {
  return 1 - d * d * (3 - 2 * d);
}

}  // namespace

FeatureDisplacement::FeatureDisplacement(const FractalFeatures& features, int depth) : side_(1 << depth) {
  for (const auto& [edge, net] : features.nets) {
    const ifs::EdgePieces smooth = ifs::edge_pieces(features.smooth, std::span(&net, 1), depth);
    Points delta = feature_curve_nodes(features, edge, depth);
    delta.topRows(smooth.start.rows()) -= smooth.start;
    delta.bottomRows(1) -= smooth.end.bottomRows(1);
    delta_.emplace(edge, std::move(delta));
  }
}

void FeatureDisplacement::add(int from, int to, int at, double weight, Eigen::RowVectorXd& p) const {
  const auto it = delta_.find(from < to ? std::array{from, to} : std::array{to, from});
  if (it == delta_.end()) return;
  p += weight * it->second.row(from < to ? at : side_ - at);
}

bool FeatureDisplacement::touches(const std::array<int, 4>& c, bool quad) const {
  const int n = quad ? 4 : 3;
  for (int k = 0; k < n; ++k) {
    const int a = c[static_cast<std::size_t>(k)], b = c[static_cast<std::size_t>((k + 1) % n)];
    if (delta_.contains(a < b ? std::array{a, b} : std::array{b, a})) return true;
  }
  return false;
}

void FeatureDisplacement::add_quad(const std::array<int, 4>& c, int I, int J, Eigen::RowVectorXd& p) const {
  const double s = static_cast<double>(I) / side_, t = static_cast<double>(J) / side_;
  // The block's sides as surface_automaton_mesh names them: J = 0 from corner 0 to 1, I = side from 1
  // to 2, J = side from 3 to 2, I = 0 from 0 to 3.
  add(c[0], c[1], I, blend(t), p);
  add(c[1], c[2], J, blend(1 - s), p);
  add(c[3], c[2], I, blend(1 - t), p);
  add(c[0], c[3], J, blend(s), p);
}

void FeatureDisplacement::add_triangle(const std::array<int, 4>& c, int i, int j,
                                       Eigen::RowVectorXd& p) const {
  // Side ab, c the third corner: Δ at λ_b along it, weighted by φ(λ_c / (λ_a + λ_c)), which is 0 on the
  // side ab and 1 on the side bc; on the side ac Δ vanishes (λ_b = 0 is a mesh vertex).
  const int k = side_ - i - j;  // λ0·side
  if (side_ - i > 0) add(c[0], c[1], i, blend(static_cast<double>(j) / (side_ - i)), p);
  if (side_ - j > 0) add(c[1], c[2], j, blend(static_cast<double>(k) / (side_ - j)), p);
  if (side_ - j > 0) add(c[0], c[2], j, blend(static_cast<double>(i) / (side_ - j)), p);
}

}  // namespace detail
}  // namespace cifs::subdivision
