// SPDX-License-Identifier: MIT
// cifs — the mesh schemes' facts and rules in one place (OpenSubdiv's Sdc is the model): a traits
// table that the refiner, the limits, the analysis, the CLI and Python read, and the vertex and edge
// masks computed on abstract neighbourhoods (sharpness values and counts, not a topology), with
// semi-sharp creases and corners (DeRose, Kass, Truong 1998) blended as OpenSubdiv blends them.
#pragma once

#include <array>
#include <span>
#include <string_view>

#include "cifs/mesh.hpp"

namespace cifs::subdivision {

enum class MeshScheme { catmull_clark, loop, doo_sabin, butterfly, sqrt3, bilinear };

/// How a scheme makes its child faces: a quad per face corner (Catmull–Clark, bilinear), four
/// triangles per triangle (Loop, Butterfly), a face per face, edge and vertex (Doo–Sabin), or a
/// centroid and edge flips (√3).
enum class Split { quads, triangles, dual, sqrt3 };

/// The facts about a mesh scheme (OpenSubdiv's Sdc::SchemeTypeTraits, extended).
struct SchemeTraits {
  MeshScheme scheme;
  std::string_view name;         // as the CLI, files and Python spell it
  std::string_view description;  // one line, for help texts
  Split split;
  int face_size;        // 3: runs on triangles only; 0: any polygon
  int regular_valence;  // interior valence of the regular vertex; 0 for Doo–Sabin (dual: faces)
  bool interpolating;   // old vertices stay
  /// Refines creases, corners and holes by its own rules (OpenSubdiv's semi-sharp rules); a scheme
  /// without refuses tagged meshes with a message naming the tag.
  bool sharpness;
  bool factored;  // has a factored form (factored_subdivide)
};

/// The table, in the order help texts list the schemes.
std::span<const SchemeTraits> mesh_schemes() noexcept;
const SchemeTraits& traits(MeshScheme scheme) noexcept;
/// The scheme of that name; InvalidInput naming the list (and the closest name) otherwise.
MeshScheme named_mesh_scheme(std::string_view name);
std::string_view scheme_name(MeshScheme scheme) noexcept;
/// Loop, Butterfly and √3 run on triangles only.
bool triangles_only(MeshScheme scheme) noexcept;
/// "catmull-clark, loop, …": the names, for messages and help.
std::string scheme_names();

/// How a vertex is refined, from its sharpness and its sharp incident edges (OpenSubdiv's
/// Crease::Rule): smooth (no sharp edge), dart (one), crease (two), corner (more, or a sharp vertex).
enum class VertexRule { smooth, dart, crease, corner };
VertexRule vertex_rule(double vertex_sharpness, int sharp_edges) noexcept;
std::string_view rule_name(VertexRule rule) noexcept;

/// Sharpness as the rules hold it: in single precision, as OpenSubdiv holds it (so that results
/// agree with it to round-off whatever the values), ≥ kInfiniteSharpness as kInfiniteSharpness, ≤ 0
/// as 0. Every sharpness below is computed in single precision the same way.
double held_sharpness(double s) noexcept;
/// Sharpness after one level: s − 1 (0 once s ≤ 1), infinite stays infinite.
double decremented_sharpness(double s) noexcept;
/// The sharpness after one level of the halves, at a vertex, of the edges around it (`around`, their
/// sharpness; `out` the same size): `decremented_sharpness` under the uniform method; under Chaikin's,
/// ¾s + ¼(mean of the other semi-sharp edges at the vertex) − 1. Linear in the valence.
void child_edge_sharpness(CreaseMethod method, std::span<const double> around,
                          std::span<double> out) noexcept;

/// A vertex's neighbourhood as its rule sees it: incident face count and the sharpness of its
/// incident edges (in ring order) and of itself, before and after the step.
struct VertexNeighbourhood {
  int faces = 0;
  std::span<const double> edges, child_edges;
  double sharpness = 0, child_sharpness = 0;
};

/// A vertex point's weights: `vertex` on the vertex itself, `edge` on the far end of every incident
/// edge, `face` on the centre of every incident face (Catmull–Clark), plus `crease` on the far ends of
/// the two ring edges `crease_ends` (-1: none). Every OpenSubdiv mask of Catmull–Clark, Loop and
/// bilinear (smooth, crease, corner and their fractional blends) has this form.
struct VertexMask {
  double vertex = 1, edge = 0, face = 0;
  std::array<int, 2> crease_ends{-1, -1};
  double crease = 0;
};
/// The vertex point rule of a primal scheme (Catmull–Clark, Loop, bilinear) at a vertex with at least
/// one edge: the parent rule's mask, blended with the child rule's when the step changes the rule
/// (OpenSubdiv's ComputeVertexVertexMask and ComputeFractionalWeightAtVertex).
VertexMask vertex_mask(MeshScheme scheme, CreaseMethod method, const VertexNeighbourhood& n);
/// The weight of the parent rule's mask when a vertex's rule changes during the step (OpenSubdiv's
/// ComputeFractionalWeightAtVertex): the mean sharpness of what turns smooth — the vertex and the
/// edges of `n` — at most 1, in single precision as sharpness is held. The face-varying rules take
/// it over a part of the ring (the edges inside one value's span).
double fractional_weight(CreaseMethod method, const VertexNeighbourhood& n) noexcept;

/// An edge's neighbourhood: its sharpness, that of its two halves after the step, and the sizes of its
/// (one or two) faces.
struct EdgeNeighbourhood {
  double sharpness = 0;
  std::array<double, 2> child_sharpness{0, 0};
  std::array<int, 2> face_sizes{0, 0};  // 0: no second face
  bool operator==(const EdgeNeighbourhood&) const = default;
};
/// An edge point's weights: `end` on each end, `face` on each face — its centre for Catmull–Clark,
/// its corner opposite the edge for Loop (OpenSubdiv's ComputeEdgeVertexMask: the smooth mask, the
/// midpoint on a crease, their blend by the sharpness when the edge turns smooth during the step).
struct EdgeMask {
  double end = 0.5, face = 0;
};
EdgeMask edge_mask(MeshScheme scheme, TriangleRule triangles, const EdgeNeighbourhood& n);

/// The rules of Biermann, Levin and Zorin 2000 ("Piecewise smooth subdivision surfaces with normal
/// control"; RuleSet::blz, docs/subdivision-surfaces.md): at a crease or corner vertex c, the edge
/// point of a smooth edge c r inside a sector of k faces that spans the angle θ weighs ¾ − γ on c and
/// γ on r, the other weights as usual (⅛ on the two opposite corners for Loop, 1/16 on the other
/// corners of the two quads for Catmull–Clark), with θ_k = θ/k and γ = ½ − ¼cos θ_k (Loop),
/// ⅜ − ¼cos θ_k (Catmull–Clark): γ = ⅜, the standard rule, at a regular crease (θ_k = π/3 and
/// π/2). This is the shift δ = ⅜ − γ from r to c that the standard edge point gets.
double blz_edge_shift(MeshScheme scheme, double cos_theta_k) noexcept;
/// θ: π for a crease or boundary sector, π/2 for a convex corner's, 3π/2 for a concave corner's.
double blz_sector_angle(VertexRule rule, bool concave) noexcept;
/// The flatness s of a concave corner's sector: its vertex, edge and face points p become
/// (1 − s)p + s(c + ½x₁(e₀ − c) + ½x₂(e_k − c)), x₁, x₂ the subdominant eigenvectors' values at
/// p (e₀, e_k the ends of the sector's sharp edges), which keeps λ = ½ and its eigenvectors and
/// scales every other eigenvalue by 1 − s (the reference implementation's default, Subdivide 2.0).
inline constexpr double kBlzConcaveFlatness = 0.5;

}  // namespace cifs::subdivision
