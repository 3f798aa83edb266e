// SPDX-License-Identifier: MIT
// cifs — quad meshes of surface attractors: separable (tensor-product) and generic routes.
#include "cifs/ifs/mesh.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/memory.hpp"
#include "cifs/row_combination.hpp"
#include "saturating.hpp"
#include "walk.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

namespace {

/// The global node grid of A × B patches at depth K: cells (A·2^K) × (B·2^K), nodes one more each way.
struct Grid {
  int A = 0, B = 0, depth = 0;
  int cu = 0, cv = 0;  // cells along u and v
  int side = 0;        // 2^K: cells per patch and direction
  std::size_t vertices = 0, quads = 0;
};

/// Refuses (before any work) a mesh above the byte limit or beyond int indices (vertices, and the
/// corners that face_offsets count); `what` says what the depth is applied to.
void check_size(std::size_t vertices, std::size_t quads, std::size_t cols, int depth, const std::string& what,
                std::size_t max_bytes) {
  const std::size_t bytes = mesh_bytes(vertices, cols, quads);
  const bool indexed = vertices <= static_cast<std::size_t>(INT_MAX) && mul_sat(quads, 4) <= INT_MAX;
  if (bytes <= max_bytes && indexed) return;
  std::ostringstream msg;
  // The message names the depth the user gave, not this routine.
  msg << "depth " << depth << " on " << what << " gives ";
  if (vertices == kSaturated) {
    msg << "more than 2^64 vertices";
  } else {
    msg << vertices << " vertices of " << cols << " coordinates and " << quads << " quads ("
        << static_cast<double>(bytes) / static_cast<double>(std::size_t{1} << 30) << " GiB)";
    if (!indexed)
      msg << ", more than the 2^31 − 1 vertices and corners a mesh addresses";
    else
      msg << ", more than the limit of "
          << static_cast<double>(max_bytes) / static_cast<double>(std::size_t{1} << 30)
          << " GiB held in memory";
  }
  msg << "; lower the depth";
  throw InvalidInput(msg.str());
}

std::size_t cells(int patches, int depth) {
  return depth > 30 ? kSaturated : mul_sat(static_cast<std::size_t>(patches), std::size_t{1} << depth);
}

/// Checks the depth and the sizes, and refuses a mesh above the byte limit before any work.
Grid make_grid(int A, int B, int depth, std::size_t cols, const MeshOptions& options) {
  if (depth < 0) throw InvalidInput("the depth " + std::to_string(depth) + " is negative; give a depth ≥ 0");
  const std::size_t cu = cells(A, depth), cv = cells(B, depth);
  const std::size_t vertices = mul_sat(cu + (cu < kSaturated), cv + (cv < kSaturated));
  check_size(vertices, mul_sat(cu, cv), cols, depth,
             std::to_string(A) + " by " + std::to_string(B) + " patches", options.max_bytes);
  return Grid{A, B, depth, static_cast<int>(cu), static_cast<int>(cv), 1 << depth, vertices, mul_sat(cu, cv)};
}

/// dst[0 … n) = src[0 … n) for 4-byte T. With `stream`, non-temporal stores (SSE2): the lines are not
/// read into the cache before being overwritten, which halves the memory traffic of an output far
/// larger than the cache. The caller fences (`stream_fence`) after its last streaming store.
template <class T>
void put(T* dst, const T* src, std::size_t n, bool stream) noexcept {
  static_assert(sizeof(T) == 4);
  std::size_t k = 0;
#if defined(__SSE2__)
  if (stream) {
    for (; k < n && (reinterpret_cast<std::uintptr_t>(dst + k) & 15) != 0; ++k) dst[k] = src[k];
    for (; k + 4 <= n; k += 4)
      _mm_stream_si128(reinterpret_cast<__m128i*>(dst + k),
                       _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + k)));
  }
#endif
  for (; k < n; ++k) dst[k] = src[k];
}

/// The corners of `blocks` grids of bu × bv cells, block after block, cell (I, J) of block b at face
/// b·bu·bv + I·bv + J with the corners (I, J), (I+1, J), (I+1, J+1), (I, J+1) of the block's
/// (bu + 1) × (bv + 1) nodes, and the offsets 0, 4, 8, …: one pass over the output, never zeroed
/// first (appended a row of cells at a time from one row shifted by a vertex row each time). The
/// storage of `mesh` is reused when it is large enough (no page faults when a caller meshes into
/// the same object again), and overwritten in place when it has the size (streaming stores when large).
/// States and normals are the routes'.
void write_quads(int blocks, int bu, int bv, Mesh& mesh) {
  const std::size_t faces =
      static_cast<std::size_t>(blocks) * static_cast<std::size_t>(bu) * static_cast<std::size_t>(bv);
  std::vector<int>& corners = mesh.face_vertices;
  std::vector<int>& offsets = mesh.face_offsets;
  // Storage of the right size is overwritten in place (no clearing, no capacity checks); other storage
  // is rebuilt by appending.
  const bool in_place = corners.size() == 4 * faces && offsets.size() == faces + 1;
  const bool stream = in_place && (5 * faces + 1) * sizeof(int) >= kStreamBytes;
  if (!in_place) {
    corners.clear();
    reserve_huge(corners, 4 * faces);
    offsets.clear();
    reserve_huge(offsets, faces + 1);
  }
  std::size_t written = 0;
  const int row = bv + 1;
  std::vector<int> line(4 * static_cast<std::size_t>(bv));
  for (int b = 0; b < blocks; ++b) {
    const int first = b * (bu + 1) * row;
    for (int J = 0; J < bv; ++J) {
      const auto at = 4 * static_cast<std::size_t>(J);
      line[at] = first + J;
      line[at + 1] = first + row + J;
      line[at + 2] = first + row + J + 1;
      line[at + 3] = first + J + 1;
    }
    for (int I = 0; I < bu; ++I, written += line.size()) {
      if (in_place)
        put(corners.data() + written, line.data(), line.size(), stream);
      else
        corners.insert(corners.end(), line.begin(), line.end());
      for (int& v : line) v += row;
    }
  }
  std::array<int, 1024> run{};
  for (std::size_t f = 0; f <= faces; f += run.size()) {
    const std::size_t n = std::min(run.size(), faces + 1 - f);
    for (std::size_t k = 0; k < n; ++k) run[k] = static_cast<int>(4 * (f + k));
    if (in_place)
      put(offsets.data() + f, run.data(), n, stream);
    else
      offsets.insert(offsets.end(), run.begin(), run.begin() + static_cast<std::ptrdiff_t>(n));
  }
  if (stream) stream_fence();
  mesh.normals.resize(0, 0);
  mesh.normal_indices.clear();
}

/// Vertices allocated (not set) and the quads of the grid.
void allocate(const Grid& grid, Eigen::Index cols, Mesh& mesh) {
  resize_huge(mesh.vertices, static_cast<Eigen::Index>(grid.vertices), cols);
  write_quads(1, grid.cu, grid.cv, mesh);
}

void finish(Mesh& mesh, const MeshOptions& options) {
  if (options.homogeneous) mesh.vertices = cartesian(mesh.vertices);
}

/// States of the depth-K nodes of a (binary or any) automaton in order: initial entries in order,
/// children in out-edge order. States only: no nets are computed. Level by level (each level is the
/// previous one's children in order), so two vectors serve the whole expansion.
std::vector<StateId> leaf_states(const Automaton& automaton, int depth) {
  const Graph& g = automaton.graph;
  std::vector<StateId> level, next;
  for (const automata::Initial& init : automaton.initial) level.push_back(init.state);
  for (int d = 0; d < depth; ++d) {
    next.clear();
    for (const StateId s : level) {
      const auto [b, e] = out_edges(s, g);
      for (auto it = b; it != e; ++it) next.push_back(target(*it, g));
    }
    level.swap(next);
  }
  return level;
}

/// Nodes [first, first + side) of a patch along one direction, plus the far node for the last patch.
int owned(const Grid& grid, int patch, int patches) {
  return grid.side + (patch + 1 == patches ? 1 : 0);
}

}  // namespace

std::size_t mesh_bytes(std::size_t vertices, std::size_t cols, std::size_t quads) noexcept {
  const std::size_t v = mul_sat(mul_sat(vertices, cols), sizeof(double));
  // Four corners, one offset and one state per quad.
  const std::size_t q = mul_sat(quads, 4 * sizeof(int) + sizeof(int) + sizeof(std::uint32_t));
  return v > kSaturated - q ? kSaturated : v + q;
}

namespace {

/// The separable route's checks. It reads the factors and the state pairs, never the product's
/// matrices: validating the product (every 16 by 16 matrix of a bicubic surface) costs as much as a
/// depth-8 mesh's quads.
void check_tensor(const nurbs::TensorAutomaton& t, std::span<const Points> nets) {
  for (const auto& f : t.factors) validate(f.automaton);
  check_nets(t.product, nets);
  if (t.factor_states.size() != num_vertices(t.product.graph))
    throw InvalidInput("the tensor automaton has " + std::to_string(t.factor_states.size()) +
                       " factor state pairs for " + std::to_string(num_vertices(t.product.graph)) +
                       " product states");
  for (StateId s = 0; s < t.factor_states.size(); ++s)
    for (std::size_t dir = 0; dir < 2; ++dir)
      if (t.factor_states[s][dir] >= num_vertices(t.factors[dir].automaton.graph))
        throw InvalidInput("the tensor automaton's product state " + std::to_string(s) +
                           " names factor state " + std::to_string(t.factor_states[s][dir]) +
                           " of direction " + std::to_string(dir) + ", which does not exist");
  const int A = static_cast<int>(t.factors[0].automaton.initial.size()),
            B = static_cast<int>(t.factors[1].automaton.initial.size());
  if (t.patches.size() != t.product.initial.size() || t.patches.size() != static_cast<std::size_t>(A) * B)
    throw InvalidInput("the tensor automaton has " + std::to_string(t.patches.size()) + " patches for " +
                       std::to_string(t.product.initial.size()) + " initial entries and " +
                       std::to_string(A) + " by " + std::to_string(B) + " factor segments");
  for (std::size_t k = 0; k < t.patches.size(); ++k)
    if (t.patches[k] != std::array<int, 2>{static_cast<int>(k) / B, static_cast<int>(k) % B})
      throw InvalidInput("the tensor automaton's patch " + std::to_string(k) +
                         " is not in u-major order; build it with tensor_automaton");
}

/// Curve stencil tables: row I of F[dir] is the functional, on the net of the segment owning node
/// I, of the point at node I — the factor's attractor under identity nets.
std::array<Points, 2> factor_tables(const nurbs::TensorAutomaton& t, int depth, std::size_t max_bytes) {
  std::array<Points, 2> F;
  for (std::size_t dir = 0; dir < 2; ++dir) {
    const Automaton& f = t.factors[dir].automaton;
    std::vector<Points> identity;
    for (const auto& init : f.initial)
      identity.push_back(Points::Identity(f.graph[init.state].size, f.graph[init.state].size));
    F[dir] = attractor_points(f, identity, depth,
                              PointsOptions{.closed = false, .max_bytes = max_bytes, .max_table_depth = 8});
  }
  return F;
}

/// The vertices, a patch row at a time. Homogeneous rows are divided by w a vertex row at a time,
/// straight into the output: no whole homogeneous mesh, and no second allocation of the vertices.
///
/// v pass once per patch row a: Y_k (k ≤ p) is row k of every patch net of the row taken along v
/// at the nodes the patch owns, i.e. Y_k(J) = Σ_l F_v(J, l)·N_b(k·(q+1) + l) — a `cv + 1 by C`
/// vertex row, stored contiguously. Each vertex row I of the patch row is then the (p + 1)-term
/// combination Σ_k F_u(I, k)·Y_k over one contiguous run of (cv + 1)·C doubles.
void write_vertices(const std::array<Points, 2>& F, std::span<const Points> nets, const Grid& grid,
                    bool homogeneous, bool reused, Mesh& mesh) {
  const int A = grid.A, B = grid.B;
  const Eigen::Index C = nets[0].cols(), D = homogeneous ? C - 1 : C;
  const Eigen::Index p1 = F[0].cols(), q1 = F[1].cols();
  const Eigen::Index width = static_cast<Eigen::Index>(grid.cv + 1) * C;
  std::vector<double> Y(static_cast<std::size_t>(p1 * width));
  std::vector<double> H(homogeneous ? static_cast<std::size_t>(width) : 0);  // one homogeneous row
  // Streaming stores for a large reused output (fresh pages are zeroed by the kernel on the first
  // write, in the cache: streaming over them was slower; homogeneous rows go through the row H).
  const bool stream = reused && !homogeneous &&
                      static_cast<std::size_t>(mesh.vertices.size()) * sizeof(double) >= kStreamBytes;
  const RowCombination combine = row_combination(static_cast<int>(p1), stream);
  std::vector<const double*> rows(static_cast<std::size_t>(p1));  // the p + 1 rows Y_k
  for (Eigen::Index k = 0; k < p1; ++k) rows[static_cast<std::size_t>(k)] = Y.data() + k * width;
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
      if (!homogeneous) {
        combine(f, static_cast<int>(p1), rows.data(), width, row);
        continue;
      }
      combine(f, static_cast<int>(p1), rows.data(), width, H.data());
      for (int J = 0; J <= grid.cv; ++J, row += D) {
        const double* h = H.data() + static_cast<Eigen::Index>(J) * C;
        const double w = h[D];
        if (w == 0)
          throw InvalidInput("mesh vertex " +
                             std::to_string(static_cast<std::size_t>(I) * (grid.cv + 1) + J) +
                             " has weight 0 (a point at infinity); give the surface positive weights");
        for (Eigen::Index c = 0; c < D; ++c) row[c] = h[c] / w;  // as cartesian(): the same bits
      }
    }
  }
  if (stream) stream_fence();
}

/// Leaf states: the product state of the pair of factor leaf states. Rows I with the same u leaf
/// state are equal, so each distinct row is built once and copied.
void write_states(const nurbs::TensorAutomaton& t, const Grid& grid, Mesh& mesh) {
  const std::array<std::vector<StateId>, 2> leaves{leaf_states(t.factors[0].automaton, grid.depth),
                                                   leaf_states(t.factors[1].automaton, grid.depth)};
  const auto nv_states = num_vertices(t.factors[1].automaton.graph);
  std::vector<std::uint32_t> pair_id(num_vertices(t.factors[0].automaton.graph) * nv_states, 0);
  for (StateId s = 0; s < t.factor_states.size(); ++s)
    pair_id[t.factor_states[s][0] * nv_states + t.factor_states[s][1]] = static_cast<std::uint32_t>(s);
  std::vector<std::vector<std::uint32_t>> state_row(num_vertices(t.factors[0].automaton.graph));
  const bool in_place = mesh.states.size() == grid.quads;
  // Streamed with the rest of a large mesh (the states alone are a fifth of the faces).
  const bool stream = in_place && mesh_bytes(grid.vertices, 3, grid.quads) >= kStreamBytes;
  if (!in_place) {
    mesh.states.clear();
    reserve_huge(mesh.states, grid.quads);
  }
  for (int I = 0; I < grid.cu; ++I) {
    const StateId su = leaves[0][static_cast<std::size_t>(I)];
    std::vector<std::uint32_t>& states = state_row[su];
    if (states.empty()) {
      states.resize(static_cast<std::size_t>(grid.cv));
      for (std::size_t J = 0; J < states.size(); ++J) states[J] = pair_id[su * nv_states + leaves[1][J]];
    }
    if (in_place)
      put(mesh.states.data() + static_cast<std::size_t>(I) * states.size(), states.data(), states.size(),
          stream);
    else
      mesh.states.insert(mesh.states.end(), states.begin(), states.end());
  }
  if (stream) stream_fence();
}

}  // namespace

void surface_mesh(const nurbs::TensorAutomaton& t, std::span<const Points> nets, int depth, Mesh& mesh,
                  const MeshOptions& options) {
  check_tensor(t, nets);
  const int A = static_cast<int>(t.factors[0].automaton.initial.size()),
            B = static_cast<int>(t.factors[1].automaton.initial.size());
  const Eigen::Index C = nets[0].cols();
  if (options.homogeneous && C < 2)
    throw InvalidInput("rational control nets need at least 2 columns (w·x, w), got " + std::to_string(C));
  const Grid grid = make_grid(A, B, depth, static_cast<std::size_t>(C), options);
  const std::array<Points, 2> F = factor_tables(t, depth, options.max_bytes);
  const Eigen::Index p1 = F[0].cols(), q1 = F[1].cols();
  if (nets[0].rows() != p1 * q1)
    throw InvalidInput("the control nets have " + std::to_string(nets[0].rows()) +
                       " points, the tensor automaton's factors give " + std::to_string(p1) + " by " +
                       std::to_string(q1));
  const bool keep = options.keep_faces && mesh.face_vertices.size() == 4 * grid.quads &&
                    mesh.face_offsets.size() == grid.quads + 1 && mesh.states.size() == grid.quads;
  const Eigen::Index D = options.homogeneous ? C - 1 : C;
  const bool reused =
      static_cast<std::size_t>(mesh.vertices.size()) == grid.vertices * static_cast<std::size_t>(D);
  if (keep) {
    resize_huge(mesh.vertices, static_cast<Eigen::Index>(grid.vertices), D);
    mesh.normals.resize(0, 0);
    mesh.normal_indices.clear();
  } else {
    allocate(grid, D, mesh);
  }
  write_vertices(F, nets, grid, options.homogeneous, reused, mesh);
  if (!keep) write_states(t, grid, mesh);
}

Mesh surface_mesh(const nurbs::TensorAutomaton& automaton, std::span<const Points> nets, int depth,
                  const MeshOptions& options) {
  Mesh mesh;
  surface_mesh(automaton, nets, depth, mesh, options);
  return mesh;
}

namespace {

/// Where the generic route writes a patch: node (I, J) of the patch is vertex `vertex + I·row + J`,
/// cell (I, J) face `face + I·face_row + J`; the patch's last node row (column) is its own when
/// its cells end at `close_u` (`close_v`), otherwise the next patch's first.
struct Placement {
  std::size_t vertex = 0, face = 0;
  int row = 0, face_row = 0, close_u = 0, close_v = 0;
};

/// The generic route's output: where each initial entry goes, and the faces as `blocks` grids of
/// block_u × block_v cells (one grid of A × B patches, or one block per entry).
struct Layout {
  std::vector<Placement> placements = {};
  int blocks = 0, block_u = 0, block_v = 0;
  std::size_t vertices = 0, faces = 0;
  std::string what = {};  // what the depth is applied to, for refusals
};

/// quad_mesh's layout: `patches` must fill their A × B grid exactly once.
Layout grid_layout(std::span<const std::array<int, 2>> patches, std::size_t initial, int depth) {
  if (patches.size() != initial)
    throw InvalidInput(std::to_string(patches.size()) + " patches given for the automaton's " +
                       std::to_string(initial) + " initial entries (one patch per entry)");
  int A = 0, B = 0;
  for (const auto& [a, b] : patches) {
    if (a < 0 || b < 0)
      throw InvalidInput("patch (" + std::to_string(a) + ", " + std::to_string(b) + ") has a negative index");
    A = std::max(A, a + 1);
    B = std::max(B, b + 1);
  }
  std::vector<int> patch_at(static_cast<std::size_t>(A) * B, -1);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    int& slot = patch_at[static_cast<std::size_t>(patches[i][0]) * B + patches[i][1]];
    if (slot >= 0)
      throw InvalidInput("initial entries " + std::to_string(slot) + " and " + std::to_string(i) +
                         " are both placed at patch (" + std::to_string(patches[i][0]) + ", " +
                         std::to_string(patches[i][1]) + ")");
    slot = static_cast<int>(i);
  }
  if (patches.size() != patch_at.size())
    throw InvalidInput(std::to_string(patches.size()) + " patches do not fill their " + std::to_string(A) +
                       " by " + std::to_string(B) + " grid");
  if (depth < 0) throw InvalidInput("the depth " + std::to_string(depth) + " is negative; give a depth ≥ 0");
  const std::size_t cu = cells(A, depth), cv = cells(B, depth);
  Layout out{.blocks = 1,
             .vertices = mul_sat(cu + (cu < kSaturated), cv + (cv < kSaturated)),
             .faces = mul_sat(cu, cv),
             .what = std::to_string(A) + " by " + std::to_string(B) + " patches"};
  if (out.vertices > static_cast<std::size_t>(INT_MAX)) return out;  // refused by check_size
  out.block_u = static_cast<int>(cu);
  out.block_v = static_cast<int>(cv);
  const int side = 1 << depth, row = out.block_v + 1;
  for (const auto& [a, b] : patches) {
    const int I = a * side, J = b * side;
    out.placements.push_back(
        {.vertex = static_cast<std::size_t>(I) * static_cast<std::size_t>(row) + static_cast<std::size_t>(J),
         .face = static_cast<std::size_t>(I) * static_cast<std::size_t>(out.block_v) +
                 static_cast<std::size_t>(J),
         .row = row,
         .face_row = out.block_v,
         .close_u = out.block_u - I,
         .close_v = out.block_v - J});
  }
  return out;
}

/// patch_meshes' layout: entry i is the block of (2^K + 1)² vertices and 4^K faces i.
Layout block_layout(std::size_t initial, int depth) {
  if (depth < 0) throw InvalidInput("the depth " + std::to_string(depth) + " is negative; give a depth ≥ 0");
  const std::size_t side = cells(1, depth),
                    nodes = side < kSaturated ? mul_sat(side + 1, side + 1) : kSaturated;
  Layout out{.blocks = static_cast<int>(std::min(initial, static_cast<std::size_t>(INT_MAX))),
             .vertices = mul_sat(nodes, initial),
             .faces = mul_sat(mul_sat(side, side), initial),
             .what = std::to_string(initial) + " patches"};
  if (out.vertices > static_cast<std::size_t>(INT_MAX)) return out;  // refused by check_size
  const int s = 1 << depth, block = (s + 1) * (s + 1);
  out.block_u = out.block_v = s;
  for (std::size_t i = 0; i < initial; ++i)
    out.placements.push_back({.vertex = i * static_cast<std::size_t>(block),
                              .face = i * static_cast<std::size_t>(s) * static_cast<std::size_t>(s),
                              .row = s + 1,
                              .face_row = s,
                              .close_u = s,
                              .close_v = s});
  return out;
}

/// A table's layout: a grid when it has patches.
Layout layout(const MeshStencilTable& table) {
  const std::size_t initial = table.automaton.initial.size();
  return table.patches.empty() ? block_layout(initial, table.depth)
                               : grid_layout(table.patches, initial, table.depth);
}

/// Checks that the automaton is valid, then the nets when given, then that every reachable state has
/// four children.
std::vector<StateId> surface_states(const Automaton& automaton,
                                    std::optional<std::span<const Points>> nets = std::nullopt) {
  validate(automaton);
  if (nets) check_nets(automaton, *nets);
  const Graph& g = automaton.graph;
  auto states = reachable_states(automaton);
  for (const StateId s : states)
    if (out_degree(s, g) != 4)
      throw InvalidInput(detail::state_label(automaton, s) + " has " + std::to_string(out_degree(s, g)) +
                         " children, a surface state needs 4 (GH, GB, DH, DB)");
  return states;
}

/// The tables of depth L ≤ `max_depth`, lowered until they (and, while building, the previous
/// level) hold at most `max_entries` doubles.
void build_tables(const Automaton& automaton, std::span<const StateId> states, int max_depth,
                  std::size_t max_entries, MeshStencilTable& out) {
  using Table = MeshStencilTable::RowMatrix;
  const Graph& g = automaton.graph;
  const auto table_size = [&](int L) {
    const std::size_t m = (std::size_t{1} << L) + 1;
    std::size_t total = 0;
    for (const StateId s : states) total += m * m * static_cast<std::size_t>(g[s].size);
    return total;
  };
  int L = std::max(max_depth, 0);
  while (L > 0 && table_size(L) + table_size(L - 1) > max_entries) --L;
  const auto n = num_vertices(g);
  out.table_depth = L;
  auto& table = out.tables;
  auto& leaf = out.leaf_states;
  table.assign(n, Table());
  leaf.assign(n, {});
  std::vector<Table> next(n);
  std::vector<std::vector<std::uint32_t>> next_leaf(n);
  {
    std::array<std::vector<Eigen::RowVectorXd>, 4> corner;
    for (int k = 0; k < 4; ++k)
      corner[static_cast<std::size_t>(k)] = detail::repeated_child_functionals_unchecked(automaton, k);
    for (const StateId s : states) {
      table[s].resize(4, g[s].size);
      for (std::size_t k = 0; k < 4; ++k) table[s].row(static_cast<Eigen::Index>(k)) = corner[k][s];
      leaf[s] = {static_cast<std::uint32_t>(s)};
    }
  }
  for (int l = 1; l <= L; ++l) {
    const int h = 1 << (l - 1), m = 2 * h + 1;
    for (const StateId s : states) {
      Table& T = next[s];
      T.resize(Eigen::Index{m} * m, g[s].size);
      std::vector<std::uint32_t>& S = next_leaf[s];
      S.assign(4 * static_cast<std::size_t>(h) * static_cast<std::size_t>(h), 0);
      int c = 0;
      for (auto [e, end] = out_edges(s, g); e != end; ++e, ++c) {
        const StateId child = target(*e, g);
        const Table P = table[child] * g[*e].matrix;  // (h+1)² functionals on the parent's net
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
}

/// The table of a checked automaton (`states` its reachable states) over a checked layout.
MeshStencilTable build_table(const Automaton& automaton, std::span<const StateId> states, int depth,
                             std::span<const std::array<int, 2>> patches, int max_table_depth,
                             std::size_t max_entries) {
  MeshStencilTable out{.automaton = automaton,
                       .depth = depth,
                       .patches = std::vector<std::array<int, 2>>(patches.begin(), patches.end())};
  build_tables(automaton, states, std::min(max_table_depth, depth), max_entries, out);
  return out;
}

/// Writes the mesh of checked nets over a checked layout: the faces, then a walk to depth K − L in
/// which each node writes the nodes it owns and the states of its 4^L leaves.
void emit_mesh(const MeshStencilTable& table, const Layout& layout, std::span<const Points> nets, Mesh& mesh,
               const MeshOptions& options) {
  const Automaton& automaton = table.automaton;
  const int depth = table.depth, L = table.table_depth, side_L = 1 << L, m = side_L + 1;
  const Eigen::Index C = nets[0].cols();
  const bool keep = options.keep_faces && mesh.face_vertices.size() == 4 * layout.faces &&
                    mesh.face_offsets.size() == layout.faces + 1 && mesh.states.size() == layout.faces;
  resize_huge(mesh.vertices, static_cast<Eigen::Index>(layout.vertices), C);
  mesh.normals.resize(0, 0);  // a reused mesh's normals belong to its old vertices
  mesh.normal_indices.clear();
  if (!keep) {
    write_quads(layout.blocks, layout.block_u, layout.block_v, mesh);
    assign_huge(mesh.states, layout.faces, std::uint32_t{0});  // written block by block, out of order
  }
  detail::depth_first(
      automaton, nets, depth - L,
      [&](std::size_t i, StateId s, const Points& net, int d, std::span<const int> word) {
        if (d < depth - L) return true;
        const Placement& p = layout.placements[i];
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
              table.tables[s].data() + static_cast<Eigen::Index>(r) * m * size, cols, size, net,
              mesh.vertices.data() +
                  (static_cast<Eigen::Index>(p.vertex) + static_cast<Eigen::Index>(I0 + r) * p.row + J0) * C);
        for (int r = 0; r < side_L && !keep; ++r)
          std::copy_n(table.leaf_states[s].begin() + static_cast<std::ptrdiff_t>(r) * side_L, side_L,
                      mesh.states.begin() + static_cast<std::ptrdiff_t>(p.face) +
                          static_cast<std::ptrdiff_t>(I0 + r) * p.face_row + J0);
        return false;
      });
  finish(mesh, options);
}

/// The generic route for quad_mesh (a grid of `patches`) and patch_meshes (no grid): every refusal
/// before any work.
void generic_mesh(const Automaton& automaton, std::span<const Points> nets,
                  std::optional<std::span<const std::array<int, 2>>> grid, int depth, Mesh& mesh,
                  const MeshOptions& options) {
  const auto states = surface_states(automaton, nets);
  const std::span<const std::array<int, 2>> patches = grid.value_or(std::span<const std::array<int, 2>>{});
  const Layout place = grid ? grid_layout(patches, automaton.initial.size(), depth)
                            : block_layout(automaton.initial.size(), depth);
  const Eigen::Index C = nets[0].cols();
  check_size(place.vertices, place.faces, static_cast<std::size_t>(C), depth, place.what, options.max_bytes);
  const MeshStencilTable table = build_table(automaton, states, depth, patches, options.max_table_depth,
                                             place.vertices * static_cast<std::size_t>(C) / 2);
  emit_mesh(table, place, nets, mesh, options);
}

/// Checks a table that may have been edited against its automaton, as mesh_stencil_table built it.
void check_table(const MeshStencilTable& t, std::span<const Points> nets) {
  const Automaton& a = t.automaton;
  const auto states = surface_states(a, nets);
  const Graph& g = a.graph;
  const auto n = num_vertices(g);
  bool fits = t.depth >= 0 && t.table_depth >= 0 && t.table_depth <= t.depth && t.table_depth < 16 &&
              t.tables.size() == n && t.leaf_states.size() == n;
  if (fits) {
    const Eigen::Index m = (Eigen::Index{1} << t.table_depth) + 1;
    const std::size_t leaves = std::size_t{1} << (2 * t.table_depth);
    for (const StateId s : states) {
      fits = fits && t.tables[s].rows() == m * m && t.tables[s].cols() == g[s].size &&
             t.leaf_states[s].size() == leaves;
      for (const std::uint32_t leaf : t.leaf_states[s]) fits = fits && leaf < n;
    }
  }
  if (!fits)
    throw InvalidInput("the mesh stencil table does not fit its automaton; build it with mesh_stencil_table");
}

}  // namespace

void quad_mesh(const Automaton& automaton, std::span<const Points> nets,
               std::span<const std::array<int, 2>> patches, int depth, Mesh& mesh,
               const MeshOptions& options) {
  generic_mesh(automaton, nets, patches, depth, mesh, options);
}

Mesh quad_mesh(const Automaton& automaton, std::span<const Points> nets,
               std::span<const std::array<int, 2>> patches, int depth, const MeshOptions& options) {
  Mesh mesh;
  quad_mesh(automaton, nets, patches, depth, mesh, options);
  return mesh;
}

Mesh patch_meshes(const Automaton& automaton, std::span<const Points> nets, int depth,
                  const MeshOptions& options) {
  Mesh mesh;
  generic_mesh(automaton, nets, std::nullopt, depth, mesh, options);
  return mesh;
}

MeshStencilTable mesh_stencil_table(const Automaton& automaton, int depth,
                                    const MeshStencilOptions& options) {
  const auto states = surface_states(automaton);
  const std::size_t initial = automaton.initial.size();
  const Layout place =
      options.patches.empty() ? block_layout(initial, depth) : grid_layout(options.patches, initial, depth);
  // Only the index limits: the bytes depend on the nets' columns and are checked when applied.
  check_size(place.vertices, place.faces, 3, depth, place.what, kSaturated);
  return build_table(automaton, states, depth, options.patches, options.max_table_depth, options.max_entries);
}

void apply_table(const MeshStencilTable& table, std::span<const Points> nets, Mesh& mesh,
                 const MeshOptions& options) {
  check_table(table, nets);
  const Layout place = layout(table);
  check_size(place.vertices, place.faces, static_cast<std::size_t>(nets[0].cols()), table.depth, place.what,
             options.max_bytes);
  emit_mesh(table, place, nets, mesh, options);
}

Mesh apply_table(const MeshStencilTable& table, std::span<const Points> nets, const MeshOptions& options) {
  Mesh mesh;
  apply_table(table, nets, mesh, options);
  return mesh;
}

}  // namespace cifs::ifs
