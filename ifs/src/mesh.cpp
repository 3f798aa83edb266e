// SPDX-License-Identifier: MIT
// cifs — quad meshes of surface attractors: separable (tensor-product) and generic routes.
#include "cifs/ifs/mesh.hpp"

#include <algorithm>
#include <climits>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/memory.hpp"
#include "walk.hpp"

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

namespace {

constexpr std::size_t kSaturated = std::numeric_limits<std::size_t>::max();

std::size_t mul_sat(std::size_t a, std::size_t b) noexcept {
  return (a != 0 && b > kSaturated / a) ? kSaturated : a * b;
}

/// The global node grid of A × B patches at depth K: cells (A·2^K) × (B·2^K), nodes one more each way.
struct Grid {
  int A = 0, B = 0, depth = 0;
  int cu = 0, cv = 0;  // cells along u and v
  int side = 0;        // 2^K: cells per patch and direction
  std::size_t vertices = 0, quads = 0;
};

/// Refuses (before any work) a mesh above the byte limit or beyond int indices; `what` says what
/// the depth is applied to.
void check_size(std::size_t vertices, std::size_t quads, std::size_t cols, int depth, const std::string& what,
                const MeshOptions& options) {
  const std::size_t bytes = mesh_bytes(vertices, cols, quads);
  if (bytes <= options.max_bytes && vertices <= static_cast<std::size_t>(INT_MAX)) return;
  std::ostringstream msg;
  // The message names the depth the user gave, not this routine.
  msg << "depth " << depth << " on " << what << " gives ";
  if (vertices == kSaturated) {
    msg << "more than 2^64 vertices";
  } else {
    msg << vertices << " vertices of " << cols << " coordinates and " << quads << " quads ("
        << static_cast<double>(bytes) / static_cast<double>(std::size_t{1} << 30) << " GiB)";
    if (vertices > static_cast<std::size_t>(INT_MAX))
      msg << ", more than the 2^31 − 1 vertices a mesh addresses";
    else
      msg << ", more than the limit of "
          << static_cast<double>(options.max_bytes) / static_cast<double>(std::size_t{1} << 30)
          << " GiB held in memory";
  }
  msg << "; lower the depth";
  throw InvalidInput(msg.str());
}

std::size_t cells(int patches, int depth) {
  return depth > 30 ? kSaturated : mul_sat(static_cast<std::size_t>(patches), std::size_t{1} << depth);
}

/// Checks the depth and the sizes, and refuses a mesh above the byte limit before any work.
Grid make_grid(int A, int B, int depth, std::size_t cols, const MeshOptions& options,
               const std::string& who) {
  if (depth < 0) throw InvalidInput(who + ": depth is " + std::to_string(depth) + ", must be ≥ 0");
  const std::size_t cu = cells(A, depth), cv = cells(B, depth);
  const std::size_t vertices = mul_sat(cu + (cu < kSaturated), cv + (cv < kSaturated));
  check_size(vertices, mul_sat(cu, cv), cols, depth,
             std::to_string(A) + " by " + std::to_string(B) + " patches", options);
  return Grid{A, B, depth, static_cast<int>(cu), static_cast<int>(cv), 1 << depth, vertices, mul_sat(cu, cv)};
}

/// Vertices allocated (not set), quads in cell order (I, J) → I·cv + J, corners counter-clockwise in
/// (u, v). The quads are appended a row at a time from one row of cells shifted by a vertex row
/// each time: one pass over the output, never zeroed first (16 of the 20 connectivity bytes a cell).
/// The routes fill quad_state themselves.
/// The storage of `mesh` is reused when it is large enough (no page faults when a caller meshes
/// into the same object again).
void allocate(const Grid& grid, Eigen::Index cols, QuadMesh& mesh) {
  resize_huge(mesh.vertices, static_cast<Eigen::Index>(grid.vertices), cols);
  mesh.quads.clear();
  reserve_huge(mesh.quads, grid.quads);
  const int row = grid.cv + 1;
  std::vector<std::array<int, 4>> line(static_cast<std::size_t>(grid.cv));
  for (int J = 0; J < grid.cv; ++J) line[static_cast<std::size_t>(J)] = {J, row + J, row + J + 1, J + 1};
  for (int I = 0; I < grid.cu; ++I) {
    mesh.quads.insert(mesh.quads.end(), line.begin(), line.end());
    for (auto& quad : line)
      for (int& v : quad) v += row;
  }
}

void finish(QuadMesh& mesh, const MeshOptions& options) {
  if (options.homogeneous) mesh.vertices = cartesian(mesh.vertices);
}

/// States of the depth-K nodes of a (binary or any) automaton in order: initial entries in order,
/// children in out-edge order. States only: no nets are computed.
std::vector<StateId> leaf_states(const Automaton& automaton, int depth) {
  const Graph& g = automaton.graph;
  std::vector<StateId> out;
  std::vector<std::pair<StateId, int>> stack;
  for (const automata::Initial& init : automaton.initial) {
    stack.emplace_back(init.state, 0);
    while (!stack.empty()) {
      const auto [s, d] = stack.back();
      stack.pop_back();
      if (d == depth) {
        out.push_back(s);
        continue;
      }
      // Pushed in reverse so that the first child is visited first.
      const auto [b, e] = boost::out_edges(s, g);
      std::vector<StateId> children;
      for (auto it = b; it != e; ++it) children.push_back(boost::target(*it, g));
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.emplace_back(*it, d + 1);
    }
  }
  return out;
}

/// Nodes [first, first + side) of a patch along one direction, plus the far node for the last patch.
int owned(const Grid& grid, int patch, int patches) {
  return grid.side + (patch + 1 == patches ? 1 : 0);
}

/// One vertex row of the separable route: out[e] = Σ_k f[k]·Y[k·n + e] for e < n, summed in k order.
/// P1 > 0 fixes p + 1 so that the k sum unrolls and the e loop vectorises; 0 reads p1 at run time.
template <int P1>
void combine_rows(const double* f, Eigen::Index p1, const double* __restrict Y, Eigen::Index n,
                  double* __restrict out) noexcept {
  if constexpr (P1 > 0) p1 = P1;
  for (Eigen::Index e = 0; e < n; ++e) {
    double acc = f[0] * Y[e];
    for (Eigen::Index k = 1; k < p1; ++k) acc += f[k] * Y[k * n + e];
    out[e] = acc;
  }
}

using RowKernel = void (*)(const double*, Eigen::Index, const double*, Eigen::Index, double*) noexcept;

RowKernel row_kernel(Eigen::Index p1) noexcept {
  switch (p1) {
    case 2:
      return combine_rows<2>;
    case 3:
      return combine_rows<3>;
    case 4:
      return combine_rows<4>;
    case 5:
      return combine_rows<5>;
    case 6:
      return combine_rows<6>;
    default:
      return combine_rows<0>;
  }
}

}  // namespace

Mesh to_mesh(QuadMesh quad_mesh) {
  std::vector<int> corners;
  corners.reserve(4 * quad_mesh.quads.size());
  for (const auto& q : quad_mesh.quads) corners.insert(corners.end(), q.begin(), q.end());
  quad_mesh.quads = {};  // freed before the offsets are allocated
  Mesh mesh = uniform_mesh(std::move(quad_mesh.vertices), std::move(corners), 4);
  mesh.states = std::move(quad_mesh.quad_state);
  return mesh;
}

std::size_t mesh_bytes(std::size_t vertices, std::size_t cols, std::size_t quads) noexcept {
  const std::size_t v = mul_sat(mul_sat(vertices, cols), sizeof(double));
  const std::size_t q = mul_sat(quads, sizeof(std::array<int, 4>) + sizeof(std::uint32_t));
  return v > kSaturated - q ? kSaturated : v + q;
}

void surface_mesh(const nurbs::TensorAutomaton& t, std::span<const Points> nets, int depth, QuadMesh& mesh,
                  const MeshOptions& options) {
  // The route reads the factors and the state pairs, never the product's matrices: validating the
  // product (every 16 by 16 matrix of a bicubic surface) costs as much as a depth-8 mesh's quads.
  for (const auto& f : t.factors) validate(f.automaton);
  check_nets(t.product, nets, "surface_mesh");
  if (t.factor_states.size() != boost::num_vertices(t.product.graph))
    throw InvalidInput("surface_mesh: " + std::to_string(t.factor_states.size()) +
                       " factor state pairs for " + std::to_string(boost::num_vertices(t.product.graph)) +
                       " product states");
  for (StateId s = 0; s < t.factor_states.size(); ++s)
    for (std::size_t dir = 0; dir < 2; ++dir)
      if (t.factor_states[s][dir] >= boost::num_vertices(t.factors[dir].automaton.graph))
        throw InvalidInput("surface_mesh: product state " + std::to_string(s) + " names factor state " +
                           std::to_string(t.factor_states[s][dir]) + " of direction " + std::to_string(dir) +
                           ", which does not exist");
  const int A = static_cast<int>(t.factors[0].automaton.initial.size()),
            B = static_cast<int>(t.factors[1].automaton.initial.size());
  if (t.patches.size() != t.product.initial.size() || t.patches.size() != static_cast<std::size_t>(A) * B)
    throw InvalidInput("surface_mesh: the automaton has " + std::to_string(t.patches.size()) +
                       " patches for " + std::to_string(t.product.initial.size()) + " initial entries and " +
                       std::to_string(A) + " by " + std::to_string(B) + " factor segments");
  for (std::size_t k = 0; k < t.patches.size(); ++k)
    if (t.patches[k] != std::array<int, 2>{static_cast<int>(k) / B, static_cast<int>(k) % B})
      throw InvalidInput("surface_mesh: patch " + std::to_string(k) + " is not in u-major order");
  const Eigen::Index C = nets[0].cols();
  if (options.homogeneous && C < 2)
    throw InvalidInput("surface_mesh: homogeneous rows need at least 2 columns (w·x, w), got " +
                       std::to_string(C));
  const Grid grid = make_grid(A, B, depth, static_cast<std::size_t>(C), options, "surface_mesh");

  // Curve stencil tables: row I of F[dir] is the functional, on the net of the segment owning
  // node I, of the point at node I — the factor's attractor under identity nets.
  std::array<Points, 2> F;
  std::array<std::vector<StateId>, 2> leaves;
  for (std::size_t dir = 0; dir < 2; ++dir) {
    const Automaton& f = t.factors[dir].automaton;
    std::vector<Points> identity;
    for (const auto& init : f.initial)
      identity.push_back(Points::Identity(f.graph[init.state].size, f.graph[init.state].size));
    F[dir] = attractor_points(
        f, identity, depth,
        PointsOptions{.closed = false, .max_bytes = options.max_bytes, .max_table_depth = 8});
    leaves[dir] = leaf_states(f, depth);
  }
  const Eigen::Index p1 = F[0].cols(), q1 = F[1].cols();
  if (nets[0].rows() != p1 * q1)
    throw InvalidInput("surface_mesh: nets of " + std::to_string(nets[0].rows()) +
                       " rows, the factors give " + std::to_string(p1) + " by " + std::to_string(q1));
  // Homogeneous rows are divided by w a vertex row at a time, straight into the output: no whole
  // homogeneous mesh, and no second allocation of the vertices.
  const Eigen::Index D = options.homogeneous ? C - 1 : C;
  allocate(grid, D, mesh);

  // v pass once per patch row a: Y_k (k ≤ p) is row k of every patch net of the row taken along v
  // at the nodes the patch owns, i.e. Y_k(J) = Σ_l F_v(J, l)·N_b(k·(q+1) + l) — a `cv + 1 by C`
  // vertex row, stored contiguously. Each vertex row I of the patch row is then the (p + 1)-term
  // combination Σ_k F_u(I, k)·Y_k over one contiguous run of (cv + 1)·C doubles.
  const Eigen::Index width = static_cast<Eigen::Index>(grid.cv + 1) * C;
  std::vector<double> Y(static_cast<std::size_t>(p1 * width));
  std::vector<double> H(options.homogeneous ? static_cast<std::size_t>(width) : 0);  // one homogeneous row
  const RowKernel combine = row_kernel(p1);
  for (int a = 0; a < A; ++a) {
    for (int b = 0; b < B; ++b) {
      const Points& N = nets[static_cast<std::size_t>(a) * B + b];
      const int J0 = b * grid.side, cols = owned(grid, b, B);
      for (Eigen::Index k = 0; k < p1; ++k)
        for (int J = J0; J < J0 + cols; ++J) {
          const double* f = F[1].data() + static_cast<Eigen::Index>(J) * q1;
          double* y = Y.data() + k * width + static_cast<Eigen::Index>(J) * C;
          for (Eigen::Index c = 0; c < C; ++c) {
            double acc = f[0] * N(k * q1, c);
            for (Eigen::Index l = 1; l < q1; ++l) acc += f[l] * N(k * q1 + l, c);
            y[c] = acc;
          }
        }
    }
    for (int I = a * grid.side, end = I + owned(grid, a, A); I < end; ++I) {
      const double* f = F[0].data() + static_cast<Eigen::Index>(I) * p1;
      double* row = mesh.vertices.data() + static_cast<Eigen::Index>(I) * (grid.cv + 1) * D;
      if (!options.homogeneous) {
        combine(f, p1, Y.data(), width, row);
        continue;
      }
      combine(f, p1, Y.data(), width, H.data());
      for (int J = 0; J <= grid.cv; ++J, row += D) {
        const double* h = H.data() + static_cast<Eigen::Index>(J) * C;
        const double w = h[D];
        if (w == 0)
          throw InvalidInput("surface_mesh: vertex " +
                             std::to_string(static_cast<std::size_t>(I) * (grid.cv + 1) + J) +
                             " has weight 0 (a point at infinity)");
        for (Eigen::Index c = 0; c < D; ++c) row[c] = h[c] / w;  // as cartesian(): the same bits
      }
    }
  }

  // Leaf states: the product state of the pair of factor leaf states. Rows I with the same u leaf
  // state are equal, so each distinct row is built once and copied.
  const auto nv_states = boost::num_vertices(t.factors[1].automaton.graph);
  std::vector<std::uint32_t> pair_id(boost::num_vertices(t.factors[0].automaton.graph) * nv_states, 0);
  for (StateId s = 0; s < t.factor_states.size(); ++s)
    pair_id[t.factor_states[s][0] * nv_states + t.factor_states[s][1]] = static_cast<std::uint32_t>(s);
  std::vector<std::vector<std::uint32_t>> state_row(boost::num_vertices(t.factors[0].automaton.graph));
  mesh.quad_state.clear();
  reserve_huge(mesh.quad_state, grid.quads);
  for (int I = 0; I < grid.cu; ++I) {
    const StateId su = leaves[0][static_cast<std::size_t>(I)];
    std::vector<std::uint32_t>& states = state_row[su];
    if (states.empty()) {
      states.resize(static_cast<std::size_t>(grid.cv));
      for (std::size_t J = 0; J < states.size(); ++J) states[J] = pair_id[su * nv_states + leaves[1][J]];
    }
    mesh.quad_state.insert(mesh.quad_state.end(), states.begin(), states.end());
  }
}

QuadMesh surface_mesh(const nurbs::TensorAutomaton& automaton, std::span<const Points> nets, int depth,
                      const MeshOptions& options) {
  QuadMesh mesh;
  surface_mesh(automaton, nets, depth, mesh, options);
  return mesh;
}

namespace {

/// Where the generic route writes a patch: node (I, J) of the patch is vertex `vertex + I·row + J`,
/// cell (I, J) quad `quad + I·quad_row + J`; the patch's last node row (column) is its own when
/// its cells end at `close_u` (`close_v`), otherwise the next patch's first.
struct Placement {
  std::size_t vertex = 0, quad = 0;
  int row = 0, quad_row = 0, close_u = 0, close_v = 0;
};

/// Stencil tables of the generic route: per state, the (2^L + 1)² node functionals (row
/// i·(2^L + 1) + j for node (i, j) of the state's square, owned by the child min(i / h, 1),
/// min(j / h, 1), h = 2^(L−1), like the global nodes by their leaves; level 0 holds the corner
/// functionals) and the states of its 4^L leaves.
struct NodeTables {
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  int depth = 0;
  std::vector<RowMatrix> table;
  std::vector<std::vector<std::uint32_t>> leaf;
};

/// Checks that every reachable state has four children.
std::vector<StateId> surface_states(const Automaton& automaton, std::span<const Points> nets,
                                    const std::string& who) {
  validate(automaton);
  check_nets(automaton, nets, who);
  const Graph& g = automaton.graph;
  auto states = reachable_states(automaton);
  for (const StateId s : states)
    if (boost::out_degree(s, g) != 4)
      throw InvalidInput(who + ": " + detail::state_label(automaton, s) + " has " +
                         std::to_string(boost::out_degree(s, g)) +
                         " children, a surface state needs 4 (GH, GB, DH, DB)");
  return states;
}

/// The tables of depth L ≤ `max_depth`, lowered until they (and, while building, the previous
/// level) stay below half of an output of `output_doubles`.
NodeTables node_tables(const Automaton& automaton, std::span<const StateId> states, int max_depth,
                       std::size_t output_doubles) {
  const Graph& g = automaton.graph;
  const auto table_size = [&](int L) {
    const std::size_t m = (std::size_t{1} << L) + 1;
    std::size_t total = 0;
    for (const StateId s : states) total += m * m * static_cast<std::size_t>(g[s].size);
    return total;
  };
  int L = std::max(max_depth, 0);
  while (L > 0 && table_size(L) + table_size(L - 1) > output_doubles / 2) --L;
  const auto n = boost::num_vertices(g);
  NodeTables out{.depth = L,
                 .table = std::vector<NodeTables::RowMatrix>(n),
                 .leaf = std::vector<std::vector<std::uint32_t>>(n)};
  auto& table = out.table;
  auto& leaf = out.leaf;
  std::vector<NodeTables::RowMatrix> next(n);
  std::vector<std::vector<std::uint32_t>> next_leaf(n);
  {
    std::array<std::vector<Eigen::RowVectorXd>, 4> corner;
    for (int k = 0; k < 4; ++k)
      corner[static_cast<std::size_t>(k)] = repeated_child_functionals(automaton, k);
    for (const StateId s : states) {
      table[s].resize(4, g[s].size);
      for (std::size_t k = 0; k < 4; ++k) table[s].row(static_cast<Eigen::Index>(k)) = corner[k][s];
      leaf[s] = {static_cast<std::uint32_t>(s)};
    }
  }
  for (int l = 1; l <= L; ++l) {
    const int h = 1 << (l - 1), m = 2 * h + 1;
    for (const StateId s : states) {
      NodeTables::RowMatrix& T = next[s];
      T.resize(Eigen::Index{m} * m, g[s].size);
      std::vector<std::uint32_t>& S = next_leaf[s];
      S.assign(4 * static_cast<std::size_t>(h) * static_cast<std::size_t>(h), 0);
      int c = 0;
      for (auto [e, end] = boost::out_edges(s, g); e != end; ++e, ++c) {
        const StateId child = boost::target(*e, g);
        const NodeTables::RowMatrix P =
            table[child] * g[*e].matrix;  // (h+1)² functionals on the parent's net
        const int iu = c / 2, iv = c % 2;
        for (int i = 0; i <= h; ++i)
          for (int j = 0; j <= h; ++j) {
            const int I = iu * h + i, J = iv * h + j;
            if (std::min(I / h, 1) == iu && std::min(J / h, 1) == iv)
              T.row(I * m + J) = P.row(i * (h + 1) + j);
            if (i < h && j < h)
              S[static_cast<std::size_t>(I) * 2 * static_cast<std::size_t>(h) + static_cast<std::size_t>(J)] =
                  leaf[child][static_cast<std::size_t>(i) * static_cast<std::size_t>(h) +
                              static_cast<std::size_t>(j)];
          }
      }
    }
    std::swap(table, next);
    std::swap(leaf, next_leaf);
  }
  return out;
}

/// Walks to depth K − L; each node writes the nodes it owns and the states of its 4^L leaves,
/// where `place(i)` puts initial entry i.
template <class Place>
void emit_patches(const Automaton& automaton, std::span<const Points> nets, int depth,
                  const NodeTables& tables, QuadMesh& mesh, const Place& place) {
  const int L = tables.depth, side_L = 1 << L, m = side_L + 1;
  const Eigen::Index C = mesh.vertices.cols();
  detail::depth_first(
      automaton, nets, depth - L,
      [&](std::size_t i, StateId s, const Points& net, int d, std::span<const int> word) {
        if (d < depth - L) return true;
        const Placement p = place(i);
        int I0 = 0, J0 = 0;
        for (int k = 0; k < d; ++k) {
          I0 += (word[static_cast<std::size_t>(k)] / 2) << (depth - 1 - k);
          J0 += (word[static_cast<std::size_t>(k)] % 2) << (depth - 1 - k);
        }
        const int rows = side_L + (I0 + side_L == p.close_u ? 1 : 0);
        const int cols = side_L + (J0 + side_L == p.close_v ? 1 : 0);
        const Eigen::Index size = automaton.graph[s].size;
        for (int r = 0; r < rows; ++r)
          detail::emit(
              tables.table[s].data() + static_cast<Eigen::Index>(r) * m * size, cols, size, net,
              mesh.vertices.data() +
                  (static_cast<Eigen::Index>(p.vertex) + static_cast<Eigen::Index>(I0 + r) * p.row + J0) * C);
        for (int r = 0; r < side_L; ++r)
          std::copy_n(tables.leaf[s].begin() + static_cast<std::ptrdiff_t>(r) * side_L, side_L,
                      mesh.quad_state.begin() + static_cast<std::ptrdiff_t>(p.quad) +
                          static_cast<std::ptrdiff_t>(I0 + r) * p.quad_row + J0);
        return false;
      });
}

}  // namespace

QuadMesh quad_mesh(const Automaton& automaton, std::span<const Points> nets,
                   std::span<const std::array<int, 2>> patches, int depth, const MeshOptions& options) {
  const auto states = surface_states(automaton, nets, "quad_mesh");
  if (patches.size() != automaton.initial.size())
    throw InvalidInput("quad_mesh: " + std::to_string(patches.size()) + " patches for " +
                       std::to_string(automaton.initial.size()) + " initial entries");
  int A = 0, B = 0;
  for (const auto& [a, b] : patches) {
    if (a < 0 || b < 0)
      throw InvalidInput("quad_mesh: patch (" + std::to_string(a) + ", " + std::to_string(b) +
                         ") is negative");
    A = std::max(A, a + 1);
    B = std::max(B, b + 1);
  }
  std::vector<int> patch_at(static_cast<std::size_t>(A) * B, -1);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    int& slot = patch_at[static_cast<std::size_t>(patches[i][0]) * B + patches[i][1]];
    if (slot >= 0)
      throw InvalidInput("quad_mesh: initial entries " + std::to_string(slot) + " and " + std::to_string(i) +
                         " are both placed at patch (" + std::to_string(patches[i][0]) + ", " +
                         std::to_string(patches[i][1]) + ")");
    slot = static_cast<int>(i);
  }
  if (patches.size() != patch_at.size())
    throw InvalidInput("quad_mesh: " + std::to_string(patches.size()) + " patches do not fill their " +
                       std::to_string(A) + " by " + std::to_string(B) + " grid");
  const Eigen::Index C = nets[0].cols();
  const Grid grid = make_grid(A, B, depth, static_cast<std::size_t>(C), options, "quad_mesh");
  const NodeTables tables = node_tables(automaton, states, std::min(options.max_table_depth, depth),
                                        grid.vertices * static_cast<std::size_t>(C));
  QuadMesh mesh;
  allocate(grid, C, mesh);
  assign_huge(mesh.quad_state, grid.quads, std::uint32_t{0});  // written block by block, out of order
  const int row = grid.cv + 1;
  emit_patches(automaton, nets, depth, tables, mesh, [&](std::size_t i) {
    const int I = patches[i][0] * grid.side, J = patches[i][1] * grid.side;
    return Placement{
        .vertex = static_cast<std::size_t>(I) * static_cast<std::size_t>(row) + static_cast<std::size_t>(J),
        .quad = static_cast<std::size_t>(I) * static_cast<std::size_t>(grid.cv) + static_cast<std::size_t>(J),
        .row = row,
        .quad_row = grid.cv,
        .close_u = grid.cu - I,
        .close_v = grid.cv - J};
  });
  finish(mesh, options);
  return mesh;
}

QuadMesh patch_meshes(const Automaton& automaton, std::span<const Points> nets, int depth,
                      const MeshOptions& options) {
  const auto states = surface_states(automaton, nets, "patch_meshes");
  if (depth < 0) throw InvalidInput("patch_meshes: depth is " + std::to_string(depth) + ", must be ≥ 0");
  const auto F = static_cast<int>(automaton.initial.size());
  const std::size_t side = cells(1, depth),
                    nodes = side < kSaturated ? mul_sat(side + 1, side + 1) : kSaturated;
  const Eigen::Index C = nets.empty() ? 0 : nets[0].cols();
  check_size(mul_sat(nodes, static_cast<std::size_t>(F)),
             mul_sat(mul_sat(side, side), static_cast<std::size_t>(F)), static_cast<std::size_t>(C), depth,
             std::to_string(F) + " patches", options);
  const int s = 1 << depth, block = (s + 1) * (s + 1);
  QuadMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(F) * block, C);
  advise_huge_pages(mesh.vertices.data(), static_cast<std::size_t>(mesh.vertices.size()) * sizeof(double));
  reserve_huge(mesh.quads,
               static_cast<std::size_t>(F) * static_cast<std::size_t>(s) * static_cast<std::size_t>(s));
  for (int i = 0; i < F; ++i)
    for (int I = 0; I < s; ++I)
      for (int J = 0; J < s; ++J) {
        const int v = i * block + I * (s + 1) + J;
        mesh.quads.push_back({v, v + s + 1, v + s + 2, v + 1});
      }
  assign_huge(mesh.quad_state, mesh.quads.size(), std::uint32_t{0});
  const NodeTables tables = node_tables(automaton, states, std::min(options.max_table_depth, depth),
                                        static_cast<std::size_t>(mesh.vertices.size()));
  emit_patches(automaton, nets, depth, tables, mesh, [&](std::size_t i) {
    return Placement{.vertex = i * static_cast<std::size_t>(block),
                     .quad = i * static_cast<std::size_t>(s) * static_cast<std::size_t>(s),
                     .row = s + 1,
                     .quad_row = s,
                     .close_u = s,
                     .close_v = s};
  });
  finish(mesh, options);
  return mesh;
}

}  // namespace cifs::ifs
