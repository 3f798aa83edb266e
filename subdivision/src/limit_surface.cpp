// SPDX-License-Identifier: MIT
// cifs — a subdivision surface's limit as one controlled IFS (Catmull–Clark and Loop), its
// evaluation at any (face, u, v), its attractor meshes and its fractal versions
// (cifs/subdivision/limit.hpp).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs_surface.hpp"
#include "cifs/ifs/bcifs_triangle.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/subdivision/limit.hpp"
#include "fractal_features.hpp"
#include "limit_patches.hpp"
#include "local_mesh.hpp"
#include "surface_states.hpp"

namespace cifs::subdivision {
namespace {

using detail::corner;
using detail::corner_index;

/// The uniform cubic B-spline's halves (rows: the child's control points on the parent's).
Eigen::Matrix4d cubic_half(int half) {
  Eigen::Matrix4d G;
  G << 4, 4, 0, 0, 1, 6, 1, 0, 0, 4, 4, 0, 0, 1, 6, 1;
  G /= 8;
  return half == 0 ? G : Eigen::Matrix4d(G.reverse());  // D is G read backwards
}

bool quads(MeshScheme scheme) {
  return scheme == MeshScheme::catmull_clark;
}

/// Which corner of face f, if any, is extraordinary; InvalidInput (naming the face) for what the
/// surface automaton does not build.
int extraordinary_corner(const MeshTopology& t, MeshScheme scheme, int f) {
  const std::string where = std::string(scheme_name(scheme)) + " limit surface: face " + std::to_string(f);
  const std::size_t sides = quads(scheme) ? 4 : 3;
  const int regular = quads(scheme) ? 4 : 6;
  const char* polygon =
      quads(scheme) ? "a quad (refine one level first)" : "a triangle (loop runs on triangles)";
  const auto corners = face(t, static_cast<std::size_t>(f));
  if (corners.size() != sides) throw InvalidInput(where + ": not " + polygon);
  int ev = -1, extraordinary = 0;
  for (std::size_t k = 0; k < sides; ++k) {
    const auto v = static_cast<std::size_t>(corners[k]);
    if (valence(t, v) != regular) {
      ev = static_cast<int>(k);
      ++extraordinary;
    }
    for (const int g : vertex_faces(t, v))
      if (face(t, static_cast<std::size_t>(g)).size() != sides)
        throw InvalidInput(where + ": a corner touches a face that is not " + polygon);
  }
  if (extraordinary > 1)
    throw InvalidInput(where + ": " + std::to_string(extraordinary) +
                       " extraordinary corners (refine one level first)");
  return ev;
}

bool is_regular(const automata::Automaton& a, automata::StateId s) {
  return a.graph[s].name == "regular";
}

/// The labels of a state's four children, in the order of their out-edges.
std::array<const char*, 4> child_labels(MeshScheme scheme) {
  if (quads(scheme)) return {"GH", "GB", "DH", "DB"};
  return {"C0", "C1", "C2", "M"};
}

/// The state "regular": the uniform bicubic B-spline net (Catmull–Clark) or the regular box-spline
/// patch's 12 points (Loop), its four children its own quarters.
automata::StateId add_regular(MeshScheme scheme, automata::Graph& g) {
  const auto labels = child_labels(scheme);
  const ExtraordinaryPatch regular_patch = quads(scheme) ? ExtraordinaryPatch{} : loop_patch(6);
  const automata::StateId regular =
      add_vertex(automata::State{.size = quads(scheme) ? 16 : 12, .recurrent = false, .name = "regular"}, g);
  for (std::size_t c = 0; c < 4; ++c) {
    Eigen::MatrixXd M;
    if (quads(scheme))
      M = automata::kron(cubic_half(static_cast<int>(c / 2)), cubic_half(static_cast<int>(c % 2)));
    else
      M = c == 0 ? regular_patch.subdivide : regular_patch.regular[c - 1];
    add_edge(regular, regular, automata::Transition{labels[c], M}, g);
  }
  return regular;
}

/// The automaton of the given faces (initial entry i is faces[i], `segment` the face's index).
SurfaceAutomaton build_automaton(const Mesh& mesh, const MeshTopology& t, MeshScheme scheme,
                                 std::span<const int> faces) {
  SurfaceAutomaton out;
  out.scheme = scheme;
  automata::Graph& g = out.automaton.graph;
  const auto labels = child_labels(scheme);
  const automata::StateId regular = add_regular(scheme, g);
  std::map<int, automata::StateId> extraordinary;  // by valence
  const auto state_of = [&](int n) {
    if (const auto it = extraordinary.find(n); it != extraordinary.end()) return it->second;
    const ExtraordinaryPatch patch = quads(scheme) ? catmull_clark_patch(n) : loop_patch(n);
    const automata::StateId s = add_vertex(automata::State{.size = static_cast<int>(patch.subdivide.rows()),
                                                           .recurrent = false,
                                                           .name = "E" + std::to_string(n)},
                                           g);
    add_edge(s, s, automata::Transition{labels[0], patch.subdivide}, g);
    // Quads: child 2·iu + iv, (0, 1) regular[2], (1, 0) regular[0], (1, 1) regular[1]. Triangles:
    // C1, C2, M are regular[0], [1], [2].
    const std::array<std::size_t, 3> order =
        quads(scheme) ? std::array<std::size_t, 3>{2, 0, 1} : std::array<std::size_t, 3>{0, 1, 2};
    for (std::size_t c = 1; c < 4; ++c)
      add_edge(s, regular, automata::Transition{labels[c], patch.regular[order[c - 1]]}, g);
    return extraordinary.emplace(n, s).first->second;
  };
  const Eigen::Index d = mesh.vertices.cols();
  for (const int f : faces) {
    const int ev = extraordinary_corner(t, scheme, f);
    const int first = corner(t, f, std::max(ev, 0));
    std::vector<int> support;
    automata::StateId state = regular;
    if (ev >= 0) {
      const int n = valence(t, static_cast<std::size_t>(first));
      try {
        state = state_of(n);
      } catch (const InvalidInput& e) {
        throw InvalidInput(std::string(scheme_name(scheme)) + " limit surface: face " + std::to_string(f) +
                           ": " + e.what());
      }
    }
    if (!quads(scheme)) {
      support = detail::triangle_support(t, f, first);
    } else if (ev < 0) {
      const std::array<int, 16> net = detail::regular_net(t, f, first);
      support.assign(net.begin(), net.end());
    } else {
      support = detail::patch_support(t, f, first);
    }
    Points net(static_cast<Eigen::Index>(support.size()), d);
    for (std::size_t k = 0; k < support.size(); ++k)
      net.row(static_cast<Eigen::Index>(k)) = mesh.vertices.row(support[k]);
    out.automaton.initial.push_back(automata::Initial{.segment = f, .state = state});
    out.nets.push_back(std::move(net));
    const int e = corner_index(t, f, first);
    out.corners.push_back(
        {first, corner(t, f, e + 1), corner(t, f, e + 2), quads(scheme) ? corner(t, f, e + 3) : -1});
  }
  return out;
}

void check_scheme(MeshScheme scheme) {
  if (scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
    throw InvalidInput("limit surface: " + std::string(scheme_name(scheme)) +
                       " is not built (catmull-clark and loop are)");
}

}  // namespace

SurfaceAutomaton surface_automaton(const Mesh& mesh, MeshScheme scheme) {
  check_scheme(scheme);
  const std::string who = std::string(scheme_name(scheme)) + " surface automaton";
  if (mesh.tags.rules == RuleSet::blz)
    throw InvalidInput(who +
                       ": the rule set 'blz' is not built for the whole-surface automaton (its patches "
                       "are OpenSubdiv's rules')");
  const MeshTopology t = build_topology(mesh);
  // A closed untagged mesh: the smooth rules' patches ("regular", "E<n>"). Otherwise the configurations
  // evaluate_limit_surface descends, under the mesh's tags and boundary rule.
  MeshTags smooth = mesh.tags;
  smooth.boundary = BoundaryRule::edge_only;  // the boundary rule matters where there is a boundary
  const std::string feature = first_feature(smooth);
  const bool open =
      std::any_of(t.boundary_vertex.begin(), t.boundary_vertex.end(), [](char b) { return b != 0; });
  if (feature.empty() && !open) {
    std::vector<int> faces(face_count(t));
    std::iota(faces.begin(), faces.end(), 0);
    return build_automaton(mesh, t, scheme, faces);
  }
  SurfaceAutomaton out;
  out.scheme = scheme;
  detail::add_feature_faces(mesh, scheme, add_regular(scheme, out.automaton.graph), out);
  return out;
}

namespace {

/// The index of a shared node: a mesh vertex ({v, −1, 0}) or the point `at` cells along the mesh edge
/// from its lower vertex to its higher one; {−1, −1, 0} for a node inside a face.
std::array<int, 3> edge_node(int from, int to, int at, int side) {
  return from < to ? std::array{from, to, at} : std::array{to, from, side - at};
}

/// Loop's attractor at `depth`: per face the nodes (i, j), i + j ≤ 2^depth, of the patch's
/// triangle grid; a leaf's corners are the fixed points of its corner children repeated.
Mesh triangle_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options,
                   const detail::FeatureDisplacement* features) {
  if (depth < 0 || depth > 15)
    throw InvalidInput("loop limit surface mesh: depth " + std::to_string(depth) + " is outside 0 … 15");
  if (surface.nets.empty()) return {};
  const int side = 1 << depth;
  const std::size_t faces = surface.nets.size(), cols = static_cast<std::size_t>(surface.nets.front().cols());
  const std::size_t nodes =
                        faces * static_cast<std::size_t>(side + 1) * static_cast<std::size_t>(side + 2) / 2,
                    cells = faces * static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  if (ifs::mesh_bytes(nodes, cols, cells) > options.max_bytes || nodes > static_cast<std::size_t>(INT_MAX))
    throw InvalidInput("loop limit surface mesh: depth " + std::to_string(depth) + " on " +
                       std::to_string(faces) + " faces gives " + std::to_string(cells) +
                       " triangles, more than the limit of " + std::to_string(options.max_bytes >> 20) +
                       " MiB held in memory; lower the depth");
  std::array<std::vector<Eigen::RowVectorXd>, 3> fixed;
  for (std::size_t c = 0; c < 3; ++c)
    fixed[c] = ifs::repeated_child_functionals(surface.automaton, static_cast<int>(c));
  const automata::Graph& g = surface.automaton.graph;
  std::map<std::array<int, 3>, int> shared;
  std::vector<int> node_of((static_cast<std::size_t>(side) + 1) * static_cast<std::size_t>(side + 1));
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<int> corners;
  corners.reserve(3 * cells);
  std::vector<std::uint32_t> states;
  states.reserve(cells);
  for (std::size_t f = 0; f < faces; ++f) {
    const auto& c = surface.corners[f];
    const bool moved = features != nullptr && features->touches(c, false);
    // The face's nodes: shared ones by the mesh's topology, the others new.
    for (int i = 0; i <= side; ++i)
      for (int j = 0; i + j <= side; ++j) {
        std::array<int, 3> key{-1, -1, 0};
        if (i == 0 && j == 0)
          key = {c[0], -1, 0};
        else if (i == side)
          key = {c[1], -1, 0};
        else if (j == side)
          key = {c[2], -1, 0};
        else if (j == 0)
          key = edge_node(c[0], c[1], i, side);
        else if (i + j == side)
          key = edge_node(c[1], c[2], j, side);
        else if (i == 0)
          key = edge_node(c[0], c[2], j, side);
        int& node = node_of[static_cast<std::size_t>(i) * static_cast<std::size_t>(side + 1) +
                            static_cast<std::size_t>(j)];
        if (key[0] < 0) {
          node = static_cast<int>(rows.size());
          rows.emplace_back();
          continue;
        }
        const auto [it, fresh] = shared.emplace(key, static_cast<int>(rows.size()));
        node = it->second;
        if (fresh) rows.emplace_back();
      }
    // Down the tree: a triangle's corner 0 at (i, j), its corners 1 and 2 at ± h along i and j
    // (− for the turned middle triangles).
    const auto visit = [&](const auto& self, automata::StateId state, const Points& net, int i, int j,
                           int sign, int h) -> void {
      if (h == 1) {
        const std::array<std::array<int, 2>, 3> at{{{i, j}, {i + sign, j}, {i, j + sign}}};
        for (std::size_t k = 0; k < 3; ++k) {
          const int node = node_of[static_cast<std::size_t>(at[k][0]) * static_cast<std::size_t>(side + 1) +
                                   static_cast<std::size_t>(at[k][1])];
          auto& row = rows[static_cast<std::size_t>(node)];
          if (row.size() == 0) {
            row = fixed[k][state] * net;
            if (options.homogeneous) row /= row(row.size() - 1);
            if (moved) features->add_triangle(c, at[k][0], at[k][1], row);
          }
          corners.push_back(node);
        }
        states.push_back(static_cast<std::uint32_t>(state));
        return;
      }
      const int half = h / 2;
      const std::array<std::array<int, 3>, 4> child{{{i, j, sign},
                                                     {i + sign * half, j, sign},
                                                     {i, j + sign * half, sign},
                                                     {i + sign * half, j + sign * half, -sign}}};
      std::size_t k = 0;
      for (auto [e, end] = out_edges(state, g); e != end; ++e, ++k)
        self(self, target(*e, g), Points(g[*e].matrix * net), child[k][0], child[k][1], child[k][2], half);
    };
    visit(visit, surface.automaton.initial[f].state, surface.nets[f], 0, 0, 1, side);
  }
  Points vertices(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (std::size_t v = 0; v < rows.size(); ++v) vertices.row(static_cast<Eigen::Index>(v)) = rows[v];
  Mesh out = uniform_mesh(std::move(vertices), std::move(corners), 3);
  out.states = std::move(states);
  return out;
}

}  // namespace

namespace {

/// The attractor mesh, each face's nodes moved by its fractal feature curves first (`features` may
/// be null).
Mesh attractor_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options,
                    const detail::FeatureDisplacement* features) {
  if (!quads(surface.scheme)) return triangle_mesh(surface, depth, options, features);
  Mesh blocks = ifs::patch_meshes(surface.automaton, surface.nets, depth, options);
  // Node (I, J) of face f's block is shared with its neighbours when it lies on the block's border:
  // a mesh vertex at a corner, else a point of a mesh edge, named by the edge's end vertices (lower
  // index first) and its distance from the lower one in cells. Each gets the first block's vertex.
  const int side = 1 << depth, row = side + 1, block = row * row;
  if (features != nullptr)
    for (std::size_t f = 0; f < surface.corners.size(); ++f) {
      if (!features->touches(surface.corners[f], true)) continue;
      for (int I = 0; I <= side; ++I)
        for (int J = 0; J <= side; ++J) {
          const auto v = static_cast<Eigen::Index>(f * static_cast<std::size_t>(block)) +
                         static_cast<Eigen::Index>(I) * row + J;
          Eigen::RowVectorXd p = blocks.vertices.row(v);
          features->add_quad(surface.corners[f], I, J, p);
          blocks.vertices.row(v) = p;
        }
    }
  std::map<std::array<int, 3>, int> shared;
  std::vector<int> index(static_cast<std::size_t>(blocks.vertices.rows()));
  int next = 0;
  const auto corner_node = [&](int I, int J) -> int {
    if (I == 0 && J == 0) return 0;
    if (I == side && J == 0) return 1;
    if (I == side && J == side) return 2;
    if (I == 0 && J == side) return 3;
    return -1;
  };
  for (std::size_t f = 0; f < surface.corners.size(); ++f) {
    const auto& c = surface.corners[f];
    for (int I = 0; I <= side; ++I)
      for (int J = 0; J <= side; ++J) {
        const std::size_t v = f * static_cast<std::size_t>(block) + static_cast<std::size_t>(I * row + J);
        std::array<int, 3> key{-1, -1, 0};
        if (const int k = corner_node(I, J); k >= 0) {
          key = {c[static_cast<std::size_t>(k)], -1, 0};
        } else if (I == 0 || I == side || J == 0 || J == side) {
          // Sides: J = 0 from corner 0 to 1 (I cells from 0), I = side from 1 to 2, J = side from 3
          // to 2, I = 0 from 0 to 3.
          int from = 0, to = 0, at = 0;
          if (J == 0)
            from = c[0], to = c[1], at = I;
          else if (I == side)
            from = c[1], to = c[2], at = J;
          else if (J == side)
            from = c[3], to = c[2], at = I;
          else
            from = c[0], to = c[3], at = J;
          key = edge_node(from, to, at, side);
        }
        if (key[0] < 0) {
          index[v] = next++;
          continue;
        }
        const auto [it, fresh] = shared.emplace(key, next);
        index[v] = it->second;
        if (fresh) ++next;
      }
  }
  Mesh out;
  out.vertices.resize(next, blocks.vertices.cols());
  std::vector<bool> written(static_cast<std::size_t>(next), false);
  for (std::size_t v = 0; v < index.size(); ++v) {
    const auto w = static_cast<std::size_t>(index[v]);
    if (written[w]) continue;
    out.vertices.row(index[v]) = blocks.vertices.row(static_cast<Eigen::Index>(v));
    written[w] = true;
  }
  std::vector<int> corners;
  corners.reserve(blocks.face_vertices.size());
  for (const int v : blocks.face_vertices) corners.push_back(index[static_cast<std::size_t>(v)]);
  out = uniform_mesh(out.vertices, std::move(corners), 4);
  out.states = blocks.states;
  return out;
}

}  // namespace

Mesh surface_automaton_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options) {
  return attractor_mesh(surface, depth, options, nullptr);
}

Mesh surface_automaton_mesh(const FractalSurface& fractal, int depth, const ifs::MeshOptions& options) {
  if (fractal.features.nets.empty()) return attractor_mesh(fractal.surface, depth, options, nullptr);
  if (depth < 0 || depth > 15)
    throw InvalidInput("fractal surface mesh: depth " + std::to_string(depth) + " is outside 0 … 15");
  if (options.homogeneous)
    throw InvalidInput(
        "fractal surface mesh: fractal feature curves are built for Cartesian nets, not homogeneous");
  const detail::FeatureDisplacement features(fractal.features, depth);
  return attractor_mesh(fractal.surface, depth, options, &features);
}

namespace {

/// The BC-IFS of the scheme's regular patch: Catmull–Clark's uniform bicubic patch (4 × 4 control
/// points, knots 0 … 7, one patch whose sides all lie on knot lines), Loop's box-spline triangle.
ifs::Bcifs regular_patch_bcifs(MeshScheme scheme) {
  if (!quads(scheme)) return ifs::triangle_bcifs(loop_triangle_patch());
  nurbs::Knots knots(8);
  for (std::size_t k = 0; k < knots.size(); ++k) knots[k] = static_cast<double>(k);
  const nurbs::Surface patch = nurbs::make_surface({3, 3}, {knots, knots}, {4, 4}, Points::Zero(16, 3));
  return ifs::surface_bcifs(nurbs::tensor_automaton(patch));
}

}  // namespace

FractalSurface fractal_surface(const SurfaceAutomaton& smooth, const ifs::PerturbOptions& options) {
  if (smooth.scheme != MeshScheme::catmull_clark && smooth.scheme != MeshScheme::loop)
    throw InvalidInput("fractal subdivision surfaces: " + std::string(scheme_name(smooth.scheme)) +
                       " is not built (catmull-clark and loop are)");
  FractalSurface out;
  out.perturbation = ifs::perturb(regular_patch_bcifs(smooth.scheme), options);
  const automata::Automaton& cells = out.perturbation.system.automaton;
  // The new graph: the BC-IFS's cells, then the smooth automaton's extraordinary states with their
  // regular children led to the patch cell (the BC-IFS's one initial state).
  automata::Graph g = cells.graph;
  const automata::StateId root = cells.initial.at(0).state;
  const automata::Graph& old = smooth.automaton.graph;
  std::vector<automata::StateId> moved(num_vertices(old), root);
  for (automata::StateId s = 0; s < num_vertices(old); ++s)
    if (!is_regular(smooth.automaton, s)) moved[s] = add_vertex(old[s], g);
  for (automata::StateId s = 0; s < num_vertices(old); ++s) {
    if (is_regular(smooth.automaton, s)) continue;
    for (auto [e, end] = out_edges(s, old); e != end; ++e)
      add_edge(moved[s], moved[target(*e, old)], old[*e], g);
  }
  out.surface.automaton.graph = std::move(g);
  for (const automata::Initial& i : smooth.automaton.initial)
    out.surface.automaton.initial.push_back(automata::Initial{.segment = i.segment, .state = moved[i.state]});
  out.surface.nets = smooth.nets;
  out.surface.corners = smooth.corners;
  out.surface.scheme = smooth.scheme;
  return out;
}

}  // namespace cifs::subdivision
