// SPDX-License-Identifier: MIT
// cifs — the mesh schemes' traits table and their vertex and edge masks on abstract neighbourhoods
// (cifs/subdivision/rules.hpp; the rules: docs/subdivision-surfaces.md, "Creases, corners, holes").
#include "cifs/subdivision/rules.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/suggest.hpp"

namespace cifs::subdivision {
namespace {

constexpr SchemeTraits kSchemes[] = {
    {MeshScheme::catmull_clark, "catmull-clark", "quads from any polygons, C2 but at extraordinary vertices",
     Split::quads, 0, 4, false, true, true},
    {MeshScheme::loop, "loop", "triangles, C2 but at extraordinary vertices", Split::triangles, 3, 6, false,
     true, true},
    {MeshScheme::doo_sabin, "doo-sabin", "dual quadratic: a face per face, edge and vertex", Split::dual, 0,
     0, false, false, false},
    {MeshScheme::butterfly, "butterfly",
     "modified Butterfly: interpolating triangles (Zorin, Schröder, Sweldens)", Split::triangles, 3, 6, true,
     false, false},
    {MeshScheme::sqrt3, "sqrt3", "Kobbelt's √3: triangles, a centroid per face and edge flips", Split::sqrt3,
     3, 6, false, false, false},
    {MeshScheme::bilinear, "bilinear", "quads at edge midpoints and face centroids, vertices kept",
     Split::quads, 0, 4, true, true, false},
};

bool sharp(double s) noexcept {
  return s > 0;
}

int sharp_count(std::span<const double> s) noexcept {
  return static_cast<int>(std::count_if(s.begin(), s.end(), sharp));
}

/// The first two sharp edges (OpenSubdiv's GetSharpEdgePairOfCrease).
std::array<int, 2> crease_ends(std::span<const double> s) noexcept {
  std::array<int, 2> ends{-1, -1};
  int found = 0;
  for (std::size_t i = 0; i < s.size() && found < 2; ++i)
    if (sharp(s[i])) ends[static_cast<std::size_t>(found++)] = static_cast<int>(i);
  return ends;
}

/// The mask of one rule (no blending).
VertexMask rule_mask(MeshScheme scheme, VertexRule rule, int faces, std::span<const double> edges) {
  VertexMask m;
  if (scheme == MeshScheme::bilinear || rule == VertexRule::corner) return m;
  if (rule == VertexRule::crease) {
    m.vertex = 0.75;
    m.crease_ends = crease_ends(edges);
    m.crease = 0.125;
    return m;
  }
  const double n = faces;
  if (scheme == MeshScheme::catmull_clark) {
    m.vertex = (n - 2) / n;
    m.edge = m.face = 1 / (n * n);
  } else if (faces == 6) {  // Loop, regular
    m.vertex = 0.625;
    m.edge = 0.0625;
  } else {  // Loop's β(n) = (1/n)(5/8 − (3/8 + ¼cos(2π/n))²)
    const double c = 0.375 + 0.25 * std::cos(2 * std::numbers::pi / n);
    m.edge = (0.625 - c * c) / n;
    m.vertex = 1 - m.edge * n;
  }
  return m;
}

}  // namespace

double fractional_weight(CreaseMethod method, const VertexNeighbourhood& n) noexcept {
  int count = 0;
  float sum = 0;
  if (sharp(n.sharpness) && !sharp(n.child_sharpness)) {
    count = 1;
    sum = static_cast<float>(n.sharpness);
  }
  for (std::size_t i = 0; i < n.edges.size(); ++i) {
    const double s = n.edges[i];
    const bool decays =
        method == CreaseMethod::uniform ? sharp(s) && s <= 1 : sharp(s) && !sharp(n.child_edges[i]);
    if (decays) {
      sum += static_cast<float>(s);
      ++count;
    }
  }
  if (count == 0) return 0;
  const float w = sum / static_cast<float>(count);
  return w > 1 ? 1.0 : w;
}

std::span<const SchemeTraits> mesh_schemes() noexcept {
  return kSchemes;
}

const SchemeTraits& traits(MeshScheme scheme) noexcept {
  for (const SchemeTraits& t : kSchemes)
    if (t.scheme == scheme) return t;
  return kSchemes[0];  // unreachable: every enumerator has a row
}

std::string scheme_names() {
  std::string out;
  for (const SchemeTraits& t : kSchemes) out += (out.empty() ? "" : ", ") + std::string(t.name);
  return out;
}

MeshScheme named_mesh_scheme(std::string_view name) {
  for (const SchemeTraits& t : kSchemes)
    if (t.name == name) return t.scheme;
  std::vector<std::string> names;
  for (const SchemeTraits& t : kSchemes) names.emplace_back(t.name);
  throw InvalidInput("unknown mesh scheme '" + std::string(name) + "'" + did_you_mean(name, names) + " (" +
                     scheme_names() + ")");
}

std::string_view scheme_name(MeshScheme scheme) noexcept {
  return traits(scheme).name;
}

bool triangles_only(MeshScheme scheme) noexcept {
  return traits(scheme).face_size == 3;
}

VertexRule vertex_rule(double vertex_sharpness, int sharp_edges) noexcept {
  if (sharp(vertex_sharpness) || sharp_edges > 2) return VertexRule::corner;
  return sharp_edges == 0 ? VertexRule::smooth : sharp_edges == 1 ? VertexRule::dart : VertexRule::crease;
}

std::string_view rule_name(VertexRule rule) noexcept {
  switch (rule) {
    case VertexRule::smooth:
      return "smooth";
    case VertexRule::dart:
      return "dart";
    case VertexRule::crease:
      return "crease";
    case VertexRule::corner:
      return "corner";
  }
  return "";
}

double held_sharpness(double s) noexcept {
  return s >= kInfiniteSharpness ? kInfiniteSharpness : s > 0 ? static_cast<float>(s) : 0.0;
}

double decremented_sharpness(double s) noexcept {
  if (s >= kInfiniteSharpness) return kInfiniteSharpness;
  return s > 1 ? static_cast<float>(s) - 1.0F : 0.0;
}

void child_edge_sharpness(CreaseMethod method, std::span<const double> around,
                          std::span<double> out) noexcept {
  if (method == CreaseMethod::uniform || around.size() < 2) {
    for (std::size_t i = 0; i < around.size(); ++i) out[i] = decremented_sharpness(around[i]);
    return;
  }
  // The semi-sharp edges' sum, once (in the order OpenSubdiv adds them: the same float).
  float sum = 0;
  int count = 0;
  for (const double x : around)
    if (sharp(x) && x < kInfiniteSharpness) {
      sum += static_cast<float>(x);
      ++count;
    }
  for (std::size_t i = 0; i < around.size(); ++i) {
    const double s = around[i];
    if (!sharp(s) || s >= kInfiniteSharpness) {
      out[i] = sharp(s) ? kInfiniteSharpness : 0.0;
      continue;
    }
    // Chaikin: ¾ of its own sharpness and ¼ of the mean of the other semi-sharp edges here.
    float own = static_cast<float>(s);
    if (count > 1) own = 0.75F * own + 0.25F * ((sum - own) / static_cast<float>(count - 1));
    own -= 1.0F;
    out[i] = own > 0 ? own : 0.0;
  }
}

VertexMask vertex_mask(MeshScheme scheme, CreaseMethod method, const VertexNeighbourhood& n) {
  const VertexRule parent = vertex_rule(n.sharpness, sharp_count(n.edges));
  if (parent == VertexRule::smooth || parent == VertexRule::dart)
    return rule_mask(scheme, VertexRule::smooth, n.faces, n.edges);
  const VertexMask p = rule_mask(scheme, parent, n.faces, n.edges);
  VertexRule child = vertex_rule(n.child_sharpness, sharp_count(n.child_edges));
  if (child == parent) return p;
  if (child == VertexRule::dart) child = VertexRule::smooth;
  const VertexMask c = rule_mask(scheme, child, n.faces, n.child_edges);
  const double w = fractional_weight(method, n);
  // At most one of the two masks has crease ends (both creases would be the same rule).
  VertexMask m;
  m.vertex = w * p.vertex + (1 - w) * c.vertex;
  m.edge = w * p.edge + (1 - w) * c.edge;
  m.face = w * p.face + (1 - w) * c.face;
  if (p.crease_ends[0] >= 0) {
    m.crease_ends = p.crease_ends;
    m.crease = w * p.crease;
  } else if (c.crease_ends[0] >= 0) {
    m.crease_ends = c.crease_ends;
    m.crease = (1 - w) * c.crease;
  }
  return m;
}

EdgeMask edge_mask(MeshScheme scheme, TriangleRule triangles, const EdgeNeighbourhood& n) {
  if (scheme == MeshScheme::bilinear) return {};
  const bool crease = sharp(n.child_sharpness[0]) && sharp(n.child_sharpness[1]);
  if (sharp(n.sharpness) && crease) return {};
  EdgeMask m;
  if (scheme == MeshScheme::loop) {
    m.end = 0.375;
    m.face = 0.125;
  } else if (triangles == TriangleRule::smooth && n.face_sizes[1] > 0 &&
             (n.face_sizes[0] == 3 || n.face_sizes[1] == 3)) {
    // OpenSubdiv's TRI_SUB_SMOOTH: 0.47 for a triangle's centre, ¼ for any other face's.
    const double f0 = n.face_sizes[0] == 3 ? 0.47 : 0.25, f1 = n.face_sizes[1] == 3 ? 0.47 : 0.25;
    m.face = 0.5 * (f0 + f1);
    m.end = 0.5 * (1 - 2 * m.face);
  } else {
    m.end = 0.25;
    m.face = n.face_sizes[1] > 0 ? 0.25 : 0.5;
  }
  if (sharp(n.sharpness)) {  // the edge turns smooth during the step: blend by its sharpness
    const double s = n.sharpness;
    m.end = s * 0.5 + (1 - s) * m.end;
    m.face *= 1 - s;
  }
  return m;
}

double blz_edge_shift(MeshScheme scheme, double cos_theta_k) noexcept {
  // Catmull–Clark: γ = ⅜ − ¼cos θ_k; Loop: γ = ½ − ¼cos θ_k; δ = ⅜ − γ.
  return scheme == MeshScheme::loop ? 0.25 * cos_theta_k - 0.125 : 0.25 * cos_theta_k;
}

double blz_sector_angle(VertexRule rule, bool concave) noexcept {
  if (rule != VertexRule::corner) return std::numbers::pi;
  return concave ? 1.5 * std::numbers::pi : 0.5 * std::numbers::pi;
}

}  // namespace cifs::subdivision
