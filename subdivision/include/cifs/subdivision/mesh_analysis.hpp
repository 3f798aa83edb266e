// SPDX-License-Identifier: MIT
// cifs — the local subdivision matrix S_n of a mesh scheme around an extraordinary vertex (seed 003
// §1) and its spectrum: what decides the tangent plane and the curvature of the limit surface there
// (docs/subdivision-surfaces.md, "Spectra at extraordinary vertices").
//
// The invariant neighbourhood and its numbering, sector j = 0 … n − 1 counter-clockwise from r_0
// (c the vertex, r_j its neighbours, face j between r_j and r_{j+1}):
// - Catmull–Clark: c, then r_j, f_j per sector (f_j the corner of quad j opposite c): 2n + 1; on
//   the boundary c, r_0, f_0, …, f_{n−2}, r_{n−1} (n edges, n − 1 quads): 2n.
// - Loop: c, r_0 … r_{n−1}: n + 1, on the boundary too.
// - Modified Butterfly (two rings): c, then r_j, p_j, q_j per sector, p_j the vertex beyond r_j
//   (opposite c in r_j's ring), q_j the corner across the edge r_j r_{j+1}: 3n + 1; on the boundary
//   (n edges, n − 1 faces) p_0 and p_{n−1} are the next boundary vertices and q_j runs to n − 2: 3n.
// - √3, two steps (one step rotates the ring by half a sector): c, r_0 … r_{n−1}: n + 1. After
//   one step the ring is the face centroids; after two, the centroid of the level-1 triangle
//   (c¹, m_{j−1}, m_j) lies in the direction of r_j and takes its number. On the boundary (c,
//   r_0 … r_{n−1}, from an even level: the boundary kept, then trisected) r_0 and r_{n−1} become
//   the trisection points next to c, and r_j the centroid of (c, m_{j−1}, m_j): the one-ring is
//   invariant there too (the trisection points that read two boundary vertices away are not in it).
// - Doo–Sabin, around a k-gon face (valence k): per corner g_i of the face, g_i, a_i, b_i, c_i:
//   a_i, b_i the outer corners of the quad across the edge g_i g_{i+1} (a_i next to g_i), c_i the
//   corner opposite g_i of the quad at g_i outside the two edge quads: 4k.
// Every vertex other than the extraordinary one is regular (valence 4 for quads, 6 for triangles).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/mesh.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/scheme.hpp"

namespace cifs::subdivision {

using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using LongVector = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

/// A dense exact matrix, row-major.
struct RationalMatrix {
  int rows = 0;
  int cols = 0;
  std::vector<Rational> entries;
  const Rational& operator()(int i, int j) const {
    return entries[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) +
                   static_cast<std::size_t>(j)];
  }
};

/// Where the extraordinary vertex is and what is tagged there. Boundary vertices (valence = number
/// of edges, 2 … 16: valence − 1 faces) are analysed for Catmull–Clark, Loop, Butterfly (mesh.cpp's
/// rule: the 4-point curve, reflected wings) and √3 (Kobbelt's boundary rule); Butterfly and √3 have
/// one boundary rule (`rule` must be edge_only); infinitely sharp edges and corners for
/// Catmull–Clark and Loop only, with the rules OpenSubdiv uses (rules.hpp): `rule` at valence 2
/// (one face); a sharp edge's point is its midpoint; the vertex follows the smooth rule with no or
/// one sharp edge (a dart), the crease rule ¾c + ⅛(ends) with two (a boundary's edges count), and
/// stays (a corner) with more or when `corner`.
struct LocalOptions {
  bool boundary = false;
  BoundaryRule rule = BoundaryRule::edge_only;
  /// Infinitely sharp edges c r_j, by j (increasing; on the boundary 1 … valence − 2: the boundary
  /// edges are sharp anyway). They cut the faces around c into sectors.
  std::vector<int> sharp{};
  bool corner = false;  // c infinitely sharp
  /// A corner whose sectors are meant to span more than π together (Biermann, Levin, Zorin 2000):
  /// the verdict asks for a sector image angle above π instead of below.
  bool concave = false;
  /// OpenSubdiv's rules or Biermann–Levin–Zorin's (rules.hpp; `concave` then flattens the corner's
  /// sectors).
  RuleSet rules = RuleSet::opensubdiv;
  /// Doo–Sabin at a k-gon face touching the boundary (`boundary` set; k = the valence): whether each
  /// corner g_i is an interior vertex, at least one of them and not all (doo_sabin_boundary_matrix).
  std::vector<char> interior_corners{};
};

/// What the options make of the vertex: "interior", "dart", "boundary", "crease" or "corner" (the
/// vertex rule; "boundary" for the crease rule along a boundary, and for a Doo–Sabin face touching it).
std::string vertex_class(int valence, const LocalOptions& options);

/// The faces of each sector between consecutive sharp edges (boundary edges included),
/// counter-clockwise from r_0; a smooth or dart vertex has one sector of all its faces. A Doo–Sabin
/// face touching the boundary: its runs of interior corners (each a sector of the surface), from g_0.
std::vector<int> sector_sizes(int valence, const LocalOptions& options);

/// Valences analysed: interior 3 … 16 (Doo–Sabin: the face's corners), boundary 2 … 16 (1 … 15 faces).
inline constexpr int kMinValence = 3;
inline constexpr int kMaxValence = 16;
inline constexpr int kMinBoundaryValence = 2;
inline constexpr int kMaxBoundaryValence = 16;

/// S_n: new neighbourhood = S_n · old neighbourhood, in the numbering above. Rows sum to 1.
struct LocalMatrix {
  MeshScheme scheme = MeshScheme::catmull_clark;
  int valence = 0;
  LocalOptions options;
  int steps = 1;                    // subdivision steps S_n spans: 2 for √3, else 1
  std::vector<std::string> labels;  // "c", "r0", "f0", …: the numbering
  /// The exact matrix when every weight is rational: always for Catmull–Clark and √3 boundary
  /// vertices; Loop, √3 and Doo–Sabin when cos(2π/n) is rational (n = 3, 4, 6); Butterfly at n = 3, 4, 6
  /// and on the boundary.
  std::optional<RationalMatrix> exact;
  /// The same in long double (the exact one rounded; otherwise computed with long double cosines,
  /// every entry within 1e-18 of its true value).
  LongMatrix values;
};

/// Route (a): S_n written from the scheme's rules in the numbering above (a Doo–Sabin face touching the
/// boundary: doo_sabin_boundary_matrix of `options.interior_corners`). Throws InvalidInput for a
/// valence out of range or interior corners that do not fit it.
LocalMatrix local_matrix(MeshScheme scheme, int valence, const LocalOptions& options = {});

/// The local mesh route (b) refines: the extraordinary vertex (Doo–Sabin: face) of the valence
/// with `rings` rings of regular faces around it, vertex (face) 0 at the centre; planar positions.
Mesh local_mesh(MeshScheme scheme, int valence, const LocalOptions& options = {}, int rings = 3);

/// Route (b): S_n read off the general refinement (`refine_topology`, √3 two levels through
/// `stencil_table`) of `local_mesh`: the neighbourhood found from the topology on both levels, the
/// child vertex matched to the old one it weighs most (the centre, then r_0 or g_0), its rows taken
/// as they are. `exact` is empty; `values` are the refinement's doubles. Throws std::logic_error
/// if the child neighbourhood's weights reach outside the old one (it would not be invariant).
LocalMatrix refined_local_matrix(MeshScheme scheme, int valence, const LocalOptions& options = {});

/// The spectrum and what it says. Eigenvalues in long double (Eigen's real Schur form); an
/// equality below is decided to `tolerance`.
///
/// μ is λ3, the eigenvalue of largest modulus after λ0 = 1 and the subdominant pair λ1 ≥ λ2 (0
/// when S_n has three eigenvalues). The limit surface near the vertex scales like λ2^k across and
/// μ^k out of its tangent plane, so its curvature goes like (|μ|/λ2²)^k: the ratio λ2²/|μ| (=
/// λ1²/|μ| at an interior vertex, where λ1 = λ2) is 1 for bounded curvature, > 1 when it tends to
/// 0 at the vertex (a flat spot) and < 1 when it grows without bound (for generic data, whose
/// component along μ's eigenvectors is not zero).
struct LocalSpectrum {
  /// By modulus, largest first; equal moduli: larger real part first, then larger imaginary part.
  std::vector<std::complex<long double>> eigenvalues;
  bool dominant_simple = false;                // λ0 = 1 and |λ1| < 1
  bool subdominant_pair = false;               // λ1 = λ2 real and positive (at a boundary vertex: rarely)
  bool gap = false;                            // |λ3| < λ2, λ1 and λ2 real and positive
  long double subdominant = 0;                 // λ1 (real part)
  long double second = 0;                      // λ2 (real part)
  std::complex<long double> mu{0};             // λ3
  std::optional<long double> curvature_ratio;  // λ2²/|μ|; absent when μ = 0
  std::string curvature;                       // "bounded", "zero" (also when μ = 0), "unbounded"
  /// N by 2, orthonormal columns: ker(S − λ1 I) when λ1 = λ2, else an eigenvector of λ1 and one of λ2.
  LongMatrix subdominant_basis;
  LongVector limit_stencil;  // left eigenvector of 1, summing to 1: the limit position's weights
  long double residual = 0;  // max |S x − λ x| over the basis, |yᵀS − yᵀ| over the stencil
  long double tolerance = 1e-12L;
};

LocalSpectrum local_spectrum(const LocalMatrix& matrix);

/// Reif's test of C¹ at an interior extraordinary vertex (Doo–Sabin: face): with λ0 = 1 simple and
/// a real double subdominant λ1 = λ2 above every other |λ|, the limit surface is C¹ there for
/// generic data iff the characteristic map Φ — the limit of the net whose planar positions are the
/// two subdominant eigenvectors, extended outside the invariant neighbourhood by the eigen-equation
/// — is regular (its Jacobian has one sign, nowhere zero) and injective on one ring of patches.
/// A regular Φ is injective iff the ring's inner boundary winds once around Φ(centre) = 0.
///
/// `bernstein` (Catmull–Clark, Loop, Doo–Sabin: the regular patches are polynomials): every patch
/// of the ring, exactly the polynomial of its regular limit (bicubic / quartic box spline from
/// its limit values at the dyadic points of two steps, biquadratic from its B-spline net), in
/// Bernstein form; the Jacobian's Bernstein coefficients bound it from below (de Casteljau splits
/// where they do not decide), and the winding is counted on the inner boundary's Bézier pieces,
/// each inside a half-plane that misses 0 — a proof up to long double round-off, which the margin
/// (1e-12 of the largest coefficient) exceeds. `sampled` (Butterfly, √3: no polynomial pieces):
/// the orientation of every triangle of the net after `levels` steps and the winding of the
/// centre's ring there — evidence, not a proof.
///
/// Tagged vertices (Zorin 2000, "A method for analysis of C1-continuity of subdivision surfaces";
/// Biermann, Levin, Zorin 2000): the limit surface is piecewise smooth, one piece per sector, and the
/// rows of a sector's vertices (c, its two sharp edges' points, the points inside it) read nothing
/// from the other sectors, so each sector is the boundary vertex of as many faces under the same
/// centre rule, analysed on its own: λ0 = 1 simple, λ1 ≥ λ2 real and positive (equal or not: a
/// boundary's curve gives ½, its inside another value; equal with one eigenvector, a Jordan block, is
/// undecided), |λ3| < λ2, and the characteristic map of the
/// eigenvectors of λ1 and λ2 regular on the sector and injective — its inner boundary, from one
/// sharp edge to the other, sweeps an angle in (0, 2π) without passing through 0 (it does when
/// both eigenvectors vanish on the sharp edges: the sector's curves then shrink faster than its
/// inside and the surface folds onto the tangent plane of the inside). A corner sector must span
/// less than π (convex) or more (concave: `LocalOptions::concave`); the standard corner rule
/// spans the convex cone of its two curves' tangents, so it cannot make a concave corner. A dart
/// is checked like an interior vertex on its tagged net (λ1 ≠ λ2 allowed). Tagged vertices are
/// `sampled`, not proved (the patches along a sharp edge are not the regular polynomials).
struct C1Verdict {
  bool spectral = false;        // λ0 simple, subdominant pair, gap
  std::string method;           // "bernstein" or "sampled"; empty when the spectrum already fails
  int levels = 0;               // sampled: the net's level
  int pieces = 0;               // patches (triangles) checked
  int splits = 0;               // deepest de Casteljau split a patch needed
  bool decided = true;          // false when a patch's Jacobian stayed undecided after the splits
  bool regular = false;         // Jacobian of one sign on every piece
  int winding = 0;              // of the inner boundary around 0 (sign: the eigenvectors' orientation)
  bool through_centre = false;  // sampled: a point of the centre's ring maps to 0
  /// Smallest lower bound of |Jacobian| found (bernstein) or smallest |triangle area| (sampled),
  /// over the largest: how far from singular.
  long double margin = 0;
  /// A sector: the angle its image spans at 0 (radians; π along a smooth boundary or crease).
  long double angle = 0;
  bool c1 = false;
  std::string reason;  // one sentence: what decided
  struct Sector;
  /// Boundary, crease and corner vertices: each sector's verdict, counter-clockwise from r_0; the
  /// vertex is C¹ (on each sector up to its sharp edges) when every sector is.
  std::vector<Sector> sectors;
};

struct C1Verdict::Sector {
  int faces = 0;
  LocalSpectrum spectrum;  // of the sector's own matrix
  C1Verdict verdict;
};

/// `sampled` on any scheme (a cross-check of the Bernstein proof), at `levels` steps.
struct C1Options {
  bool sampled = false;
  int levels = 4;
};

/// The verdict for a matrix of `local_matrix` (any class) and its spectrum.
C1Verdict c1_verdict(const LocalMatrix& matrix, const LocalSpectrum& spectrum, const C1Options& options = {});

/// "Which points of my model are not smooth?" One vertex of a mesh whose neighbourhood is not the
/// regular grid's (an extraordinary interior vertex, a boundary vertex of other than the regular
/// number of faces, a crease with irregular sides, any dart or corner) and its local analysis.
struct VertexSmoothness {
  int vertex = 0;  // −1 for a Doo–Sabin face's centre
  /// Doo–Sabin: the face whose centre the point is (−1 for a vertex: the centre of the face the
  /// vertex becomes after one step).
  int face = -1;
  int valence = 0;           // edges (Doo–Sabin: the face's corners, the vertex's faces)
  LocalOptions options;      // its class as the local analysis sees it (sharp edges rotated to start at 0)
  std::string vertex_class;  // vertex_class(valence, options)
  std::vector<int> sectors;  // faces per sector
  long double lambda1 = 0, lambda2 = 0;
  std::optional<long double> curvature_ratio;  // λ2²/|μ|
  /// The largest semi-sharp value at the vertex (0: none): its tags decay within ceil(s) levels, and
  /// the vertex is analysed as it is from then on (the class of its infinitely sharp tags alone).
  double semi_sharp = 0;
  C1Verdict verdict;
};

/// Every irregular vertex of a mesh, by index, and the counts: regular vertices (not listed), vertices in
/// no face or only in holes (not on the surface), and the verdicts. Doo–Sabin counts points — a face's
/// centre, an interior vertex's (its face's after one step) — and `isolated` the faces off the surface
/// (every corner on the boundary) and the vertices in no face; boundary vertices make no face there,
/// so no point of their own, and are not counted. `analyses`: the distinct (class, valence,
/// sectors) configurations analysed — each once, whatever the number of its vertices.
struct MeshSmoothness {
  MeshScheme scheme = MeshScheme::catmull_clark;
  std::vector<VertexSmoothness> vertices;
  int regular = 0, isolated = 0;
  int c1 = 0, not_c1 = 0, undecided = 0;
  int analyses = 0;
  std::string summary;  // one line
};

/// The analysis of every vertex of a Catmull–Clark or Loop mesh with its tags (infinitely sharp creases
/// and corners, the boundary rules edge and corner), or of a √3 or modified Butterfly mesh (no tags:
/// their boundaries have one rule each); of every face and interior vertex of a Doo–Sabin mesh (no
/// tags; its boundary rule: boundary edges and vertices make no face). Throws InvalidInput, one line
/// naming the vertex, face or tag, for what it does not analyse: bilinear, a non-manifold mesh, the
/// boundary rule none, tags under √3, Butterfly and Doo–Sabin, valences (faces, corners) out of the
/// local analysis's range, non-triangles under Loop, √3 and Butterfly. A vertex with semi-sharp tags
/// is analysed as it is after ceil(s) levels (they have decayed; its reason says so) and is always
/// listed. Catmull–Clark vertices next to non-quads are analysed as they
/// are after one level (same valence and sectors, all quads). Holes change no rule (they leave faces out of
/// the surface only): the vertices around them are analysed as they are.
MeshSmoothness analyze_mesh(const Mesh& mesh, MeshScheme scheme, std::string_view who = "mesh");

/// Doo–Sabin at a k-gon face touching the boundary under mesh.cpp's rule (boundary edges and vertices
/// make no face), `inner[i]` whether corner g_i is an interior vertex: the principal submatrix of
/// local_matrix(doo_sabin, k) on g_0 … g_{k−1}, a_i and b_i where an end of edge g_i g_{i+1} is
/// interior, c_i where g_i is. Every corner point reads its own face alone, so these rows read these
/// columns only (an edge quad between two boundary corners, which may or may not exist, is left out:
/// it carries no patch near the centre). Exact where local_matrix is; `options.boundary` and
/// `options.interior_corners` are set. Throws InvalidInput unless 3 ≤ k ≤ 16 and some corner but not
/// every one is interior.
LocalMatrix doo_sabin_boundary_matrix(const std::vector<char>& inner);

/// The verdict at a Doo–Sabin face touching the boundary, from the interior k-gon's (`interior`) and its
/// interior corners: the surface near the centre is made of the patches of the interior corners only,
/// and their characteristic map is the k-gon's restricted to them — regular and injective where the
/// k-gon's is. By the map's k-fold symmetry a run of m interior corners spans 360m/k degrees (`angle`):
/// C1 on that sector; two runs or more touch at the centre only (a pinch): not C1. `c1_verdict` of a
/// doo_sabin_boundary_matrix computes the interior verdict and calls this.
C1Verdict doo_sabin_boundary_verdict(const C1Verdict& interior, const std::vector<char>& interior_corners);

/// The regularity and winding test alone, on any pair of eigenvectors of S_n for `lambda` (N by 2,
/// the numbering above): e.g. a higher Fourier mode's pair, whose map winds more than once.
C1Verdict characteristic_map_verdict(MeshScheme scheme, int valence, long double lambda,
                                     const LongMatrix& pair, const C1Options& options = {});

}  // namespace cifs::subdivision
