// SPDX-License-Identifier: MIT
// cifs — "which points of my model are not smooth?": every irregular vertex of a mesh classified from
// its topology and tags and given the local analysis of its class, computed once per configuration
// (cifs/subdivision/mesh_analysis.hpp; docs/subdivision-surfaces.md, "Which points are not smooth").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <utility>

#include "cifs/errors.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision {
namespace {

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}

std::string sharpness_text(double s) {
  std::string t = std::to_string(s);
  t.erase(t.find_last_not_of('0') + 1);
  if (!t.empty() && t.back() == '.') t.pop_back();
  return t;
}

/// The configuration of a vertex as the local analysis sees it; nothing for a regular vertex.
/// Semi-sharp tags decay to 0 within ceil(s) levels (either crease method: Chaikin's new sharpness is
/// at most the largest at the vertex less 1), after which the stationary rules are those of the
/// infinitely sharp tags alone: they decide the limit at the vertex. `semi_sharp` receives the largest
/// semi-sharp value at the vertex (0: none).
std::optional<LocalOptions> local_class(const MeshTopology& t, const MeshTags& tags,
                                        const std::map<std::uint64_t, double>& sharpness,
                                        const std::vector<double>& corner, MeshScheme scheme, int v,
                                        double& semi_sharp) {
  const auto ring = vertex_edges(t, static_cast<std::size_t>(v));
  const int n = static_cast<int>(ring.size());
  const bool boundary = t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
  LocalOptions o{.boundary = boundary};
  o.rules = tags.rules;
  o.concave = std::find(tags.concave.begin(), tags.concave.end(), v) != tags.concave.end();
  semi_sharp = 0;
  for (int j = 0; j < n; ++j) {
    const int w = other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>(j)]), v);
    const auto it = sharpness.find(edge_key(v, w));
    if (it == sharpness.end() || it->second <= 0) continue;
    if (it->second < kInfiniteSharpness)
      semi_sharp = std::max(semi_sharp, it->second);
    else if (!(boundary && (j == 0 || j == n - 1)))
      o.sharp.push_back(j);
  }
  const double s = corner[static_cast<std::size_t>(v)];
  if (s > 0 && s < kInfiniteSharpness) semi_sharp = std::max(semi_sharp, s);
  // √3 and Butterfly have one boundary rule each: a boundary vertex of one face is no corner there.
  const bool one_rule = scheme == MeshScheme::sqrt3 || scheme == MeshScheme::butterfly;
  o.corner = s >= kInfiniteSharpness ||
             (boundary && n == 2 && !one_rule && tags.boundary == BoundaryRule::edge_and_corner);
  // Interior: turn the ring so that the first sharp edge is r_0 (the class does not depend on it).
  if (!boundary && !o.sharp.empty()) {
    const int first = o.sharp.front();
    for (int& j : o.sharp) j -= first;
  }
  const int regular = traits(scheme).regular_valence;
  const bool plain = o.sharp.empty() && !o.corner && !o.concave;
  if (semi_sharp == 0) {
    if (plain && !boundary && n == regular) return std::nullopt;
    if (plain && boundary && n == regular / 2 + 1) return std::nullopt;
    if (!boundary && !o.corner && o.sharp.size() == 2 && o.sharp[1] == regular / 2 && n == regular)
      return std::nullopt;  // the regular crease: both sides regular
  }
  return o;
}

using Analysis = std::pair<LocalSpectrum, C1Verdict>;

Analysis analysis_of(const LocalMatrix& S) {
  LocalSpectrum spectrum = local_spectrum(S);
  C1Verdict verdict = c1_verdict(S, spectrum);
  return {std::move(spectrum), std::move(verdict)};
}

/// The interior corners of face f turned to their least rotation (the class does not depend on
/// where the face starts).
std::vector<char> least_rotation(std::vector<char> inner) {
  std::vector<char> best = inner;
  for (std::size_t i = 1; i < inner.size(); ++i) {
    std::rotate(inner.begin(), inner.begin() + 1, inner.end());
    best = std::min(best, inner);
  }
  return best;
}

/// Doo–Sabin (dual): every face's descendants shrink to its centroid and an interior vertex becomes a
/// face after one step, so the points that can be irregular are the centres of faces (k ≠ 4 corners,
/// or touching the boundary otherwise than along one edge) and of interior vertices' faces (valence ≠ 4).
MeshSmoothness analyze_doo_sabin(const MeshTopology& t, const std::string& who) {
  MeshSmoothness out;
  out.scheme = MeshScheme::doo_sabin;
  std::map<int, Analysis> interior;
  std::map<std::vector<char>, Analysis> touching;
  const auto interior_analysis = [&](int k, const std::string& element) -> const Analysis& {
    auto it = interior.find(k);
    if (it != interior.end()) return it->second;
    try {
      return interior.emplace(k, analysis_of(local_matrix(MeshScheme::doo_sabin, k))).first->second;
    } catch (const InvalidInput& e) {
      throw InvalidInput(who + ": " + element + ": " + e.what());
    }
  };
  const auto add = [&](int vertex, int face_index, int k, const char* type, const Analysis& a) {
    VertexSmoothness r;
    r.vertex = vertex;
    r.face = face_index;
    r.valence = k;
    r.vertex_class = type;
    r.lambda1 = a.first.subdominant;
    r.lambda2 = a.first.second;
    r.curvature_ratio = a.first.curvature_ratio;
    r.verdict = a.second;
    r.verdict.sectors.clear();
    (r.verdict.c1 ? out.c1 : r.verdict.decided ? out.not_c1 : out.undecided) += 1;
    out.vertices.push_back(std::move(r));
  };
  int off_surface = 0;
  for (std::size_t f = 0; f < face_count(t); ++f) {
    const auto corners = face(t, f);
    const int k = static_cast<int>(corners.size());
    std::vector<char> inner(corners.size());
    for (std::size_t i = 0; i < corners.size(); ++i)
      inner[i] = t.boundary_vertex[static_cast<std::size_t>(corners[i])] == 0 ? 1 : 0;
    const int m = static_cast<int>(std::count(inner.begin(), inner.end(), 1));
    const std::string element = "face " + std::to_string(f);
    if (m == 0) {
      ++off_surface;
    } else if (m == k) {
      if (k == 4) {
        ++out.regular;
      } else {
        add(-1, static_cast<int>(f), k, "face", interior_analysis(k, element));
      }
    } else if (const std::vector<char> key = least_rotation(inner);
               k == 4 && key == std::vector<char>{0, 0, 1, 1}) {
      ++out.regular;  // along one edge of the boundary: the half-plane's biquadratic spline
    } else {
      const Analysis& whole = interior_analysis(k, element);
      auto it = touching.find(key);
      if (it == touching.end()) {
        LocalSpectrum spectrum = local_spectrum(doo_sabin_boundary_matrix(key));
        it = touching
                 .emplace(key, Analysis{std::move(spectrum), doo_sabin_boundary_verdict(whole.second, key)})
                 .first;
      }
      add(-1, static_cast<int>(f), k, "boundary", it->second);
    }
  }
  for (int v = 0; v < t.vertex_count; ++v) {
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    if (faces.empty()) {
      ++out.isolated;
      continue;
    }
    if (t.boundary_vertex[static_cast<std::size_t>(v)]) continue;  // makes no face
    const int n = static_cast<int>(faces.size());
    if (n == 4) {
      ++out.regular;
      continue;
    }
    add(v, -1, n, "vertex", interior_analysis(n, "vertex " + std::to_string(v)));
  }
  out.analyses = static_cast<int>(interior.size() + touching.size());
  out.isolated += off_surface;
  out.summary =
      "doo-sabin: " + std::to_string(face_count(t)) + " faces and " + std::to_string(t.vertex_count) +
      " vertices, " + std::to_string(out.regular) + " regular points, " +
      std::to_string(out.vertices.size()) + " irregular: " + std::to_string(out.c1) + " C1, " +
      std::to_string(out.not_c1) + " not C1, " + std::to_string(out.undecided) + " undecided (" +
      std::to_string(out.analyses) + (out.analyses == 1 ? " local analysis" : " local analyses") + ")" +
      (off_surface > 0 ? ", " + std::to_string(off_surface) + " faces off the surface" : "") +
      (out.isolated > off_surface ? ", " + std::to_string(out.isolated - off_surface) + " in no face" : "");
  return out;
}

}  // namespace

MeshSmoothness analyze_mesh(const Mesh& mesh, MeshScheme scheme, std::string_view who_view) {
  const std::string who(who_view);
  if (scheme == MeshScheme::bilinear)
    throw InvalidInput(who + ": bilinear's limit surface is the refined mesh itself (C0 at every vertex); " +
                       "there is nothing to analyse");
  check_mesh(mesh, who);
  if (mesh.tags.boundary == BoundaryRule::none)
    throw InvalidInput(who + ": the boundary rule 'none' is not analysed (its boundary faces are holes)");
  if (scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
    if (const std::string tag = first_feature(mesh.tags); !tag.empty())
      throw InvalidInput(who + ": the mesh has " + tag + "; " + std::string(scheme_name(scheme)) +
                         " has no rules for creases, corners or holes (catmull-clark and loop have)");
  if (scheme == MeshScheme::loop || scheme == MeshScheme::sqrt3 || scheme == MeshScheme::butterfly)
    for (std::size_t f = 0; f < face_count(mesh); ++f)
      if (face(mesh, f).size() != 3)
        throw InvalidInput(who + ": " + std::string(scheme_name(scheme)) + " runs on triangles; face " +
                           std::to_string(f) + " has " + std::to_string(face(mesh, f).size()) + " corners");
  const MeshTopology t = build_topology(mesh, who);
  if (scheme == MeshScheme::doo_sabin) return analyze_doo_sabin(t, who);
  std::map<std::uint64_t, double> sharpness;
  for (const EdgeSharpness& c : mesh.tags.creases)
    sharpness[edge_key(c.a, c.b)] = held_sharpness(c.sharpness);
  std::vector<double> corner(static_cast<std::size_t>(t.vertex_count), 0);
  for (const VertexSharpness& c : mesh.tags.corners)
    corner[static_cast<std::size_t>(c.vertex)] = held_sharpness(c.sharpness);

  // Holes leave faces out of the surface, not out of the rules (OpenSubdiv refines around them as
  // usual): a vertex is analysed as it is, unless every face of it is a hole.
  const std::vector<char> hole = hole_flags(mesh);
  MeshSmoothness out;
  out.scheme = scheme;
  using Key = std::tuple<int, bool, std::vector<int>, bool, bool>;
  std::map<Key, Analysis> cache;
  for (int v = 0; v < t.vertex_count; ++v) {
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    if (std::all_of(faces.begin(), faces.end(),
                    [&](int f) { return hole[static_cast<std::size_t>(f)] != 0; })) {
      ++out.isolated;
      continue;
    }
    double semi_sharp = 0;
    const auto o = local_class(t, mesh.tags, sharpness, corner, scheme, v, semi_sharp);
    if (!o) {
      ++out.regular;
      continue;
    }
    const int n = static_cast<int>(vertex_edges(t, static_cast<std::size_t>(v)).size());
    const Key key{n, o->boundary, o->sharp, o->corner, o->concave};
    auto it = cache.find(key);
    if (it == cache.end()) {
      LocalMatrix S;
      try {
        S = local_matrix(scheme, n, *o);
      } catch (const InvalidInput& e) {
        throw InvalidInput(who + ": vertex " + std::to_string(v) + ": " + e.what());
      }
      it = cache.emplace(key, analysis_of(S)).first;
    }
    const auto& [spectrum, verdict] = it->second;
    VertexSmoothness r{.vertex = v,
                       .valence = n,
                       .options = *o,
                       .vertex_class = vertex_class(n, *o),
                       .sectors = sector_sizes(n, *o),
                       .lambda1 = spectrum.subdominant,
                       .lambda2 = spectrum.second,
                       .curvature_ratio = spectrum.curvature_ratio,
                       .semi_sharp = semi_sharp,
                       .verdict = verdict};
    if (semi_sharp > 0)
      r.verdict.reason = "semi-sharp (s = " + sharpness_text(semi_sharp) + "): analysed after " +
                         std::to_string(static_cast<int>(std::ceil(semi_sharp))) + " levels, class " +
                         r.vertex_class + " from then on; " + r.verdict.reason;
    // Per configuration, not per vertex: the verdict's reason names the failing sector.
    r.verdict.sectors.clear();
    (verdict.c1 ? out.c1 : verdict.decided ? out.not_c1 : out.undecided) += 1;
    out.vertices.push_back(std::move(r));
  }
  out.analyses = static_cast<int>(cache.size());
  out.summary = std::string(scheme_name(scheme)) + ": " + std::to_string(t.vertex_count) + " vertices, " +
                std::to_string(out.regular) + " regular, " + std::to_string(out.vertices.size()) +
                " irregular: " + std::to_string(out.c1) + " C1, " + std::to_string(out.not_c1) + " not C1, " +
                std::to_string(out.undecided) + " undecided (" + std::to_string(out.analyses) +
                (out.analyses == 1 ? " local analysis" : " local analyses") + ")" +
                (out.isolated > 0 ? ", " + std::to_string(out.isolated) + " in no face" : "");
  return out;
}

}  // namespace cifs::subdivision
