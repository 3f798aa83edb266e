// SPDX-License-Identifier: MIT
// cifs — the tangent plane of one sector at a vertex (sector_plane.hpp).
#include "sector_plane.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <stdexcept>

namespace cifs::subdivision::detail {

std::vector<Sector> sectors_around(const MeshTopology& t, const MeshTags& tags) {
  const auto edges = vertex_edges(t, 0);
  const auto faces = vertex_faces(t, 0);
  const auto m = static_cast<int>(faces.size());
  if (m == 0) return {};
  std::vector<char> sharp(edges.size(), 0);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const auto e = static_cast<std::size_t>(edges[k]);
    const int w = other_vertex(t, e, 0);
    sharp[k] =
        static_cast<char>(is_boundary_edge(t, e) ||
                          std::any_of(tags.creases.begin(), tags.creases.end(), [&](const EdgeSharpness& c) {
                            return c.sharpness > 0 && ((c.a == 0 && c.b == w) || (c.b == 0 && c.a == w));
                          }));
  }
  // Face k lies between edges k and k + 1 (cifs/topology.hpp); a boundary vertex's edges 0 and m are
  // its boundary edges.
  const bool boundary = t.boundary_vertex[0] != 0;
  const auto cuts = static_cast<int>(std::count(sharp.begin(), sharp.end(), 1));
  std::vector<Sector> out;
  if (!boundary && cuts <= 1) {  // smooth or a dart: every face, from the sharp edge if any
    const int start = static_cast<int>(std::find(sharp.begin(), sharp.end(), 1) - sharp.begin()) % m;
    Sector s;
    for (int i = 0; i < m; ++i) s.faces.push_back((start + i) % m);
    out.push_back(std::move(s));
    return out;
  }
  const int start = boundary ? 0 : static_cast<int>(std::find(sharp.begin(), sharp.end(), 1) - sharp.begin());
  for (int i = 0; i < m; ++i) {
    const int k = (start + i) % m;
    if (i == 0 || sharp[static_cast<std::size_t>(k)] != 0)
      out.push_back(Sector{.faces = {}, .bounded = true});
    out.back().faces.push_back(k);
  }
  return out;
}

SectorPlane sector_plane(const Eigen::MatrixXd& S, const MeshTopology& t, const Sector& sector) {
  SectorPlane out;
  const auto refuse = [&](const std::string& why) {
    out.refused = why;
    return out;
  };
  const auto edges = vertex_edges(t, 0);
  const auto faces = vertex_faces(t, 0);
  std::vector<int> rows{0};
  for (const int k : sector.faces)
    for (const int w : face(t, static_cast<std::size_t>(faces[static_cast<std::size_t>(k)])))
      if (std::find(rows.begin(), rows.end(), w) == rows.end()) rows.push_back(w);
  const auto N = static_cast<Eigen::Index>(rows.size());
  const auto row = [&](Eigen::Index i) { return rows[static_cast<std::size_t>(i)]; };
  if (N > 257) return refuse("a sector of more than 128 faces (the eigenproblem is not run there)");
  Eigen::MatrixXd A(N, N);
  for (Eigen::Index i = 0; i < N; ++i) {
    for (Eigen::Index j = 0; j < N; ++j) A(i, j) = S(row(i), row(j));
    if (std::abs(S.row(row(i)).cwiseAbs().sum() - A.row(i).cwiseAbs().sum()) > 1e-12)
      throw std::logic_error("limit: a sector's rows read outside it");
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(A, false);
  std::vector<std::complex<double>> values(eigen.eigenvalues().begin(), eigen.eigenvalues().end());
  std::sort(values.begin(), values.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
  constexpr double kTight = 1e-9;
  // Eigenvalues of a Jordan block split by about √ε (1e-8) in double: a gap or a pair closer than this
  // proves nothing (Catmull–Clark's boundary vertex of 4 faces, Loop's of 6: the curve's ½ and the inside's).
  constexpr double kGap = 1e-6;
  if (values.size() < 3 || std::abs(values[0] - 1.0) > kTight || std::abs(values[1]) >= 1 - kTight)
    return refuse("1 is not a simple eigenvalue of its sector");
  const std::complex<double> l1 = values[1], l2 = values[2];
  const double l3 = values.size() > 3 ? std::abs(values[3]) : 0.0;  // a ring of three: nothing below
  if (std::abs(l1.imag()) > kTight || std::abs(l2.imag()) > kTight || l2.real() <= l3 + kGap)
    return refuse("no pair of real subdominant eigenvalues above the rest in its sector");
  // The null space of B − λ when it has `dimension` dimensions; empty when λ is defective there (a
  // Jordan block: no pair of eigenvectors to span a plane).
  const auto null_space = [&](const Eigen::MatrixXd& B, double lambda, int dimension) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B - lambda * Eigen::MatrixXd::Identity(N, N),
                                                Eigen::ComputeFullV);
    const auto& sigma = svd.singularValues();
    if (sigma(N - dimension) > kTight * std::max(1.0, sigma(0))) return Eigen::MatrixXd();
    return Eigen::MatrixXd(svd.matrixV().rightCols(dimension));
  };
  const auto pair = [&](const Eigen::MatrixXd& B) {
    if (std::abs(l1.real() - l2.real()) < kTight) return null_space(B, l1.real(), 2);
    const Eigen::MatrixXd a = null_space(B, l1.real(), 1), b = null_space(B, l2.real(), 1);
    if (a.size() == 0 || b.size() == 0) return Eigen::MatrixXd();
    Eigen::MatrixXd both(N, 2);
    both << a, b;
    return both;
  };
  Eigen::MatrixXd right = pair(A);
  const Eigen::MatrixXd left = pair(A.transpose());
  if (right.size() == 0 || left.size() == 0) return refuse("its subdominant eigenvalue is defective");
  const Eigen::Matrix2d gram = left.transpose() * right;
  if (std::abs(gram.determinant()) <= kGap) return refuse("its subdominant eigenvectors are degenerate");
  Eigen::MatrixXd dual = left * gram.inverse().transpose();  // dualᵀ right = I
  const auto at = [&](int vertex) {
    return Eigen::RowVector2d(right.row(std::find(rows.begin(), rows.end(), vertex) - rows.begin()));
  };
  const auto across = [&](std::size_t k) {  // the other end of edge k around the vertex
    return other_vertex(t, static_cast<std::size_t>(edges[k % edges.size()]), 0);
  };
  const auto first = static_cast<std::size_t>(sector.faces.front()),
             last = static_cast<std::size_t>(sector.faces.back());
  if (sector.bounded && at(across(first)).norm() <= kTight * right.norm() &&
      at(across(last + 1)).norm() <= kTight * right.norm())
    return refuse("the curves bounding its sector leave the plane of its subdominant eigenvectors (not C¹)");
  // Orientation: near the vertex a face's edges are r(a) and r(b) in the frame (l_1 · x, l_2 · x), a the
  // corner after the vertex (edge k), b the one before (edge k + 1); counter-clockwise faces turn from a
  // to b, so the determinants, summed over the sector, must be positive.
  double turn = 0, scale = 0;
  for (const int k : sector.faces) {
    const Eigen::RowVector2d a = at(across(static_cast<std::size_t>(k))),
                             b = at(across(static_cast<std::size_t>(k) + 1));
    turn += a.x() * b.y() - a.y() * b.x();
    scale += a.norm() * b.norm();
  }
  if (!(std::abs(turn) > kTight * scale)) return refuse("its faces' edges span no plane in the pair's");
  if (turn < 0) {
    right.col(1) *= -1;
    dual.col(1) *= -1;
  }
  out.lambda = {l1.real(), l2.real()};
  out.left = Eigen::MatrixXd::Zero(2, S.cols());
  out.right = Eigen::MatrixXd::Zero(S.rows(), 2);
  for (Eigen::Index i = 0; i < N; ++i) {
    out.left.col(row(i)) = dual.row(i).transpose();
    out.right.row(row(i)) = right.row(i);
  }
  return out;
}

}  // namespace cifs::subdivision::detail
