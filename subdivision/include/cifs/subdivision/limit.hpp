// SPDX-License-Identifier: MIT
// cifs — limit positions and normals of a subdivision surface's vertices, from the left
// eigenvectors of the local subdivision matrices (docs/subdivision-surfaces.md, "Limit points").
//
// At a vertex of valence n the invariant neighbourhood x (mesh_analysis.hpp's numbering) evolves
// as x_{k+1} = S_n x_k. A left eigenvector l of S_n for 1 gives l·x_{k+1} = l·x_k: normalised to sum
// 1 it is the limit position's stencil, exact at any level. Two left eigenvectors for the
// subdominant λ1 give l·x_{k+1} = λ1 l·x_k: each is the component of the neighbourhood along one
// subdominant right eigenvector, that is, a vector of the tangent plane — their cross product is
// the normal. Computed once per valence and replayed on any topology, like the refinement's weights.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_triangle.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/mesh.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision {

/// The tangent masks of one sector of a vertex between sectors (a crease or corner vertex: its faces
/// split by the sharp edges between two of them): `faces` are positions in vertex_faces(topology, v),
/// counter-clockwise; `tangent_u`, `tangent_v` weigh the vertex's neighbourhood like LimitMask's, with
/// tangent_u × tangent_v pointing to the side the sector's faces are counter-clockwise from. Both empty
/// where the sector's spectrum proves no tangent plane, `refused` saying why.
struct SectorMask {
  std::vector<int> faces;
  std::vector<double> tangent_u, tangent_v;
  std::string refused;
};

/// Limit weights for one kind of vertex (a valence, interior or boundary), on its neighbourhood in
/// mesh_analysis.hpp's numbering (Butterfly's vertices next to an extraordinary or boundary vertex:
/// whatever the level's vertices their masks weigh): `position` sums to 1; `tangent_u`, `tangent_v`
/// sum to 0 (empty under bilinear, at isolated vertices, at Butterfly's boundary vertices, at vertices
/// between sectors and where no tangent plane is proved), ordered so that tangent_u × tangent_v
/// points to the side the faces are counter-clockwise from. Their lengths are not derivatives of any
/// parametrisation: use them for the tangent plane and the normal. `refused`: why a vertex of one
/// sector has no tangents (else empty). `sectors`: at a vertex between sectors (Catmull–Clark and
/// Loop), one per sector (the surface has a tangent plane per sector there); empty elsewhere.
struct LimitMask {
  std::vector<double> position, tangent_u, tangent_v;
  std::string refused;
  std::vector<SectorMask> sectors;
};

/// Per vertex of a topology, its neighbourhood (the topology) and which mask weighs it (the
/// weights, one copy per kind of vertex).
struct LimitStencils {
  std::vector<int> offsets{0};   // `#V + 1`, into columns
  std::vector<int> columns;      // each vertex's neighbourhood, in its mask's order
  std::vector<int> mask_of;      // per vertex, an index into masks
  std::vector<LimitMask> masks;  // one per kind of vertex present
};

/// Limit positions and tangent directions of every vertex (`#V by d` each, d the data's columns);
/// tangent rows are 0 where the mask has none.
struct LimitFrame {
  Points positions, tangent_u, tangent_v;
};
LimitFrame evaluate_limit(const LimitStencils& stencils, const Points& vertices, bool tangents = true);
/// The same into `out`, whose storage is reused when it already has the size.
void evaluate_limit(const LimitStencils& stencils, const Points& vertices, LimitFrame& out,
                    bool tangents = true);

/// The stencils of every vertex of a refinement's last level, under its features (creases, corners,
/// holes, boundary rules; docs/subdivision-surfaces.md, "Limit points"):
/// - Catmull–Clark and Loop, every vertex class and valence. A smooth interior vertex (regular faces
///   around it) takes the closed-form masks (smooth_mask in limit.cpp, any valence). Any other — on
///   the boundary, on or next to a sharp edge, a corner, a dart, next to a hole or a non-quad, semi-sharp
///   — is cut out with its one-ring (under Chaikin's crease method with the faces and edges of the far end
///   of each semi-sharp edge that has another semi-sharp edge there: the edge's half at that end decays
///   with it) and refined by the production rules until the ring is stationary
///   (its sharpness spent: at most ⌈s⌉ steps), where its class's matrix S gives the position (the left
///   eigenvector of 1) and the tangents of each sector (the faces between sharp or boundary edges; one
///   sector at a dart, a boundary vertex without sharp edges, a smooth vertex): the left eigenvectors of
///   the real subdominant pair of S's block on the sector (valence ≤ 128), where that block proves a
///   plane (see SectorMask; refused, as evaluate_limit_surface refuses: no real pair above the rest, the
///   bounding curves leaving the plane, a face alone between two edges that are one smooth curve). One
///   sector: the mask's tangents; several (creases, corners): `sectors`. Its own masks are the class's
///   through those steps: exact at any level, the sharpness still to spend included.
/// - Butterfly and bilinear interpolate: every vertex is its own limit. Butterfly's interior vertices
///   (valence ≥ 3) take the tangents of the left eigenvectors of S_n for λ1 = ½, closed forms at every
///   valence (butterfly_mask in limit.cpp): on S_n's neighbourhood where every neighbour is an interior
///   vertex of valence 6 (at every interior vertex from the first step on), otherwise — next to an
///   extraordinary or boundary vertex — through the step's own rows of its child's neighbourhood,
///   where S_n holds. Its boundary vertices have no tangents
///   (`refused`). √3: interior vertices of valence 3 … 16, from the eigenvectors of local_matrix.
/// InvalidInput naming the vertex for what is not built; Doo–Sabin's limit points belong to faces.
LimitStencils limit_stencils(const MeshRefinement& refinement);

/// The mesh's own tags give the features.
struct LimitOptions {
  /// Unit normals: per vertex, or per face corner (Mesh::normal_indices) when a vertex is between sectors
  /// (each corner takes its sector's); InvalidInput naming the vertex where a sector has no tangent plane.
  bool normals = false;
  std::size_t max_bytes = std::size_t{4} << 30;
};

/// The mesh after `levels` steps with every vertex moved to its limit position (and `normals` set
/// when asked): a sampling of the limit surface itself, exact at the vertices. It carries the last
/// level's tags (holes stay holes).
Mesh limit_mesh(const Mesh& mesh, MeshScheme scheme, int levels, const LimitOptions& options = {});

/// A point of a face's parameter domain (OpenSubdiv's): a quad's square [0, 1]² with corner 0 at
/// (0, 0), 1 at (1, 0), 3 at (0, 1); a triangle's u, v ≥ 0, u + v ≤ 1 with corner 1 at (1, 0), 2 at
/// (0, 1).
struct FacePoint {
  int face = 0;
  double u = 0, v = 0;
};

/// Positions and first partials ∂/∂u, ∂/∂v, `#points by d` (du, dv empty when not asked for), unit
/// normals du × dv / |du × dv| when asked (`#points by 3`, else empty).
struct SurfaceSample {
  Points positions, du, dv, normals;
};

/// What evaluate_limit_surface computes beside the positions.
struct SurfaceOptions {
  bool partials = true;  // du, dv; without them no point is refused for want of a tangent plane
  bool normals = false;  // with the partials; 3-D data only; refused where du and dv are parallel
};

/// A patch with one extraordinary corner of valence n as a controlled IFS (Stam 1998 without the
/// eigenbasis): its control points go one level down by `subdivide` into the patch at the corner,
/// whose net has the same shape, and by `regular[k]` into the regular nets of the other quarters.
/// The attractor of this automaton — the extraordinary state looping on itself, leaving into
/// regular states — is the patch.
/// Catmull–Clark: 2n + 8 control points (the corner's neighbourhood, then the 7 outer points);
/// regular[k] are 16-point B-spline nets (rows by i along s, then j) of the quarters k = 0: s ≥ ½,
/// t < ½; 1: both ≥ ½; 2: s < ½, t ≥ ½; the corner at (s, t) = (0, 0).
/// Loop: n + 6 control points (the corner's neighbourhood, then the 5 points beyond it in the other
/// corners' rings) of the triangle s, t ≥ 0, s + t ≤ 1; regular[k] are 12-point nets (the regular
/// patch's, n = 6) of the triangles k = 0 at corner (1, 0), at (2s − 1, 2t); 1 at corner (0, 1), at
/// (2s, 2t − 1); 2 the middle one turned by a half turn, at (1 − 2s, 1 − 2t). At n = 6 the patch is
/// the regular one (a quartic box-spline patch) and `subdivide` its own corner triangle.
struct ExtraordinaryPatch {
  int valence = 0;
  Eigen::MatrixXd subdivide;               // square, the patch's control points
  std::array<Eigen::MatrixXd, 3> regular;  // regular nets × the patch's control points
  Eigen::RowVectorXd limit;                // the corner's limit position's weights
};
ExtraordinaryPatch catmull_clark_patch(int valence);
ExtraordinaryPatch loop_patch(int valence);

/// The regular Loop patch (the quartic three-direction box spline of loop_patch(6)'s 12 points) in
/// the layout of ifs::triangle_bcifs: its children C0, C1, C2, M (loop_patch(6)'s subdivide, regular[0
/// … 2]); side k the 10 points whose box splines do not vanish on the side from corner k to k + 1 (all
/// but the two beyond the opposite corner), read in the order of side 0's turned by k thirds of a turn;
/// the reversal of a side's net by the half turn about its midpoint. Positions from the lattice of the
/// patch (docs/bcifs.md, "Triangular patches").
ifs::TrianglePatch loop_triangle_patch();

/// A subdivision surface's limit as one controlled IFS: a patch per face of the mesh, four children
/// per state. Catmull–Clark: state "regular" (the 16-point uniform bicubic B-spline net; children
/// GH, GB, DH, DB by the tensor products of the cubic B-spline's G and D, as automata/tensor.hpp
/// orders them) or "E<n>" for a face with an extraordinary corner of valence n (its
/// ExtraordinaryPatch net; child GH is E<n> itself by `subdivide`, the other three are regular
/// quarters), in the quad layout of ifs::quad_mesh. Loop: "regular" (12 points) or "E<n>"
/// (n + 6), children C0 (the triangle at the patch's corner (0, 0): E<n> itself), C1, C2 and M (the
/// regular triangles of loop_patch). The ifs engine (attractors, tolerance traversal, chaos game;
/// ifs::patch_meshes for quads) runs on it unchanged.
struct SurfaceAutomaton {
  MeshScheme scheme = MeshScheme::catmull_clark;
  automata::Automaton automaton;  // an initial entry per face (its `segment`), holes skipped
  std::vector<Points> nets;       // per initial entry
  /// Per initial entry: the mesh vertices at the patch's (s, t) = (0, 0), (1, 0), (1, 1), (0, 1) (triangles:
  /// (0, 0), (1, 0), (0, 1), then −1), counter-clockwise like the face (its first extraordinary or irregular
  /// corner at (0, 0)). The patch's (s, t) is the face's (u, v) turned by one step per position of corners[0]
  /// among the face's corners.
  std::vector<std::array<int, 4>> corners;
};
/// The automaton of a closed untagged mesh under Catmull–Clark (quads) or Loop (triangles) whose faces
/// have at most one extraordinary corner (InvalidInput naming the face otherwise; one step of refinement
/// gives that); under Catmull–Clark also of a mesh with a boundary or tags: quads, holes skipped, states of
/// configurations (docs/subdivision-surfaces.md). InvalidInput for other schemes, blz, Loop with features.
SurfaceAutomaton surface_automaton(const Mesh& mesh, MeshScheme scheme);

/// The limit surface at any (face, u, v) of any mesh refine_topology takes under Catmull–Clark or
/// Loop, with its tags (boundaries under the three rules, sharp and semi-sharp creases under both
/// crease methods, corners, darts, holes) and any valence, exactly, partials included, in OpenSubdiv's
/// parametrisation (Bfr::Parameterization): quads (u, v) ∈ [0, 1]² (corner 0 at (0, 0), 1 at (1, 0), 3
/// at (0, 1)); triangles u, v ≥ 0, u + v ≤ 1 (corner 1 at (1, 0), 2 at (0, 1)); Catmull–Clark's n-gons
/// (triangles too) as n quad sub-faces, sub-face i (the quad of corner i one level down, its own u
/// towards the edge after corner i) the square [x, x + ½] × [y, y + ½], x = i mod D, y = i div D, D = 2
/// for triangles, 3 for 5 … 9 corners, 1 + ⌊√(n − 1)⌋ from 10.
/// An automaton of local configurations (a face, the one-rings of its corners, their tags) refined by
/// the production rules: a point descends until its configuration's patch is a polynomial — proved
/// so, not assumed: regular interior, boundary, crease and corner patches — and is evaluated there
/// (docs/subdivision-surfaces.md, "The limit surface at any (face, u, v)").
/// At a vertex whose configuration never becomes one (extraordinary, dart, a crease vertex's sector that
/// is not regular) the value is its limit point (limit_stencils' route), and the parametric partials do
/// not exist there (they tend to 0 where the subdominant eigenvalue λ < ½, grow without bound where
/// λ > ½): du and dv are instead the parts of the face's two edges out of the vertex in its tangent
/// plane — the plane of the subdominant eigenvectors of the vertex's sector (the faces around it between
/// sharp edges, the point's face among them) — signed as ∂/∂u, ∂/∂v are (the edge along u, the other
/// along v, each leaving the corner with the sign of the parameter's change), measured at the face's
/// level: Σ_i r_i(e) λ_i^−k (l_i · ring_k) over the pair, which is the parametric derivative at a
/// regular vertex. Their cross product is along the limit normal (the limit of the normals at points
/// approaching the vertex; limit_stencils' normal where it has one); their lengths are a convention.
/// InvalidInput naming the point where that sector's spectrum proves no tangent plane (no real
/// subdominant pair above the rest, the curves bounding the sector leaving its plane, the face alone
/// between two sharp or boundary edges — a smooth corner —, a sector of more than 128 faces) unless the
/// partials are not asked for; normals are refused, naming the point, where du and dv are parallel (a
/// polynomial patch's corner on a straight crease or boundary, where the parametric partials span no
/// plane). InvalidInput naming the point for a face that does not exist, a hole
/// (tagged, or under the boundary rule `none`), (u, v) outside the domain or not finite;
/// refine_topology's refusals for the mesh (non-manifold, Loop on non-triangles).
SurfaceSample evaluate_limit_surface(const Mesh& mesh, MeshScheme scheme, std::span<const FacePoint> at,
                                     const SurfaceOptions& options = {});
/// The same into `out`, whose storage is reused when it already has the size (no fresh pages for the
/// kernel to clear on repeated calls: on 1 M points most of the time of a fresh output). After an
/// InvalidInput its contents are unspecified.
void evaluate_limit_surface(const Mesh& mesh, MeshScheme scheme, std::span<const FacePoint> at,
                            SurfaceSample& out, const SurfaceOptions& options = {});

/// The attractor of a surface automaton at `depth` as one mesh, 4^depth cells per face in face
/// order, `states` the leaves' automaton states. Quads: cell (I, J) of face f at f·4^depth +
/// I·2^depth + J, I along s. Triangles: the leaves in depth-first order of the children C0, C1, C2, M. Nodes
/// shared by neighbouring faces (along a mesh edge, at a mesh vertex) are one vertex, found from the mesh's
/// topology and computed by the first face that holds it.
Mesh surface_automaton_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options = {});

/// A fractal subdivision surface with the mesh's topology: the "regular" state is replaced by the
/// BC-IFS of the regular patch, perturbed by `options` — Catmull–Clark: the uniform bicubic patch's
/// (ifs::surface_bcifs; its face cells, named "(x,y)"); Loop: the quartic box-spline patch's
/// (ifs::triangle_bcifs(loop_triangle_patch()); face cells "T012" … "T"). The patch's sides keep their
/// smooth operators (Catmull–Clark: they lie on knot lines; Loop: the edge cells "Eb"), so every face
/// keeps the smooth surface's boundary curves exactly and the surface stays closed (the mesh's
/// boundary and creases, Catmull–Clark, are such curves), while the inside of every regular patch —
/// around irregular vertices too, whose patches are rings of regular ones — turns fractal.
/// Fractal feature curves ("a smooth surface whose crease lines are fractal"): the mesh edges made
/// fractal, each with the net of its segment of the feature curve — the uniform cubic B-spline of the
/// crease (or boundary) polygon, a phantom point 2a − b beyond a corner a — from its lower vertex to
/// its higher one, and the perturbed BC-IFS of that curve (ifs::curve_bcifs of the uniform cubic
/// segment: 2 free coefficients, the midpoint vertex operator's centre row; knot points fixed, so every
/// mesh vertex stays where it was). The attractor meshes (surface_automaton_mesh) add to each face
/// touching such an edge the displacement φ·Δ: Δ the perturbed curve minus the smooth one along the
/// edge, φ the blend 1 − 3d² + 2d³ of the distance d from the edge (quads: the other parameter;
/// triangles: λ_c / (λ_a + λ_c) for the edge ab, c the third corner), so the displacement vanishes
/// with its slope on the face's other sides and both faces of a crease meet on the perturbed curve.
struct FractalFeatures {
  ifs::Perturbation perturbation;             // of the curve segment's BC-IFS
  ifs::Bcifs smooth;                          // the same system unperturbed
  std::map<std::array<int, 2>, Points> nets;  // per fractal edge (lower, higher vertex): 4 × dim
};

/// Which feature curves become fractal. Infinitely sharp creases and boundary curves whose ends are
/// crease, boundary or corner vertices (two or more sharp edges, or a corner tag): there the smooth
/// surface's curve is the uniform cubic B-spline of the feature polygon, whatever the faces beside it.
/// A curve stays smooth over an edge ending at a dart or at a vertex with a semi-sharp tag — and
/// semi-sharp creases stay smooth: after their sharpness is spent they are no curves of their own.
struct FractalFeatureOptions {
  bool creases = false;     // the infinitely sharp creases
  bool boundaries = false;  // the mesh's boundary curves (its boundary rule's, edge_only or edge_and_corner)
  ifs::PerturbOptions perturbation;  // of the curves' BC-IFS: amplitude, seed, values by name
};

struct FractalSurface {
  SurfaceAutomaton surface;
  ifs::Perturbation perturbation;  // of the regular patch's BC-IFS: values, residual, contraction
  FractalFeatures features;        // no nets: every feature curve stays the smooth surface's
};
FractalSurface fractal_surface(const SurfaceAutomaton& smooth, const ifs::PerturbOptions& options);
/// The same with fractal feature curves: `mesh` is the mesh `smooth` was built from (its tags say where
/// the creases and corners are). InvalidInput when a kind of curve is asked for and the mesh has none
/// that can be made fractal (naming why: no infinitely sharp crease, no boundary, every one ending at a
/// dart or a semi-sharp tag), when `mesh` is not `smooth`'s, or as ifs::perturb.
FractalSurface fractal_surface(const Mesh& mesh, const SurfaceAutomaton& smooth,
                               const ifs::PerturbOptions& options, const FractalFeatureOptions& features);

/// The attractor of a fractal surface at `depth` as surface_automaton_mesh, with its fractal feature
/// curves' displacements added face by face before the nodes are welded.
Mesh surface_automaton_mesh(const FractalSurface& fractal, int depth, const ifs::MeshOptions& options = {});

/// The nodes of a fractal feature edge (lower vertex, higher) at `depth`: 2^depth + 1 rows from the
/// lower vertex, the perturbed curve's attractor (ifs::edge_pieces). InvalidInput for an edge that is
/// not one.
Points feature_curve_nodes(const FractalFeatures& features, std::array<int, 2> edge, int depth);
}  // namespace cifs::subdivision
