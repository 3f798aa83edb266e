// SPDX-License-Identifier: MIT
// cifs — the chaos game of a controlled IFS as a density image, deterministic for any thread count.
#include "cifs/render/chaos_density.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/random.hpp"
#include "framebuffer.hpp"
#include "parallel.hpp"

namespace cifs::render {
namespace {

using automata::Graph;
using automata::StateId;

/// A transition in the form the inner loop reads: the target state and the column-major
/// `to.size by from.size` matrix.
struct Edge {
  std::uint32_t target;
  const double* M;
  int rows, cols;
};

struct Tables {
  std::vector<std::uint32_t> first, degree;  // per state: its out-edges in `edges`
  std::vector<Edge> edges;
  std::vector<Eigen::RowVectorXd> start;  // per state
  int max_size = 0;
};

Tables tables(const automata::Automaton& automaton) {
  const Graph& g = automaton.graph;
  Tables t;
  const auto states = num_vertices(g);
  t.first.resize(states);
  t.degree.resize(states);
  for (StateId s = 0; s < states; ++s) {
    t.first[s] = static_cast<std::uint32_t>(t.edges.size());
    t.degree[s] = static_cast<std::uint32_t>(out_degree(s, g));
    t.max_size = std::max(t.max_size, g[s].size);
    for (auto [b, e] = out_edges(s, g); b != e; ++b) {
      const Eigen::MatrixXd& M = g[*b].matrix;
      t.edges.push_back({static_cast<std::uint32_t>(target(*b, g)), M.data(), static_cast<int>(M.rows()),
                         static_cast<int>(M.cols())});
    }
  }
  t.start = ifs::end_functionals(automaton).start;
  return t;
}

void check_nets(const automata::Automaton& automaton, std::span<const Points> nets, bool rational) {
  ifs::check_nets(automaton, nets);
  const auto cols = nets[0].cols();
  const auto dim = rational ? cols - 1 : cols;
  if (dim != 2 && dim != 3)
    throw InvalidInput("the control nets have " + std::to_string(cols) + " columns, the chaos game draws " +
                       (rational ? "3 or 4 (homogeneous)" : "2 or 3") + std::string(" (2-D or 3-D points)"));
}

constexpr double kMaxChaosWork = 0x1p38;

/// Smallest depth at which every node's piece lies within `tolerance` pixels of its start point
/// (the point drawn for it): ifs::depth_for_tolerance at ε = tolerance / (pixels per world unit).
/// Its search visits at most as many leaves as the game draws samples (one leaf's bound costs about
/// one sample's descent), 2^12 … 2^20: past them, the deeper global bound. A perspective surface of
/// 1,000 samples searched 2^20 leaves (5 s) for a game of milliseconds.
int automatic_depth(const automata::Automaton& automaton, std::span<const Points> nets,
                    const ViewTransform& view, double tolerance, std::uint64_t samples) {
  double scale = view.scale;
  if (view.perspective) {
    const double radius = ifs::contraction(automaton).radius;  // only here: seconds for large states
    // A world length ℓ at depth z spans ℓ·F/z pixels: use the nearest depth the attractor can
    // reach (every point lies within ρ·diam(N) of the net's first row), but not nearer than
    // `near`, in front of which nothing is drawn.
    double nearest = std::numeric_limits<double>::infinity();
    for (const Points& N : nets) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      p.head(N.cols()) = N.row(0).transpose();
      nearest = std::min(nearest, (p - view.eye).dot(view.forward) - radius * ifs::diameter(N));
    }
    scale /= std::max(nearest, view.near);
  }
  const auto leaves = std::clamp<std::uint64_t>(samples, std::uint64_t{1} << 12, std::uint64_t{1} << 20);
  return ifs::depth_for_tolerance(automaton, nets, {.epsilon = tolerance / scale, .max_depth = 64}, leaves);
}

/// Per-worker buffers: hits, nearest depth, the sample index and state of that point.
struct Local {
  std::vector<std::uint32_t> counts;
  std::vector<float> depth;
  std::vector<std::uint64_t> key;
  std::vector<std::uint32_t> state;
  std::uint64_t outside = 0;
};

void check_input(const automata::Automaton& automaton, std::span<const Points> nets,
                 const ChaosDensityOptions& options) {
  check_part(options.part);
  ifs::validate(automaton);
  check_nets(automaton, nets, options.rational);
  if (options.depth < 0 || options.depth > 64)
    throw InvalidInput("the chaos game's depth " + std::to_string(options.depth) + " is outside 0 … 64");
  if (options.rational && options.depth == 0)
    throw InvalidInput("the chaos game of a rational shape needs an explicit depth; give one");
  if (!(options.pixel_tolerance > 0)) throw InvalidInput("the chaos game's pixel tolerance must be positive");
}

/// Refuses a game this part cannot count (uint32) or that would take too long, before it starts.
void check_budget(const automata::Automaton& automaton, const ChaosDensityOptions& options,
                  std::uint64_t part_samples, int depth) {
  const Part& part = options.part;
  // Counts are uint32 per process: more samples are drawn by more processes.
  if (part_samples >= (std::uint64_t{1} << 32))
    throw InvalidInput(part.count == 1
                           ? std::to_string(part_samples) +
                                 " chaos-game samples are too many: they must be below 2^32 (uint32 counts)"
                           : "part " + std::to_string(part.index) + " of " + std::to_string(part.count) +
                                 " draws " + std::to_string(part_samples) +
                                 " samples, at most 2^32 - 1 per part (uint32 counts)");
  // Each sample descends `depth` levels, a `size × size` matrix times the net per level: refuse a
  // game past ~2^38 multiply-adds (minutes) before it starts; 2^32 − 1 samples took hours.
  int size = 1;
  for (std::size_t s = 0; s < num_vertices(automaton.graph); ++s)
    size = std::max(size, automaton.graph[s].size);
  // The limit is per process: a distributed game (options.part) divides the samples.
  const double count = options.part.count > 1 ? static_cast<double>(options.part.count) : 1.0;
  const double work = static_cast<double>(part_samples) * depth * size * size;
  if (work > kMaxChaosWork)
    throw InvalidInput(
        "chaos game: " + std::to_string(options.samples) + " samples" +
        (count > 1 ? " over " + std::to_string(options.part.count) + " processes" : std::string()) +
        " × depth " + std::to_string(depth) + " × " + std::to_string(size) +
        "² coefficients = " + number_text(work, 3) + " multiply-adds" + (count > 1 ? " per process" : "") +
        ", above the limit of " + number_text(kMaxChaosWork, 3) + "; ask for at most " +
        std::to_string(static_cast<std::uint64_t>(count * kMaxChaosWork / (double(depth) * size * size))) +
        " samples");
}

/// 32 random bits per choice, two per 64-bit draw.
struct RandomBits {
  Random rng;
  std::uint64_t pool = 0;
  bool half = false;
  std::uint32_t next() noexcept {
    half = !half;
    if (half) pool = rng();
    return static_cast<std::uint32_t>(half ? pool >> 32 : pool);
  }
};

/// What every chunk of the game reads.
struct Game {
  const Tables& t;
  const automata::Automaton& automaton;
  std::span<const Points> nets;
  const ViewTransform& view;
  const std::vector<float>& Z;  // the image's depth: earlier layers hide points behind them
  std::size_t W, H;
  int depth;
  const ChaosDensityOptions& options;
};

/// The buffers of one sample: the edges of its walk, the functional and its next value.
struct Walk {
  std::vector<std::uint32_t> path;
  std::vector<double> r, next;
};

/// A random walk of `depth` edges from root's state; returns the leaf state.
std::uint32_t descend(const Game& g, std::uint32_t root, RandomBits& bits, Walk& walk) {
  std::uint32_t s = static_cast<std::uint32_t>(g.automaton.initial[root].state);
  for (int level = 0; level < g.depth; ++level) {
    const std::uint32_t e = g.t.first[s] + bounded(bits.next(), g.t.degree[s]);
    walk.path[static_cast<std::size_t>(level)] = e;
    s = g.t.edges[e].target;
  }
  return s;
}

/// The leaf's start point on screen: its start functional pulled back to the root's net, r ← r·M
/// leaf to root, applied to the net.
Projected leaf_point(const Game& g, std::uint32_t root, std::uint32_t leaf, Walk& walk) {
  const Eigen::RowVectorXd& start = g.t.start[leaf];
  std::copy(start.data(), start.data() + start.size(), walk.r.begin());
  for (int level = g.depth - 1; level >= 0; --level) {
    const Edge& e = g.t.edges[walk.path[static_cast<std::size_t>(level)]];
    for (int j = 0; j < e.cols; ++j) {
      const double* column = e.M + static_cast<std::ptrdiff_t>(j) * e.rows;
      double sum = 0;
      for (int i = 0; i < e.rows; ++i) sum += walk.r[static_cast<std::size_t>(i)] * column[i];
      walk.next[static_cast<std::size_t>(j)] = sum;
    }
    std::swap(walk.r, walk.next);
  }
  const Points& N = g.nets[root];
  const auto cols = g.nets[0].cols();
  double x[4] = {0, 0, 0, 0};
  for (Eigen::Index k = 0; k < cols; ++k)
    for (Eigen::Index i = 0; i < N.rows(); ++i) x[k] += walk.r[static_cast<std::size_t>(i)] * N(i, k);
  if (g.options.rational) {
    const double weight = x[cols - 1];
    x[cols - 1] = 0;
    for (auto& v : x) v /= weight;
  }
  return g.view.project({x[0], x[1], x[2]});
}

/// The samples of one chunk into a worker's buffers; returns their count.
std::uint64_t play_chunk(const Game& g, std::uint64_t chunk, Local& l) {
  RandomBits bits{Random(g.options.seed, chunk)};
  const auto roots = static_cast<std::uint32_t>(g.automaton.initial.size());
  Walk walk{std::vector<std::uint32_t>(static_cast<std::size_t>(g.depth)),
            std::vector<double>(static_cast<std::size_t>(g.t.max_size)),
            std::vector<double>(static_cast<std::size_t>(g.t.max_size))};
  const std::uint64_t first = chunk * kDensityChunk;
  const std::uint64_t count = std::min(kDensityChunk, g.options.samples - first);
  for (std::uint64_t n = 0; n < count; ++n) {
    const std::uint32_t root = roots > 1 ? bounded(bits.next(), roots) : 0;
    const std::uint32_t s = descend(g, root, bits, walk);
    const Projected p = leaf_point(g, root, s, walk);
    const bool on_screen = g.view.visible_depth(p.depth) && p.x >= 0 && p.x < static_cast<double>(g.W) &&
                           p.y >= 0 && p.y < static_cast<double>(g.H);
    if (!on_screen) {
      ++l.outside;
      continue;
    }
    const std::size_t i = static_cast<std::size_t>(p.y) * g.W + static_cast<std::size_t>(p.x);
    const float z = static_cast<float>(p.depth);
    if (!(z <= g.Z[i])) continue;  // hidden by an earlier layer
    ++l.counts[i];
    // A worker sees its samples in increasing index order, so the later of equally near
    // points always replaces the earlier.
    if (z <= l.depth[i]) {
      l.depth[i] = z;
      l.key[i] = first + n;
      l.state[i] = s;
    }
  }
  return count;
}

/// Merge: integer sums, and the nearest point (ties: the larger sample index), both independent
/// of which worker ran which chunk.
void merge(std::vector<Local>& local, std::size_t pixels, DensityLayer& layer, ChaosDensityResult& result) {
  layer = {std::vector<double>(pixels, 0), std::move(local[0].depth), std::move(local[0].key),
           std::move(local[0].state)};
  for (std::size_t i = 0; i < pixels; ++i) layer.density[i] = local[0].counts[i];
  result.outside = local[0].outside;
  for (std::size_t w = 1; w < local.size(); ++w) {
    const Local& l = local[w];
    result.outside += l.outside;
    for (std::size_t i = 0; i < pixels; ++i) {
      layer.density[i] += l.counts[i];
      if (l.depth[i] < layer.depth[i] || (l.depth[i] == layer.depth[i] && l.key[i] > layer.sample[i])) {
        layer.depth[i] = l.depth[i];
        layer.state[i] = l.state[i];
        layer.sample[i] = l.key[i];
      }
    }
  }
}

}  // namespace

ChaosDensityResult chaos_density(Image& image, const Camera& camera, const automata::Automaton& automaton,
                                 std::span<const Points> nets, const ChaosDensityOptions& options) {
  DensityLayer layer;
  const ChaosDensityResult result = chaos_density_layer(layer, image, camera, automaton, nets, options);
  // Hidden points are neither counted nor outside: they are part of the samples on screen.
  composite(image, layer, options.color);
  return result;
}

ChaosDensityResult chaos_density_layer(DensityLayer& layer, Image& image, const Camera& camera,
                                       const automata::Automaton& automaton, std::span<const Points> nets,
                                       const ChaosDensityOptions& options) {
  const ViewTransform view = detail::prepare(image, camera);
  check_input(automaton, nets, options);
  const Tables t = tables(automaton);
  ChaosDensityResult result;
  result.samples = options.samples;
  result.depth = options.depth > 0
                     ? options.depth
                     : automatic_depth(automaton, nets, view, options.pixel_tolerance, options.samples);
  const int depth = result.depth;

  const std::size_t W = image.width, H = image.height, pixels = W * H;
  const std::vector<float>& Z = image.channels["Z"];
  // This part's chunks: part.index, part.index + part.count, …
  const Part part = options.part;
  const PartChunks dealt = part_chunks(part, options.samples, kDensityChunk);
  const std::uint64_t chunks = dealt.mine, part_samples = dealt.samples;
  check_budget(automaton, options, part_samples, depth);
  const unsigned threads = detail::worker_count(options.threads, chunks);
  std::vector<Local> local(threads);
  std::mutex progress_mutex;
  std::uint64_t done = 0;
  const Game game{t, automaton, nets, view, Z, W, H, depth, options};

  detail::run_chunks(
      chunks, threads,
      [&](unsigned w) {
        Local& l = local[w];
        l.counts.assign(pixels, 0);
        l.depth.assign(pixels, std::numeric_limits<float>::infinity());
        l.key.assign(pixels, 0);
        l.state.assign(pixels, kNoState);
      },
      [&](unsigned w, std::uint64_t mine) {
        const std::uint64_t count = play_chunk(game, part.index + mine * part.count, local[w]);
        if (options.progress) {
          const std::lock_guard lock(progress_mutex);
          done += count;
          options.progress(done, part_samples);
        }
      });
  merge(local, pixels, layer, result);
  return result;
}

}  // namespace cifs::render
