// SPDX-License-Identifier: MIT
#include "cifs/ifs/fractal_fit.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/nurbs/knot_automaton.hpp"

namespace cifs::ifs {

namespace {

using automata::StateId;
using automata::TransitionId;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::RowVectorXd;

/// Where a data point lies on the attractor: the node of `word` (one child index per level) below the
/// initial entry, and its start — or, for the end of an open curve, its end.
struct Address {
  std::size_t initial = 0;
  std::vector<int> word;
  bool end = false;
};

/// The dyadic address of the domain parameter t: its segment, the binary digits of its position in the
/// segment rounded to 2^-depth (a position rounded up to the segment's end is the next segment's start).
Address address_of(double t, const nurbs::KnotAutomaton& knots, int depth, bool closed) {
  const auto& iv = knots.intervals;
  std::size_t s = 0;
  while (s + 1 < iv.size() && t >= iv[s].end) ++s;
  const double scale = std::ldexp(1.0, depth);
  const double x = std::clamp((t - iv[s].start) / (iv[s].end - iv[s].start), 0.0, 1.0);
  auto position = static_cast<std::uint64_t>(std::llround(x * scale));
  Address a;
  if (position == static_cast<std::uint64_t>(scale)) {
    if (s + 1 < iv.size() || closed) {
      s = (s + 1) % iv.size();
      position = 0;
    } else {
      a.initial = s;
      a.end = true;  // the curve's last point: the segment's end functional
      return a;
    }
  }
  a.initial = s;
  a.word.resize(static_cast<std::size_t>(depth));
  for (int k = 0; k < depth; ++k)
    a.word[static_cast<std::size_t>(k)] = static_cast<int>((position >> (depth - 1 - k)) & 1U);
  return a;
}

/// The fixed structure of the model: which matrix entry each unknown is, how the free coefficients move
/// it (K by rows), and the control points each segment's net selects.
struct Model {
  const Bcifs* system = nullptr;
  const AdmissibleSpace* space = nullptr;
  Eigen::SparseMatrix<double, Eigen::RowMajor> K;
  /// Per transition (TransitionId::index): its unknowns (indices into space->unknowns).
  std::vector<std::vector<Index>> unknowns_of;
  /// Per initial entry: the columns of the control points of its net's rows.
  std::vector<std::vector<Index>> columns;
  Index control_points = 0;
  Index free() const { return K.cols(); }
};

const MatrixXd& matrix(const Bcifs& s, StateId from, int child) {
  return s.automaton.graph[s.automaton.graph.out[from][static_cast<std::size_t>(child)]].matrix;
}

/// Adds ∂(x·T)/∂c_j to row j of `out` (nfree by cols(T)) for every free coefficient, T the matrix of
/// transition e and x a row (1 by rows(T)): Σ_u K(u, j)·x(row_u) at column col_u.
void add_left_derivative(const Model& m, TransitionId e, const RowVectorXd& x, MatrixXd& out) {
  for (const Index u : m.unknowns_of[e.index]) {
    const Coefficient& c = m.space->unknowns[static_cast<std::size_t>(u)];
    const double xr = x(c.row);
    if (xr == 0) continue;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.K, u); it; ++it)
      out(it.col(), c.col) += it.value() * xr;
  }
}

/// A vertex cell's functional ℓ (the point of its first-child chain) and ∂ℓ/∂c (nfree by size).
struct Functional {
  RowVectorXd value;
  MatrixXd d;
};

/// ℓ and ∂ℓ of vertex cell v and of every cell on its first-child chain, into `out` (memoised). On the
/// cycle the chain closes on, ℓ is the left fixed point of the cycle product P (ℓ·W = u, W = I − P + 1·u,
/// u uniform: invertible when 1 is a simple eigenvalue) and ∂ℓ solves ∂ℓ·W = ℓ·∂P; along the chain
/// ℓ_s = ℓ_next·M_s, ∂ℓ_s = ∂ℓ_next·M_s + ℓ_next·∂M_s.
void chain_functionals(const Model& m, const Bcifs& s, StateId v,
                       std::vector<std::optional<Functional>>& out) {
  const auto& g = s.automaton.graph;
  std::vector<StateId> path;
  std::vector<std::ptrdiff_t> pos(num_vertices(g), -1);
  StateId x = v;
  while (!out[x] && pos[x] < 0) {
    pos[x] = static_cast<std::ptrdiff_t>(path.size());
    path.push_back(x);
    x = target(g.out[x].front(), g);
  }
  const auto step = [&](std::size_t i, const Functional& next) {  // path[i] from its first child
    const StateId si = path[i];
    const MatrixXd& M = matrix(s, si, 0);
    Functional f{next.value * M, next.d * M};
    add_left_derivative(m, g.out[si].front(), next.value, f.d);
    out[si] = std::move(f);
  };
  std::size_t chain_end = path.size();  // path[chain_end] would be x
  if (!out[x]) {                        // the chain closes on a cycle path[q …]
    const auto q = static_cast<std::size_t>(pos[x]);
    const Index n = g[x].size;
    MatrixXd P = MatrixXd::Identity(n, n);
    std::vector<MatrixXd> prefix;  // M_{i−1}⋯M_q, size(path[i]) by n
    for (std::size_t i = q; i < path.size(); ++i) {
      prefix.push_back(P);
      P = (matrix(s, path[i], 0) * P).eval();
    }
    const RowVectorXd u = RowVectorXd::Constant(n, 1.0 / static_cast<double>(n));
    const MatrixXd W = MatrixXd::Identity(n, n) - P + Eigen::VectorXd::Ones(n) * u;
    const Eigen::PartialPivLU<MatrixXd> lu(W.transpose());  // solves ℓ·W = b as Wᵀ·ℓᵀ = bᵀ
    const double rcond = lu.rcond();
    if (!(rcond > 1e-13))
      throw InvalidInput("the vertex cell " + g[x].name +
                         " has no single fixed point (1 is not a simple eigenvalue)");
    const RowVectorXd value = lu.solve(u.transpose()).transpose();
    // ℓ on the cycle, backwards from path[q] = the cycle's end.
    std::vector<RowVectorXd> cycle(path.size() - q);
    RowVectorXd next = value;
    for (std::size_t i = path.size(); i-- > q;) {
      cycle[i - q] = next * matrix(s, path[i], 0);
      next = cycle[i - q];
    }
    MatrixXd rhs = MatrixXd::Zero(m.free(), n);
    for (std::size_t i = q; i < path.size(); ++i) {
      const RowVectorXd& after = i + 1 < path.size() ? cycle[i + 1 - q] : value;  // ℓ of path[i]'s child
      MatrixXd dM = MatrixXd::Zero(m.free(), g[path[i]].size);
      add_left_derivative(m, g.out[path[i]].front(), after, dM);
      rhs += dM * prefix[i - q];
    }
    out[x] = Functional{value, lu.solve(rhs.transpose()).transpose()};
    for (std::size_t i = path.size(); i-- > q + 1;)
      step(i, i + 1 < path.size() ? *out[path[i + 1]] : *out[x]);
    chain_end = q;
  }
  for (std::size_t i = chain_end; i-- > 0;) step(i, i + 1 < path.size() ? *out[path[i + 1]] : *out[x]);
}

/// Start and end functionals of the edge cells and their derivatives.
struct EdgeFunctionals {
  std::vector<Functional> start, end;  // per StateId (empty for other cells)
};

EdgeFunctionals edge_functionals(const Model& m, const Bcifs& s) {
  const auto n = num_vertices(s.automaton.graph);
  std::vector<std::optional<Functional>> vertex(n);
  EdgeFunctionals out;
  out.start.resize(n);
  out.end.resize(n);
  for (const BoundaryOperator& b : s.boundaries) {
    const bool start = b.name == "start";
    if ((!start && b.name != "end") || s.dimension[b.cell] != 1 || s.dimension[b.boundary] != 0) continue;
    if (!vertex[b.boundary]) chain_functionals(m, s, b.boundary, vertex);
    const Functional& f = *vertex[b.boundary];
    const Index size = s.automaton.graph[b.cell].size;
    Functional e{RowVectorXd::Zero(size), MatrixXd::Zero(m.free(), size)};
    for (std::size_t i = 0; i < b.rows.size(); ++i) {
      e.value(b.rows[i]) = f.value(static_cast<Index>(i));
      e.d.col(b.rows[i]) = f.d.col(static_cast<Index>(i));
    }
    (start ? out.start : out.end)[b.cell] = std::move(e);
  }
  return out;
}

const Functional& functional_of(const EdgeFunctionals& f, const Address& a, StateId cell) {
  return a.end ? f.end[cell] : f.start[cell];
}

/// A row of a cell's size: cells are at most degree + 1 ≤ 10 wide (make_model checks), so rows live on
/// the stack — the walks below run 30 levels per data point and allocated at every level before.
constexpr Index kMaxCell = 16;
using CellRow = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxCell>;

/// The walk down one address: its states, ℓ·T_L⋯T_{i+1} per level (`left`) and the nets N_i =
/// T_i⋯T_1·N_0 (`nets`, when asked). Walks of sorted addresses share their leading digits: the states and
/// nets above the first digit that differs from the previous walk's are kept, not recomputed.
struct Walk {
  std::size_t initial = std::numeric_limits<std::size_t>::max();
  std::vector<int> word;
  std::vector<StateId> states;
  std::vector<CellRow> left;
  std::vector<Points> nets;
  Index nets_valid = 0;  // nets[0 … nets_valid) are those of the current word
};

/// Moves `w` to address a; returns the first level whose state changed (levels above it are shared).
std::size_t walk_states(const Bcifs& s, const Address& a, Walk& w) {
  const auto& g = s.automaton.graph;
  std::size_t same = 0;
  if (w.initial == a.initial) {
    const std::size_t common = std::min(w.word.size(), a.word.size());
    while (same < common && w.word[same] == a.word[same]) ++same;
  } else {
    w.initial = a.initial;
    w.states.assign(1, s.automaton.initial[a.initial].state);
    w.nets_valid = 0;
  }
  w.word.assign(a.word.begin(), a.word.end());
  w.states.resize(same + 1);
  for (std::size_t i = same; i < a.word.size(); ++i)
    w.states.push_back(target(g.out[w.states.back()][static_cast<std::size_t>(a.word[i])], g));
  w.nets_valid = std::min<Index>(w.nets_valid, static_cast<Index>(same) + 1);
  return same;
}

/// The row a (1 by #control points) with A(ū) = a·P: ℓ·T_L⋯T_1 scattered onto the segment's columns
/// (`row` is overwritten). `w.left` receives ℓ·T_L⋯T_{i+1} for i = L … 1 (index i − 1).
void attractor_row(const Model& m, const Bcifs& s, const EdgeFunctionals& f, const Address& a, Walk& w,
                   Eigen::SparseVector<double>& row) {
  walk_states(s, a, w);
  CellRow x = functional_of(f, a, w.states.back()).value;
  w.left.resize(a.word.size());
  for (std::size_t i = a.word.size(); i-- > 0;) {
    w.left[i] = x;
    x.noalias() = w.left[i].lazyProduct(matrix(s, w.states[i], a.word[i]));  // tiny: no BLAS path
  }
  row.setZero();
  const auto& columns = m.columns[a.initial];
  for (std::size_t r = 0; r < columns.size(); ++r) row.coeffRef(columns[r]) += x(static_cast<Index>(r));
}

/// The attractor points a_k·P at the addresses.
Points attractor_points(const Model& m, const Bcifs& s, const EdgeFunctionals& f, const Points& P,
                        const std::vector<Address>& at) {
  Points out(static_cast<Index>(at.size()), P.cols());
  Walk w;
  Eigen::SparseVector<double> row(m.control_points);
  for (std::size_t k = 0; k < at.size(); ++k) {
    attractor_row(m, s, f, at[k], w, row);
    out.row(static_cast<Index>(k)) = row.transpose() * P;
  }
  return out;
}

/// One evaluation of the model at free coefficients c: the system, the rows of A, the least-squares
/// control points and the residual A·P − Q.
struct Evaluation {
  Bcifs system;
  EdgeFunctionals functionals;
  Eigen::SparseMatrix<double> A;
  std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>
      normal;  // AᵀA (the solver does not move)
  Points P, residual;
  double sum_squares = 0;
};

/// Least squares with the factored normal equations and one step of iterative refinement.
MatrixXd solve_least_squares(const Evaluation& e, const MatrixXd& b) {
  MatrixXd x = e.normal->solve(e.A.transpose() * b);
  x += e.normal->solve(e.A.transpose() * (b - e.A * x));
  return x;
}

std::optional<Evaluation> evaluate_model(const Model& m, const Eigen::VectorXd& c,
                                         const std::vector<Address>& at, const Points& data) {
  Evaluation e;
  e.system = with_free_values(*m.system, *m.space, c);
  try {
    e.functionals = edge_functionals(m, e.system);
  } catch (const InvalidInput&) {
    return std::nullopt;  // a vertex operator without a single fixed point: no attractor point there
  }
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(at.size() * m.columns.front().size());
  Walk w;
  Eigen::SparseVector<double> row(m.control_points);
  for (std::size_t k = 0; k < at.size(); ++k) {
    attractor_row(m, e.system, e.functionals, at[k], w, row);
    for (Eigen::SparseVector<double>::InnerIterator it(row); it; ++it)
      entries.emplace_back(static_cast<Index>(k), it.index(), it.value());
  }
  e.A.resize(static_cast<Index>(at.size()), m.control_points);
  e.A.setFromTriplets(entries.begin(), entries.end());
  e.normal = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(e.A.transpose() * e.A);
  if (e.normal->info() != Eigen::Success || (e.normal->vectorD().array() <= 0).any()) return std::nullopt;
  e.P = solve_least_squares(e, data);
  e.residual = e.A * e.P - data;
  e.sum_squares = e.residual.squaredNorm();
  if (!std::isfinite(e.sum_squares)) return std::nullopt;
  return e;
}

/// (∂A/∂c_j)·P for every free coefficient (#points·dim by nfree, row k·dim + d), exact: for each point
/// the derivative of ℓ·T_L⋯T_1·N_0 through ℓ and through every free matrix of its word (entry (r, s)
/// of T_i gets (ℓ·T_L⋯T_{i+1})_r times row s of the net N_{i−1}).
MatrixXd point_derivatives(const Model& m, const Bcifs& system, const EdgeFunctionals& functionals,
                           const Points& P, const std::vector<Address>& at) {
  const Index dim = P.cols();
  const auto rows = static_cast<Index>(at.size());
  MatrixXd J = MatrixXd::Zero(rows * dim, m.free());  // row k·dim + d
  const auto& g = system.automaton.graph;
  Walk w;
  Eigen::SparseVector<double> row(m.control_points);
  MatrixXd block(dim, m.free());
  for (std::size_t k = 0; k < at.size(); ++k) {
    const Address& a = at[k];
    attractor_row(m, system, functionals, a, w, row);
    const auto levels = static_cast<Index>(a.word.size());
    if (static_cast<Index>(w.nets.size()) < levels + 1) w.nets.resize(static_cast<std::size_t>(levels) + 1);
    if (w.nets_valid == 0) {
      const auto& columns = m.columns[a.initial];
      w.nets[0].resize(static_cast<Index>(columns.size()), dim);
      for (std::size_t r = 0; r < columns.size(); ++r)
        w.nets[0].row(static_cast<Index>(r)) = P.row(columns[r]);
      w.nets_valid = 1;
    }
    for (Index i = w.nets_valid - 1; i < levels; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      w.nets[iu + 1].noalias() = matrix(system, w.states[iu], a.word[iu]).lazyProduct(w.nets[iu]);
    }
    w.nets_valid = levels + 1;
    // dim by nfree, the transposed derivative: built contiguous, then copied into J's strided rows.
    block.noalias() =
        (functional_of(functionals, a, w.states.back()).d * w.nets[static_cast<std::size_t>(levels)])
            .transpose();
    for (std::size_t i = 0; i < a.word.size(); ++i) {
      const TransitionId t = g.out[w.states[i]][static_cast<std::size_t>(a.word[i])];
      for (const Index u : m.unknowns_of[t.index]) {
        const Coefficient& c = m.space->unknowns[static_cast<std::size_t>(u)];
        const double lr = w.left[i](c.row);
        if (lr == 0) continue;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.K, u); it; ++it)
          block.col(it.col()) += (it.value() * lr) * w.nets[i].row(c.col).transpose();
      }
    }
    J.middleRows(static_cast<Index>(k) * dim, dim) = block;
  }
  return J;
}

/// Kaufman's variable-projection Jacobian of the residual: point_derivatives with the range of A
/// projected out, column by column of the data's layout (k by dim per coefficient).
MatrixXd jacobian(const Model& m, const Evaluation& e, const std::vector<Address>& at) {
  MatrixXd J = point_derivatives(m, e.system, e.functionals, e.P, at);
  const Index dim = e.P.cols();
  const auto rows = static_cast<Index>(at.size());
  for (Index j = 0; j < m.free(); ++j) {
    const Points V = J.col(j).reshaped(dim, rows).transpose();
    const Points projected = V - e.A * solve_least_squares(e, V);
    J.col(j) = projected.transpose().reshaped();
  }
  return J;
}

double rms_of(const Points& residual) {
  return residual.rows() ? std::sqrt(residual.squaredNorm() / static_cast<double>(residual.rows())) : 0.0;
}

double max_of(const Points& residual) {
  return residual.rows() ? residual.rowwise().norm().maxCoeff() : 0.0;
}

/// −log2 |λ|/k for the largest eigenvalue λ ≠ 1 of the k-step cycle product of each vertex class.
std::vector<VertexHolder> vertex_holder(const Bcifs& s) {
  const auto& g = s.automaton.graph;
  std::vector<VertexHolder> out;
  std::vector<char> seen(num_vertices(g), 0);
  for (const BoundaryOperator& b : s.boundaries) {
    if (s.dimension[b.boundary] != 0 || seen[b.boundary]) continue;
    // Walk to the cycle of the first-child chain; report each class on it once.
    std::vector<std::ptrdiff_t> pos(num_vertices(g), -1);
    std::vector<StateId> path;
    StateId x = b.boundary;
    while (pos[x] < 0) {
      pos[x] = static_cast<std::ptrdiff_t>(path.size());
      path.push_back(x);
      x = target(g.out[x].front(), g);
    }
    for (const StateId p : path) seen[p] = 1;
    if (out.end() !=
        std::find_if(out.begin(), out.end(), [&](const VertexHolder& h) { return h.cell == g[x].name; }))
      continue;
    const Index n = g[x].size;
    MatrixXd P = MatrixXd::Identity(n, n);
    const auto q = static_cast<std::size_t>(pos[x]);
    for (std::size_t i = q; i < path.size(); ++i) P = (matrix(s, path[i], 0) * P).eval();
    const auto lambda = eigenvalues(P);  // sorted by modulus: the first is 1
    double sub = 0;
    for (std::size_t i = 1; i < lambda.size(); ++i) sub = std::max(sub, std::abs(lambda[i]));
    const auto steps = static_cast<double>(path.size() - q);
    out.push_back({g[x].name, sub > 0 ? std::min(1.0, -std::log2(sub) / steps) : 1.0});
  }
  return out;
}

/// Largest δ over the products of the paths of `length` transitions from every reachable state: nets
/// `length` levels down are at most this times as wide as their ancestor's, so pieces at depth k are
/// O(δ^(k/length)) wide and the attractor is Hölder continuous of exponent −log2(δ)/length.
double path_delta(const automata::Automaton& a, int length) {
  double worst = 0;
  const auto descend = [&](const auto& self, StateId s, const MatrixXd& P, int k) -> void {
    if (k == length) {
      worst = std::max(worst, delta(P));
      return;
    }
    for (const TransitionId e : a.graph.out[s])
      self(self, target(e, a.graph), (a.graph[e].matrix * P).eval(), k + 1);
  };
  for (const StateId s : reachable_states(a))
    descend(descend, s, MatrixXd::Identity(a.graph[s].size, a.graph[s].size), 0);
  return worst;
}

/// The proven Hölder exponent of path_delta at kHolderPaths levels (0 when the products do not shrink).
constexpr int kHolderPaths = 8;
double holder_bound(const automata::Automaton& a) {
  const double d = path_delta(a, kHolderPaths);
  return d < 1 ? -std::log2(d) / kHolderPaths : 0.0;
}

/// The model of a curve system: its unknowns by transition, K by rows, each segment's control points.
Model make_model(const nurbs::Curve& shape, const nurbs::KnotAutomaton& knots, const Bcifs& system,
                 const AdmissibleSpace& space) {
  Model m;
  m.system = &system;
  m.space = &space;
  m.K = space.K;
  m.control_points = nurbs::distinct_count(shape);
  for (StateId st = 0; st < num_vertices(system.automaton.graph); ++st)
    if (system.automaton.graph[st].size > kMaxCell)
      throw InvalidInput("fractal fit: cell " + system.automaton.graph[st].name + " has " +
                         std::to_string(system.automaton.graph[st].size) + " rows, more than the " +
                         std::to_string(kMaxCell) + " the fit's walks hold");
  m.unknowns_of.resize(num_edges(system.automaton.graph));
  for (std::size_t u = 0; u < space.unknowns.size(); ++u)
    m.unknowns_of[transition_id(system.automaton, space.unknowns[u].transition).index].push_back(
        static_cast<Index>(u));
  for (const nurbs::KnotInterval& iv : knots.intervals) {
    std::vector<Index> cols;
    for (int r = 0; r <= shape.degree; ++r) cols.push_back((iv.span - shape.degree + r) % m.control_points);
    m.columns.push_back(std::move(cols));
  }
  return m;
}

}  // namespace

FractalFit fit_fractal(const Points& points, const FractalFitOptions& o) {
  if (o.degree < 1 || o.degree > 9)
    throw InvalidInput("fractal fit: degree " + std::to_string(o.degree) + " is not in 1 … 9");
  if (o.depth < 1 || o.depth > 52)
    throw InvalidInput("fractal fit: depth " + std::to_string(o.depth) + " is not in 1 … 52");
  if (o.reparametrizations < 0)
    throw InvalidInput("fractal fit: reparametrizations " + std::to_string(o.reparametrizations) +
                       " is negative");
  if (o.max_iterations < 0)
    throw InvalidInput("fractal fit: max_iterations " + std::to_string(o.max_iterations) + " is negative");
  if (!(o.min_holder > 0) || !(o.min_holder <= 1))
    throw InvalidInput("fractal fit: min_holder " + number_text(o.min_holder) +
                       " is not in (0, 1] (the smallest Hölder exponent kept)");
  if (!(o.relative_decrease >= 0) || !std::isfinite(o.relative_decrease))
    throw InvalidInput("fractal fit: relative_decrease must be finite and ≥ 0");
  Points data = points;
  if (o.closed && data.rows() > 2 && data.row(0) == data.row(data.rows() - 1))
    data.conservativeResize(data.rows() - 1, Eigen::NoChange);
  const Index n = o.control_points;
  const Index smallest = o.closed ? std::max<Index>(3, o.degree + 1) : o.degree + 1;
  if (n < smallest || n > data.rows())
    throw InvalidInput("fractal fit: control_points " + std::to_string(n) + " is outside " +
                       std::to_string(smallest) + " … " + std::to_string(data.rows()) +
                       " (the number of points)");
  FractalFit fit;
  fit.parameters = nurbs::fit_parameters(data, o.parametrization, o.closed);  // validates the points

  // The model: the uniform B-spline of n control points, its BC-IFS and the admissible matrices.
  const nurbs::Curve shape = nurbs::uniform_bspline(Points::Zero(n, data.cols()), o.degree, o.closed);
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(shape);
  const Bcifs system = curve_bcifs(shape, {.free_vertices = o.free_vertices});
  const AdmissibleSpace space = admissible_space(system);
  const Model m = make_model(shape, knots, system, space);
  // The Jacobian (#points·dim by #free) is the largest array: refused before any work when above the limit.
  const double jacobian_bytes =
      static_cast<double>(data.size()) * static_cast<double>(m.free()) * sizeof(double);
  if (jacobian_bytes > static_cast<double>(o.max_bytes))
    throw InvalidInput("fractal fit: " + std::to_string(data.rows()) + " points and " +
                       std::to_string(m.free()) + " free coefficients need a Jacobian of " +
                       number_text(jacobian_bytes / 1e9, 3) + " GB, above the limit of " +
                       number_text(static_cast<double>(o.max_bytes) / 1e9, 3) + " GB; fit fewer points");
  const nurbs::Domain dom = nurbs::domain(shape);
  // The addresses of parameters in [0, 1] of the domain.
  const auto addresses = [&](std::span<const double> us) {
    std::vector<Address> out;
    out.reserve(us.size());
    for (const double u : us)
      out.push_back(address_of(dom.start + u * (dom.end - dom.start), knots, o.depth, o.closed));
    return out;
  };
  std::vector<Address> at = addresses(fit.parameters);
  std::vector<int> per_segment(knots.intervals.size(), 0);
  for (const Address& a : at) ++per_segment[a.initial];
  for (std::size_t s = 0; s < per_segment.size(); ++s)
    if (per_segment[s] == 0)
      throw InvalidInput("fractal fit: no data point falls in segment " + std::to_string(s) + " of " +
                         std::to_string(per_segment.size()) + "; use fewer control points");

  // The smooth start: at the NURBS values of the free coefficients the attractor is the B-spline.
  Eigen::VectorXd c = free_values(system, space);
  std::optional<Evaluation> current = evaluate_model(m, c, at, data);
  if (!current)
    throw InvalidInput("fractal fit: the least-squares B-spline is singular here; use fewer control points");
  fit.smooth = nurbs::uniform_bspline(current->P, o.degree, o.closed);
  fit.smooth_rms = rms_of(current->residual);
  fit.smooth_max_distance = max_of(current->residual);

  // Levenberg–Marquardt on c: a step is taken only if it lowers the sum of squares and keeps the proven
  // Hölder exponent at or above the floor (the attractor exists and stays a curve). Below `floor`, the
  // round-off level of the data, nothing is a better fit.
  const double floor =
      std::pow(1e-15 * std::max(nets_diameter(std::span<const Points>(&data, 1)), 1e-300), 2) *
      static_cast<double>(data.size());
  const double holder_floor = std::min(o.min_holder, holder_bound(current->system.automaton));
  double lambda = 1e-3;
  const auto descend = [&] {
    for (int it = 0; it < o.max_iterations && current->sum_squares > floor; ++it) {
      const MatrixXd J = jacobian(m, *current, at);
      const Eigen::VectorXd r = current->residual.transpose().reshaped();
      const MatrixXd H = J.transpose() * J;
      const Eigen::VectorXd gradient = J.transpose() * r;
      const Eigen::VectorXd scale = H.diagonal().cwiseMax(1e-12 * std::max(1.0, H.diagonal().maxCoeff()));
      bool accepted = false;
      while (lambda < 1e16) {
        MatrixXd system_matrix = H;
        system_matrix.diagonal() += lambda * scale;
        const Eigen::VectorXd step = -system_matrix.ldlt().solve(gradient);
        std::optional<Evaluation> next = evaluate_model(m, c + step, at, data);
        if (next && next->sum_squares < current->sum_squares &&
            holder_bound(next->system.automaton) >= holder_floor) {
          const double decrease = (current->sum_squares - next->sum_squares) / current->sum_squares;
          c += step;
          current = std::move(next);
          lambda = std::max(lambda / 3, 1e-12);
          accepted = decrease >= o.relative_decrease;
          break;
        }
        lambda *= 4;
      }
      ++fit.iterations;
      if (!accepted) break;
    }
  };
  descend();

  // Parameter correction (as Hoschek's for smooth curves): each inner data point moves to the closest
  // attractor point among the dyadic parameters strictly between its neighbours' (order kept), a grid 8×
  // finer than the data; the descent runs again. A round is kept only when it lowers the sum of squares.
  const auto segments = static_cast<Index>(knots.intervals.size());
  const int levels = std::clamp(static_cast<int>(std::ceil(std::log2(static_cast<double>(data.rows()) /
                                                                     static_cast<double>(segments)))) +
                                    3,
                                1, std::min(o.depth, 20));
  const Index grid = segments << levels;
  for (int round = 0; round < o.reparametrizations && current->sum_squares > floor && data.rows() > 2;
       ++round) {
    std::vector<double> grid_parameters(static_cast<std::size_t>(grid) + 1);
    for (Index g = 0; g <= grid; ++g)
      grid_parameters[static_cast<std::size_t>(g)] = static_cast<double>(g) / static_cast<double>(grid);
    const Points on_grid =
        attractor_points(m, current->system, current->functionals, current->P, addresses(grid_parameters));
    std::vector<double> moved = fit.parameters;
    for (Index k = 1; k + 1 < data.rows(); ++k) {
      const auto ks = static_cast<std::size_t>(k);
      double best = current->residual.row(k).squaredNorm();
      const auto first = static_cast<Index>(std::floor(moved[ks - 1] * static_cast<double>(grid))) + 1;
      const auto last = static_cast<Index>(std::ceil(fit.parameters[ks + 1] * static_cast<double>(grid))) - 1;
      for (Index g = first; g <= last; ++g) {
        const double d = (on_grid.row(g) - data.row(k)).squaredNorm();
        if (d < best) {
          best = d;
          moved[ks] = static_cast<double>(g) / static_cast<double>(grid);
        }
      }
    }
    std::vector<Address> at_moved = addresses(moved);
    std::optional<Evaluation> next = evaluate_model(m, c, at_moved, data);
    if (!next || !(next->sum_squares < current->sum_squares))
      break;  // a segment left without data, or no gain
    fit.parameters = std::move(moved);
    at = std::move(at_moved);
    current = std::move(next);
    ++fit.reparametrizations;
    descend();
  }

  fit.system = std::move(current->system);
  fit.control_points = current->P;
  const nurbs::Curve fitted = nurbs::uniform_bspline(current->P, o.degree, o.closed);
  fit.nets = nurbs::initial_nets(knots, fitted);
  const auto names = free_names(system, space);
  for (std::size_t j = 0; j < names.size(); ++j)
    fit.coefficients.emplace_back(names[j], c(static_cast<Index>(j)));
  fit.rms = rms_of(current->residual);
  fit.max_distance = max_of(current->residual);
  fit.contraction = contraction(fit.system.automaton);
  fit.holder_bound = holder_bound(fit.system.automaton);
  fit.holder = vertex_holder(fit.system);
  fit.dimension = fit.dimension_uncertainty = std::numeric_limits<double>::quiet_NaN();
  if (o.dimension_points > 0) {
    // Box counting on the attractor's points at the deepest depth within the budget. No resolution is
    // passed: a fitted system may contract slowly along some paths, so neither the proven piece bound
    // (tolerance samples) nor the nets' diameters size its pieces usefully; the fit's uncertainty (the
    // drift of the local slopes) says how well one power law holds instead.
    try {
      const DepthSample sample =
          depth_sample(fit.system.automaton, fit.nets, {.max_points = o.dimension_points});
      const BoxCountingResult box = box_counting(sample.points, {.min_boxes = 100});
      fit.dimension = box.dimension;
      fit.dimension_uncertainty = box.uncertainty;
    } catch (const InvalidInput& e) {
      fit.dimension_note = e.what();
    }
  } else {
    fit.dimension_note = "not measured";
  }
  return fit;
}

CurvePointDerivatives curve_point_derivatives(const nurbs::Curve& shape, const Bcifs& system,
                                              const AdmissibleSpace& space, const Eigen::VectorXd& c,
                                              std::span<const double> parameters, int depth) {
  if (shape.rational) throw InvalidInput("curve_point_derivatives: a rational shape (the fit's are not)");
  if (depth < 0 || depth > 52)
    throw InvalidInput("curve_point_derivatives: depth " + std::to_string(depth) + " is not in 0 … 52");
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(shape);
  if (system.automaton.initial.size() != knots.intervals.size())
    throw InvalidInput("curve_point_derivatives: the system is not the curve system of this shape");
  const Model m = make_model(shape, knots, system, space);
  const Bcifs current = with_free_values(system, space, c);
  const EdgeFunctionals functionals = edge_functionals(m, current);
  const Points P = nurbs::cartesian_points(shape);
  std::vector<Address> at;
  at.reserve(parameters.size());
  for (const double t : parameters)
    at.push_back(address_of(nurbs::domain_parameter(shape, t), knots, depth, shape.closed));
  CurvePointDerivatives out;
  out.points = attractor_points(m, current, functionals, P, at);
  const MatrixXd J = point_derivatives(m, current, functionals, P, at);
  for (Index j = 0; j < m.free(); ++j)
    out.derivatives.push_back(J.col(j).reshaped(P.cols(), static_cast<Index>(at.size())).transpose());
  return out;
}

}  // namespace cifs::ifs
