// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_triangle.hpp"

#include <algorithm>
#include <set>
#include <string>

#include "cifs/errors.hpp"

namespace cifs::ifs {

using automata::StateId;

namespace {

constexpr std::array<const char*, 4> kFaceLabels{"C0", "C1", "C2", "M"};

/// Child c's sides on the patch's sides, from its parent's (bit k: side k). The corner child k has
/// its sides k and k − 1 on its parent's sides k and k − 1; the middle one has none.
int child_sides(int parent, int c) {
  if (c == 3) return 0;
  return parent & ((1 << c) | (1 << ((c + 2) % 3)));
}

std::string face_name(int sides) {
  std::string name = "T";
  for (int k = 0; k < 3; ++k)
    if (sides & (1 << k)) name += std::to_string(k);
  return name;
}

void check_patch(const TrianglePatch& p) {
  const Eigen::Index n = p.children[0].rows();
  for (std::size_t c = 0; c < 4; ++c)
    if (p.children[c].rows() != n || p.children[c].cols() != n)
      throw InvalidInput("triangle BC-IFS: child " + std::string(kFaceLabels[c]) + " is " +
                         std::to_string(p.children[c].rows()) + " by " + std::to_string(p.children[c].cols()) +
                         ", expected " + std::to_string(n) + " by " + std::to_string(n) + " like child C0");
  const std::size_t m = p.sides[0].size();
  if (m == 0) throw InvalidInput("triangle BC-IFS: side 0 has no rows");
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& side = p.sides[k];
    const std::string where = "triangle BC-IFS: side " + std::to_string(k);
    if (side.size() != m)
      throw InvalidInput(where + " has " + std::to_string(side.size()) + " rows, side 0 " + std::to_string(m));
    if (std::set<int>(side.begin(), side.end()).size() != m) throw InvalidInput(where + " repeats a row");
    for (const int r : side)
      if (r < 0 || r >= n)
        throw InvalidInput(where + ": row " + std::to_string(r) + " is outside the net of " + std::to_string(n));
  }
  if (p.reverse.size() != m) throw InvalidInput("triangle BC-IFS: reverse has the wrong length");
  for (std::size_t i = 0; i < m; ++i) {
    const int j = p.reverse[i];
    if (j < 0 || static_cast<std::size_t>(j) >= m || p.reverse[static_cast<std::size_t>(j)] != static_cast<int>(i))
      throw InvalidInput("triangle BC-IFS: reverse is not an involution of a side's rows (at " + std::to_string(i) +
                         ")");
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
    for (Eigen::Index j = 0; j < m; ++j) E(i, j) = T(side[static_cast<std::size_t>(i)], side[static_cast<std::size_t>(j)]);
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
  // Cells: faces by their sides on the patch's (bit k: side k), 7 = the patch, first; then the edges.
  std::array<StateId, 8> face{};
  for (int s = 7; s >= 0; --s) {
    face[static_cast<std::size_t>(s)] = add_vertex(automata::State{.size = n, .recurrent = false, .name = face_name(s)}, g);
    sys.dimension.push_back(2);
  }
  const StateId kept = add_vertex(automata::State{.size = m, .recurrent = false, .name = "Eb"}, g);
  const StateId inner = add_vertex(automata::State{.size = m, .recurrent = false, .name = "Ei"}, g);
  sys.dimension.insert(sys.dimension.end(), {1, 1});
  sys.automaton.initial.push_back(automata::Initial{.segment = 0, .state = face[7]});
  for (int s = 7; s >= 0; --s)
    for (int c = 0; c < 4; ++c) {
      add_edge(face[static_cast<std::size_t>(s)], face[static_cast<std::size_t>(child_sides(s, c))],
               automata::Transition{kFaceLabels[static_cast<std::size_t>(c)], patch.children[static_cast<std::size_t>(c)]}, g);
      sys.free.push_back(TransitionRef{face[static_cast<std::size_t>(s)], c});
    }
  const Eigen::MatrixXd G = side_operator(patch, 0), D = side_operator(patch, 1);
  for (const StateId e : {kept, inner}) {
    add_edge(e, e, automata::Transition{"G", G}, g);
    add_edge(e, e, automata::Transition{"D", D}, g);
  }
  sys.free.push_back(TransitionRef{inner, 0});
  sys.free.push_back(TransitionRef{inner, 1});
  automata::mark_recurrent(sys.automaton);
  // Boundaries: per face cell s<k> then s<k>r for k = 0, 1, 2; index 6·f + 2k + reversed.
  std::array<std::array<std::array<int, 2>, 3>, 8> side_of{};
  for (int s = 7; s >= 0; --s)
    for (int k = 0; k < 3; ++k)
      for (int r = 0; r < 2; ++r) {
        const auto& rows = patch.sides[static_cast<std::size_t>(k)];
        BoundaryOperator op{"s" + std::to_string(k) + (r ? "r" : ""), face[static_cast<std::size_t>(s)],
                            (s & (1 << k)) ? kept : inner, {}};
        for (int i = 0; i < m; ++i)
          op.rows.push_back(rows[static_cast<std::size_t>(r ? patch.reverse[static_cast<std::size_t>(i)] : i)]);
        side_of[static_cast<std::size_t>(s)][static_cast<std::size_t>(k)][static_cast<std::size_t>(r)] =
            static_cast<int>(sys.boundaries.size());
        sys.boundaries.push_back(std::move(op));
      }
  // Constraints: incidence of the children on their parent's sides (both readings), adjacency of the
  // middle child with the corner ones.
  for (int s = 7; s >= 0; --s) {
    const StateId F = face[static_cast<std::size_t>(s)];
    const std::string name = g[F].name;
    const auto b = [&](int of, int k, int r) {
      return boundary_factor(side_of[static_cast<std::size_t>(of)][static_cast<std::size_t>(k)][static_cast<std::size_t>(r)]);
    };
    for (int k = 0; k < 3; ++k) {
      const StateId e = (s & (1 << k)) ? kept : inner;
      const std::string side = ".s" + std::to_string(k);
      for (int r = 0; r < 2; ++r)
        for (int half = 0; half < 2; ++half) {
          // Reading forward, the first half (G) is child k's side; reversed, it is child k + 1's.
          const int c = (k + (half != r ? 1 : 0)) % 3;
          sys.constraints.push_back(Constraint{name + side + (r ? "r" : "") + (half ? ".D" : ".G"),
                                               {b(child_sides(s, c), k, r), transition_factor(F, c)},
                                               {transition_factor(e, half), b(s, k, r)}});
        }
      const int c = (k + 2) % 3;
      sys.constraints.push_back(Constraint{name + ".M" + side,
                                           {b(0, k, 0), transition_factor(F, 3)},
                                           {b(child_sides(s, c), k, 1), transition_factor(F, c)}});
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
