// SPDX-License-Identifier: MIT
// cifs — a subdivision surface's limit as one controlled IFS (Catmull–Clark and Loop), its
// evaluation at any (face, u, v), its attractor meshes and its fractal version
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
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/subdivision/limit.hpp"
#include "limit_patches.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {
namespace {

using detail::corner;
using detail::corner_index;

/// Uniform cubic B-spline basis on one segment and its derivative.
void cubic_basis(double t, std::array<double, 4>& b, std::array<double, 4>& d) {
  const double s = 1 - t;
  b = {s * s * s / 6, (3 * t * t * t - 6 * t * t + 4) / 6, (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6,
       t * t * t / 6};
  d = {-s * s / 2, (3 * t * t - 4 * t) / 2, (-3 * t * t + 2 * t + 1) / 2, t * t / 2};
}

/// Value and partials (times `scale`) of the bicubic B-spline patch of a 16-point net (rows by i then
/// j) at (a, b), written into three rows of D = net.cols() doubles: the loop of every point, so no
/// allocation, separable sums (along j, then i) and, for D = 3, the sums in registers.
template <int D>
void bicubic_sums(const double* net, Eigen::Index d, const std::array<double, 4>& ba,
                  const std::array<double, 4>& da, const std::array<double, 4>& bb,
                  const std::array<double, 4>& db, double scale, double* value, double* du, double* dv) {
  for (Eigen::Index k = 0; k < (D > 0 ? D : d); ++k) {
    double v = 0, u_sum = 0, v_sum = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const double* row = net + static_cast<Eigen::Index>(i * 4) * d + k;
      const double along_j = bb[0] * row[0] + bb[1] * row[d] + bb[2] * row[2 * d] + bb[3] * row[3 * d];
      const double along_dj = db[0] * row[0] + db[1] * row[d] + db[2] * row[2 * d] + db[3] * row[3 * d];
      v += ba[i] * along_j;
      u_sum += da[i] * along_j;
      v_sum += ba[i] * along_dj;
    }
    value[k] = v;
    du[k] = scale * u_sum;
    dv[k] = scale * v_sum;
  }
}

void bicubic(const Points& net, double a, double b, double scale, double* value, double* du, double* dv) {
  std::array<double, 4> ba{}, da{}, bb{}, db{};
  cubic_basis(a, ba, da);
  cubic_basis(b, bb, db);
  if (net.cols() == 3)
    bicubic_sums<3>(net.data(), 3, ba, da, bb, db, scale, value, du, dv);
  else
    bicubic_sums<0>(net.data(), net.cols(), ba, da, bb, db, scale, value, du, dv);
}

}  // namespace

namespace {

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
    if (t.boundary_vertex[v])
      throw InvalidInput(where + ": touches the boundary; boundary patches are not built");
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

/// The automaton of the given faces (initial entry i is faces[i], `segment` the face's index).
SurfaceAutomaton build_automaton(const Mesh& mesh, const MeshTopology& t, MeshScheme scheme,
                                 std::span<const int> faces) {
  SurfaceAutomaton out;
  out.scheme = scheme;
  automata::Graph& g = out.automaton.graph;
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

/// Index of the quartic Bernstein coefficient of u^a v^b w^(4 − a − b) (w = 1 − u − v).
constexpr int tri(int a, int b) {
  return a * (11 - a) / 2 + b;
}

/// Weights of the 15 quartic Bernstein polynomials at (u, v) and their partials in u and v.
void quartic_basis(double u, double v, std::array<double, 15>& b, std::array<double, 15>& bu,
                   std::array<double, 15>& bv) {
  const double w = 1 - u - v;
  std::array<double, 5> pu{1, u, u * u, u * u * u, u * u * u * u}, pv{1, v, v * v, v * v * v, v * v * v * v},
      pw{1, w, w * w, w * w * w, w * w * w * w};
  static constexpr std::array<double, 5> kFactorial{1, 1, 2, 6, 24};
  const auto at = [](const std::array<double, 5>& p, int k) {
    return k < 0 ? 0.0 : p[static_cast<std::size_t>(k)];
  };
  for (int a = 0; a <= 4; ++a)
    for (int c0 = 0; a + c0 <= 4; ++c0) {
      const int bb = c0, c = 4 - a - bb;
      const double m =
          24 / (kFactorial[static_cast<std::size_t>(a)] * kFactorial[static_cast<std::size_t>(bb)] *
                kFactorial[static_cast<std::size_t>(c)]);
      const auto k = static_cast<std::size_t>(tri(a, bb));
      b[k] = m * at(pu, a) * at(pv, bb) * at(pw, c);
      const double dw = c * at(pu, a) * at(pv, bb) * at(pw, c - 1);  // ∂/∂w
      bu[k] = m * (a * at(pu, a - 1) * at(pv, bb) * at(pw, c) - dw);
      bv[k] = m * (bb * at(pu, a) * at(pv, bb - 1) * at(pw, c) - dw);
    }
}

/// Value and partials (times `scale`) of a quartic triangle patch from its 15 Bézier rows.
void quartic(const Points& bezier, double u, double v, double scale, double* value, double* du, double* dv) {
  std::array<double, 15> b{}, bu{}, bv{};
  quartic_basis(u, v, b, bu, bv);
  for (Eigen::Index k = 0; k < bezier.cols(); ++k) {
    double x = 0, xu = 0, xv = 0;
    for (std::size_t i = 0; i < 15; ++i) {
      const double c = bezier(static_cast<Eigen::Index>(i), k);
      x += b[i] * c;
      xu += bu[i] * c;
      xv += bv[i] * c;
    }
    value[k] = x;
    du[k] = scale * xu;
    dv[k] = scale * xv;
  }
}

/// The regular Loop patch in Bernstein form: `B·net` are the quartic Bézier coefficients (rows
/// tri(a, b)) of the box-spline patch of a 12-point net. The patch is a quartic polynomial, so its
/// values at the 15 points (a, b)/4 determine it (collocation); each value is a corner of a
/// triangle two levels down, the fixed point of that corner's child repeated.
Eigen::MatrixXd quartic_bezier(const SurfaceAutomaton& s, automata::StateId regular) {
  const automata::Graph& g = s.automaton.graph;
  std::array<Eigen::MatrixXd, 4> child;
  {
    std::size_t c = 0;
    for (auto [e, end] = out_edges(regular, g); e != end; ++e) child[c++] = g[*e].matrix;
  }
  std::array<Eigen::RowVectorXd, 3> fixed;  // the corners (0, 0), (1, 0), (0, 1)
  for (std::size_t c = 0; c < 3; ++c)
    fixed[c] = ifs::repeated_child_functionals(s.automaton, static_cast<int>(c))[regular];
  constexpr int kD = 4;
  // The functional of the point (a, b)/kD, through the child holding it.
  const auto point = [&](const auto& self, int a, int b) -> Eigen::RowVectorXd {
    if (a == 0 && b == 0) return fixed[0];
    if (a == kD && b == 0) return fixed[1];
    if (a == 0 && b == kD) return fixed[2];
    if (2 * (a + b) <= kD) return self(self, 2 * a, 2 * b) * child[0];
    if (2 * a >= kD) return self(self, 2 * a - kD, 2 * b) * child[1];
    if (2 * b >= kD) return self(self, 2 * a, 2 * b - kD) * child[2];
    return self(self, kD - 2 * a, kD - 2 * b) * child[3];
  };
  Eigen::MatrixXd values(15, child[0].cols()), collocation(15, 15);
  for (int a = 0; a <= kD; ++a)
    for (int b = 0; a + b <= kD; ++b) {
      values.row(tri(a, b)) = point(point, a, b);
      std::array<double, 15> w{}, wu{}, wv{};
      quartic_basis(static_cast<double>(a) / kD, static_cast<double>(b) / kD, w, wu, wv);
      for (std::size_t k = 0; k < 15; ++k) collocation(tri(a, b), static_cast<Eigen::Index>(k)) = w[k];
    }
  return collocation.fullPivLu().solve(values);
}

/// The patch's (s, t) from the face's (u, v), the patch's corner (0, 0) being the face's corner `turn`.
std::array<double, 2> patch_parameters(bool quad, int turn, double u, double v) {
  if (quad) {
    const std::array<std::array<double, 2>, 4> st{{{u, v}, {v, 1 - u}, {1 - u, 1 - v}, {1 - v, u}}};
    return st[static_cast<std::size_t>(turn)];
  }
  const std::array<std::array<double, 2>, 3> st{{{u, v}, {v, 1 - u - v}, {1 - u - v, u}}};
  return st[static_cast<std::size_t>(turn)];
}

/// The partials in the face's (u, v) from those in the patch's (s, t): ps, pt in, du, dv out.
void face_partials(bool quad, int turn, const Eigen::RowVectorXd& ps, const Eigen::RowVectorXd& pt,
                   Eigen::Ref<Eigen::RowVectorXd> du, Eigen::Ref<Eigen::RowVectorXd> dv) {
  if (quad) {
    switch (turn) {
      case 0:
        du = ps, dv = pt;
        return;
      case 1:
        du = -pt, dv = ps;
        return;
      case 2:
        du = -ps, dv = -pt;
        return;
      default:
        du = pt, dv = -ps;
        return;
    }
  }
  switch (turn) {
    case 0:
      du = ps, dv = pt;
      return;
    case 1:  // s = v, t = 1 − u − v
      du = -pt, dv = ps - pt;
      return;
    default:  // s = 1 − u − v, t = u
      du = pt - ps, dv = -ps;
      return;
  }
}

/// The points first: a bad one is named before any work.
void check_face_points(MeshScheme scheme, int F, std::span<const FacePoint> at) {
  const bool quad = quads(scheme);
  // Triangles: u + v may pass 1 by a rounding of the caller's sum.
  const double sum_limit = quad ? 2 : 1 + 1e-12;
  for (std::size_t p = 0; p < at.size(); ++p) {
    const FacePoint& q = at[p];
    const bool no_face = q.face < 0 || q.face >= F;
    if (!no_face && q.u >= 0 && q.u <= 1 && q.v >= 0 && q.v <= 1 && q.u + q.v <= sum_limit) continue;
    const std::string where = std::string(scheme_name(scheme)) + " limit: point " + std::to_string(p) +
                              " (face " + std::to_string(q.face) + ")";
    if (no_face) throw InvalidInput(where + ": no such face; the mesh has " + std::to_string(F));
    if (!std::isfinite(q.u) || !std::isfinite(q.v))
      throw InvalidInput(where + ": (u, v) is not a pair of finite numbers");
    throw InvalidInput(where + ": (u, v) = (" + number_text(q.u, 6) + ", " + number_text(q.v, 6) +
                       ") is outside " + (quad ? "[0, 1]²" : "the triangle u, v ≥ 0, u + v ≤ 1"));
  }
}

/// The patches' automaton and what evaluating a point of one reads.
struct Patches {
  const SurfaceAutomaton& s;
  bool quad;
  /// The extraordinary point itself is the fixed point of the corner child (no partials there).
  std::vector<Eigen::RowVectorXd> corner_point;
  std::vector<char> regular;  // per state
  /// Loop's regular nets are evaluated in Bernstein form: B·net once per net.
  Eigen::MatrixXd bezier;
};

Patches patches(const SurfaceAutomaton& s, bool quad) {
  Patches P{s, quad, ifs::repeated_child_functionals(s.automaton, 0),
            std::vector<char>(num_vertices(s.automaton.graph)), Eigen::MatrixXd()};
  for (automata::StateId k = 0; k < P.regular.size(); ++k) P.regular[k] = is_regular(s.automaton, k) ? 1 : 0;
  P.bezier = quad ? Eigen::MatrixXd() : quartic_bezier(s, 0);
  return P;
}

void evaluate_regular(const Patches& P, const Points& net, double a, double b, double scale, double* value,
                      double* du, double* dv) {
  if (P.quad)
    bicubic(net, a, b, scale, value, du, dv);
  else
    quartic(net, a, b, scale, value, du, dv);
}

Points regular_form(const Patches& P, const Points& net) {
  return P.quad ? net : Points(P.bezier * net);
}

/// Per face, the nets met going down: the corner parts' chain (level j: the corner part j levels
/// down, a net of its extraordinary state) and, per level, the other parts' nets (Loop: in
/// Bernstein form). Built once per face and level, so a point costs one polynomial evaluation
/// whatever its depth.
struct Descent {
  Points own;  // a regular face's net in evaluation form
  std::vector<Points> chain;
  std::vector<automata::StateId> state;
  std::vector<std::array<Points, 4>> part;
};

/// A point (a, b) of an extraordinary patch (net, state first) other than its corner: down the
/// corner's part while the point lies in it, then the regular part that holds it.
void evaluate_extraordinary(const Patches& P, const Points& net0, automata::StateId first, double a, double b,
                            Descent& down, double* value, double* du, double* dv) {
  const bool quad = P.quad;
  const automata::Graph& g = P.s.automaton.graph;
  if (down.chain.empty()) {
    down.chain.push_back(net0);
    down.state.push_back(first);
  }
  std::size_t level = 0;
  double scale = 2;
  // Down the corner's part (quads: both below ½; triangles: a + b below ½).
  for (; quad ? std::max(a, b) < 0.5 : a + b < 0.5; ++level, a *= 2, b *= 2, scale *= 2)
    if (level + 1 == down.chain.size()) {
      const auto edge = *out_edges(down.state[level], g).first;
      down.chain.push_back(g[edge].matrix * down.chain[level]);
      down.state.push_back(target(edge, g));
      if (P.regular[down.state.back()] != 0)
        throw std::logic_error("limit surface: the corner part of an extraordinary patch is regular");
    }
  if (down.part.size() <= level) down.part.resize(level + 1);
  // The child holding (a, b) and the point in its own parameters.
  int c = 0;
  double s_child = 0, t_child = 0, sign = 1;
  if (quad) {
    const int iu = a >= 0.5 ? 1 : 0, iv = b >= 0.5 ? 1 : 0;
    c = 2 * iu + iv;
    s_child = 2 * a - iu, t_child = 2 * b - iv;
  } else if (a >= 0.5) {
    c = 1, s_child = 2 * a - 1, t_child = 2 * b;
  } else if (b >= 0.5) {
    c = 2, s_child = 2 * a, t_child = 2 * b - 1;
  } else {
    c = 3, s_child = 1 - 2 * a, t_child = 1 - 2 * b, sign = -1;  // the middle triangle, turned
  }
  Points& net = down.part[level][static_cast<std::size_t>(c)];
  if (net.size() == 0) {
    auto edge = out_edges(down.state[level], g).first;
    std::advance(edge, c);
    if (P.regular[target(*edge, g)] == 0)
      throw std::logic_error("limit surface: a side part of an extraordinary patch is not regular");
    net = regular_form(P, g[*edge].matrix * down.chain[level]);
  }
  evaluate_regular(P, net, s_child, t_child, sign * scale, value, du, dv);
}

}  // namespace

SurfaceAutomaton surface_automaton(const Mesh& mesh, MeshScheme scheme) {
  check_scheme(scheme);
  const MeshTopology t = build_topology(mesh);
  std::vector<int> faces(face_count(t));
  std::iota(faces.begin(), faces.end(), 0);
  return build_automaton(mesh, t, scheme, faces);
}

SurfaceSample evaluate_limit_surface(const Mesh& mesh, MeshScheme scheme, std::span<const FacePoint> at) {
  check_scheme(scheme);
  const bool quad = quads(scheme);
  const MeshTopology t = build_topology(mesh);
  const Eigen::Index d = mesh.vertices.cols();
  const auto F = static_cast<int>(face_count(t));
  check_face_points(scheme, F, at);
  // Only the faces asked for: the others may be boundary faces.
  std::vector<int> faces, entry(static_cast<std::size_t>(F), -1);
  for (const FacePoint& q : at)
    if (entry[static_cast<std::size_t>(q.face)] < 0) {
      entry[static_cast<std::size_t>(q.face)] = static_cast<int>(faces.size());
      faces.push_back(q.face);
    }
  const SurfaceAutomaton s = build_automaton(mesh, t, scheme, faces);
  const Patches P = patches(s, quad);
  SurfaceSample out;
  const auto count = static_cast<Eigen::Index>(at.size());
  out.positions.resize(count, d);
  out.du.resize(count, d);
  out.dv.resize(count, d);
  std::vector<Descent> descents(faces.size());
  Eigen::RowVectorXd ps(d), pt(d);
  for (Eigen::Index p = 0; p < count; ++p) {
    const FacePoint& q = at[static_cast<std::size_t>(p)];
    const auto f = static_cast<std::size_t>(entry[static_cast<std::size_t>(q.face)]);
    const int turn = corner_index(t, q.face, s.corners[f][0]);
    const auto [a, b] = patch_parameters(quad, turn, q.u, q.v);
    const automata::StateId first = s.automaton.initial[f].state;
    Descent& down = descents[f];
    if (P.regular[first] != 0) {
      if (down.own.size() == 0) down.own = regular_form(P, s.nets[f]);
      evaluate_regular(P, down.own, a, b, 1, out.positions.row(p).data(), ps.data(), pt.data());
    } else if (a == 0 && b == 0) {
      out.positions.row(p) = P.corner_point[first] * s.nets[f];
      ps.setZero();
      pt.setZero();
    } else {
      evaluate_extraordinary(P, s.nets[f], first, a, b, down, out.positions.row(p).data(), ps.data(),
                             pt.data());
    }
    face_partials(quad, turn, ps, pt, out.du.row(p), out.dv.row(p));
  }
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
Mesh triangle_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options) {
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
          if (row.size() == 0) row = fixed[k][state] * net;
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
  if (options.homogeneous)
    for (Eigen::Index v = 0; v < vertices.rows(); ++v) vertices.row(v) /= vertices(v, vertices.cols() - 1);
  Mesh out = uniform_mesh(std::move(vertices), std::move(corners), 3);
  out.states = std::move(states);
  return out;
}

}  // namespace

Mesh surface_automaton_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options) {
  if (!quads(surface.scheme)) return triangle_mesh(surface, depth, options);
  const Mesh blocks = ifs::patch_meshes(surface.automaton, surface.nets, depth, options);
  // Node (I, J) of face f's block is shared with its neighbours when it lies on the block's border:
  // a mesh vertex at a corner, else a point of a mesh edge, named by the edge's end vertices (lower
  // index first) and its distance from the lower one in cells. Each gets the first block's vertex.
  const int side = 1 << depth, row = side + 1, block = row * row;
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

FractalSurface fractal_catmull_clark(const SurfaceAutomaton& smooth, const ifs::PerturbOptions& options) {
  if (!quads(smooth.scheme))
    throw InvalidInput(
        "fractal subdivision surfaces: catmull-clark only (the BC-IFS of Loop's box spline is not built)");
  // The uniform bicubic patch: 4 × 4 control points, knots 0 … 7, one patch whose sides all lie on knot
  // lines.
  nurbs::Knots knots(8);
  for (std::size_t k = 0; k < knots.size(); ++k) knots[k] = static_cast<double>(k);
  const nurbs::Surface patch = nurbs::make_surface({3, 3}, {knots, knots}, {4, 4}, Points::Zero(16, 3));
  const nurbs::TensorAutomaton tensor = nurbs::tensor_automaton(patch);
  FractalSurface out;
  out.perturbation = ifs::perturb(ifs::surface_bcifs(tensor), options);
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
