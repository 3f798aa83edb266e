// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_triangle.hpp"

#include <algorithm>
#include <compare>
#include <map>
#include <set>
#include <string>

#include "cifs/errors.hpp"

namespace cifs::ifs {

using automata::StateId;

namespace {

constexpr std::array<const char*, 4> kFaceLabels{"C0", "C1", "C2", "M"};

/// A face cell: which of its sides (bit k: side k) and which of its corners (bit k: corner k) lie on
/// the patch's sides. Corners apart from sides keep the points on the patch's sides apart from those
/// created inside, as the curve system's a/b flags do (docs/bcifs.md).
struct FaceKey {
  int sides = 0, corners = 0;
  // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the 0 of a defaulted <=>'s expansion.
  friend auto operator<=>(const FaceKey&, const FaceKey&) = default;
};

bool has(int bits, int k) {
  return (bits >> (k % 3) & 1) != 0;
}

/// Child c's key. The corner child c has its sides c and c − 1 on its parent's, its corner c is its
/// parent's and its corners c + 1, c + 2 are the midpoints of its parent's sides c, c + 2; the middle
/// child's corners 0, 1, 2 are the midpoints of sides 1, 2, 0.
FaceKey child_key(FaceKey parent, int c) {
  FaceKey out;
  if (c == 3) {
    for (int j = 0; j < 3; ++j) out.corners |= has(parent.sides, j + 1) << j;
    return out;
  }
  out.sides = parent.sides & ((1 << c) | (1 << ((c + 2) % 3)));
  out.corners = has(parent.corners, c) << c | has(parent.sides, c) << ((c + 1) % 3) |
                has(parent.sides, c + 2) << ((c + 2) % 3);
  return out;
}

std::string face_name(FaceKey key) {
  std::string name = "T";
  for (int k = 0; k < 3; ++k)
    if (has(key.sides, k)) name += std::to_string(k);
  // Corners on the patch's sides that no side on them explains.
  std::string extra;
  for (int k = 0; k < 3; ++k)
    if (has(key.corners, k) && !has(key.sides, k) && !has(key.sides, k + 2)) extra += std::to_string(k);
  return extra.empty() ? name : name + "c" + extra;
}

/// An inner edge cell: does it start (a), end (b) on the patch's sides; Eb is {-1, -1}.
using EdgeKey = std::array<int, 2>;

std::string edge_name(EdgeKey key) {
  if (key[0] < 0) return "Eb";
  return std::string("Ei") + (key[0] ? "a" : "") + (key[1] ? "b" : "");
}

void check_patch(const TrianglePatch& p) {
  const Eigen::Index n = p.children[0].rows();
  for (std::size_t c = 0; c < 4; ++c)
    if (p.children[c].rows() != n || p.children[c].cols() != n)
      throw InvalidInput("triangle BC-IFS: child " + std::string(kFaceLabels[c]) + " is " +
                         std::to_string(p.children[c].rows()) + " by " +
                         std::to_string(p.children[c].cols()) + ", expected " + std::to_string(n) + " by " +
                         std::to_string(n) + " like child C0");
  const std::size_t m = p.sides[0].size();
  if (m == 0) throw InvalidInput("triangle BC-IFS: side 0 has no rows");
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& side = p.sides[k];
    const std::string where = "triangle BC-IFS: side " + std::to_string(k);
    if (side.size() != m)
      throw InvalidInput(where + " has " + std::to_string(side.size()) + " rows, side 0 " +
                         std::to_string(m));
    if (std::set<int>(side.begin(), side.end()).size() != m) throw InvalidInput(where + " repeats a row");
    for (const int r : side)
      if (r < 0 || r >= n)
        throw InvalidInput(where + ": row " + std::to_string(r) + " is outside the net of " +
                           std::to_string(n));
  }
  if (p.reverse.size() != m) throw InvalidInput("triangle BC-IFS: reverse has the wrong length");
  for (std::size_t i = 0; i < m; ++i) {
    const int j = p.reverse[i];
    if (j < 0 || static_cast<std::size_t>(j) >= m ||
        p.reverse[static_cast<std::size_t>(j)] != static_cast<int>(i))
      throw InvalidInput("triangle BC-IFS: reverse is not an involution of a side's rows (at " +
                         std::to_string(i) + ")");
  }
}

/// The edge operator that child `c` applies to side 0: its rows on side 0 restricted to side 0's
/// columns; InvalidInput when they read a row off the side (then the side is not subdivided alone).
Eigen::MatrixXd side_operator(const TrianglePatch& p, int c) {
  const auto& side = p.sides[0];
  const auto m = static_cast<Eigen::Index>(side.size());
  const Eigen::MatrixXd& T = p.children[static_cast<std::size_t>(c)];
  Eigen::MatrixXd E(m, m);
  std::vector<bool> on(static_cast<std::size_t>(T.cols()), false);
  for (const int r : side) on[static_cast<std::size_t>(r)] = true;
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = 0; j < m; ++j)
      E(i, j) = T(side[static_cast<std::size_t>(i)], side[static_cast<std::size_t>(j)]);
    for (Eigen::Index col = 0; col < T.cols(); ++col)
      if (!on[static_cast<std::size_t>(col)] && T(side[static_cast<std::size_t>(i)], col) != 0)
        throw InvalidInput("triangle BC-IFS: child " + std::string(kFaceLabels[static_cast<std::size_t>(c)]) +
                           "'s row " + std::to_string(side[static_cast<std::size_t>(i)]) +
                           " on side 0 reads row " + std::to_string(col) + ", which is not on side 0");
  }
  return E;
}

Factor boundary_factor(int b) {
  return Factor{Factor::Kind::boundary, b, {}};
}

Factor transition_factor(StateId from, int child) {
  return Factor{Factor::Kind::transition, 0, TransitionRef{from, child}};
}

}  // namespace

Bcifs triangle_bcifs(const TrianglePatch& patch) {
  check_patch(patch);
  Bcifs sys;
  auto& g = sys.automaton.graph;
  const auto n = static_cast<int>(patch.children[0].rows());
  const auto m = static_cast<int>(patch.sides[0].size());
  const Eigen::MatrixXd G = side_operator(patch, 0), D = side_operator(patch, 1);
  // Edge cells: Eb (kept) and the inner ones by their ends' flags; G keeps the start's, D the end's.
  std::map<EdgeKey, StateId> edges;
  const auto edge_of = [&](EdgeKey key) {
    const auto [it, added] = edges.try_emplace(key, 0);
    if (added) {
      it->second = add_vertex(automata::State{.size = m, .recurrent = false, .name = edge_name(key)}, g);
      sys.dimension.push_back(1);
    }
    return it->second;
  };
  // Face cells from the patch (all sides and corners on itself), closed under children.
  std::map<FaceKey, StateId> faces;
  std::vector<FaceKey> keys;
  const auto face_of = [&](FaceKey key) {
    const auto [it, added] = faces.try_emplace(key, 0);
    if (added) {
      it->second = add_vertex(automata::State{.size = n, .recurrent = false, .name = face_name(key)}, g);
      sys.dimension.push_back(2);
      keys.push_back(key);
    }
    return it->second;
  };
  sys.automaton.initial.push_back(automata::Initial{.segment = 0, .state = face_of({7, 7})});
  for (std::size_t f = 0; f < keys.size(); ++f)
    for (int c = 0; c < 4; ++c) face_of(child_key(keys[f], c));
  for (const FaceKey key : keys)
    for (int c = 0; c < 4; ++c) {
      add_edge(faces.at(key), faces.at(child_key(key, c)),
               automata::Transition{kFaceLabels[static_cast<std::size_t>(c)],
                                    patch.children[static_cast<std::size_t>(c)]},
               g);
      sys.free.push_back(TransitionRef{faces.at(key), c});
    }
  // Side k of a face read forward (r = 0) or backwards: its edge cell.
  const auto side_edge = [&](FaceKey key, int k, int r) {
    if (has(key.sides, k)) return edge_of({-1, -1});
    const int a = has(key.corners, k), b = has(key.corners, k + 1);
    return r ? edge_of({b, a}) : edge_of({a, b});
  };
  for (const FaceKey key : keys)
    for (int k = 0; k < 3; ++k) side_edge(key, k, 0), side_edge(key, k, 1);
  // Every edge cell gets its halves; a half's cell may be new (its flags are its parent's start or end).
  std::vector<EdgeKey> order;
  order.reserve(5);  // Eb and the four inner cells
  for (const auto& [key, e] : edges) order.push_back(key);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const EdgeKey key = order[i];
    const bool kept = key[0] < 0;
    for (const EdgeKey half : {EdgeKey{key[0], 0}, EdgeKey{0, key[1]}})
      if (!kept && !edges.count(half)) {
        edge_of(half);
        order.push_back(half);
      }
    const StateId e = edges.at(key);
    add_edge(e, kept ? e : edge_of({key[0], 0}), automata::Transition{"G", G}, g);
    add_edge(e, kept ? e : edge_of({0, key[1]}), automata::Transition{"D", D}, g);
    if (!kept) {
      sys.free.push_back(TransitionRef{e, 0});
      sys.free.push_back(TransitionRef{e, 1});
    }
  }
  automata::mark_recurrent(sys.automaton);
  // Boundaries: per face cell s<k> then s<k>r for k = 0, 1, 2.
  std::map<std::array<int, 4>, int> side_of;  // (sides, corners, k, reversed) → boundary
  for (const FaceKey key : keys)
    for (int k = 0; k < 3; ++k)
      for (int r = 0; r < 2; ++r) {
        const auto& rows = patch.sides[static_cast<std::size_t>(k)];
        BoundaryOperator op{
            "s" + std::to_string(k) + (r ? "r" : ""), faces.at(key), side_edge(key, k, r), {}};
        for (int i = 0; i < m; ++i)
          op.rows.push_back(
              rows[static_cast<std::size_t>(r ? patch.reverse[static_cast<std::size_t>(i)] : i)]);
        side_of[{key.sides, key.corners, k, r}] = static_cast<int>(sys.boundaries.size());
        sys.boundaries.push_back(std::move(op));
      }
  // Constraints: incidence of the children on their parent's sides (both readings), adjacency of the
  // middle child with the corner ones.
  for (const FaceKey key : keys) {
    const StateId F = faces.at(key);
    const std::string name = g[F].name;
    const auto b = [&](FaceKey of, int k, int r) {
      return boundary_factor(side_of.at({of.sides, of.corners, k, r}));
    };
    for (int k = 0; k < 3; ++k) {
      const std::string side = ".s" + std::to_string(k);
      for (int r = 0; r < 2; ++r) {
        const StateId e = side_edge(key, k, r);
        for (int half = 0; half < 2; ++half) {
          // Reading forward, the first half (G) is child k's side; reversed, it is child k + 1's.
          const int c = (k + (half != r ? 1 : 0)) % 3;
          sys.constraints.push_back(Constraint{name + side + (r ? "r" : "") + (half ? ".D" : ".G"),
                                               {b(child_key(key, c), k, r), transition_factor(F, c)},
                                               {transition_factor(e, half), b(key, k, r)}});
        }
      }
      const int c = (k + 2) % 3;
      sys.constraints.push_back(Constraint{(name + ".M").append(side),
                                           {b(child_key(key, 3), k, 0), transition_factor(F, 3)},
                                           {b(child_key(key, c), k, 1), transition_factor(F, c)}});
    }
  }
  try {
    check_admissible(sys);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("triangle BC-IFS: the patch's own matrices break its constraints (are the "
                                   "sides and their reversal those of the patch?): ") +
                       e.what());
  }
  return sys;
}

}  // namespace cifs::ifs
