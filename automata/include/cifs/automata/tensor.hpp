// SPDX-License-Identifier: MIT
// cifs — the pieces of tensor-product automata that know no knots: Kronecker products of
// transition matrices and the v and w directions' labels. The tensor-product automaton of a NURBS
// surface is nurbs::TensorAutomaton (cifs/nurbs/tensor_automaton.hpp).
#pragma once

#include <Eigen/Core>
#include <string>

namespace cifs::automata {

/// kron(A, B): entry (i·B.rows() + k, j·B.cols() + l) = A(i, j)·B(k, l), one product per entry, so
/// the result is exact given A and B (the matrices of the product automaton, and of the surface
/// BC-IFS built on it, are bit-identical).
Eigen::MatrixXd kron(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);
/// The v direction's halves are named H (first) and B (second), so that product labels read GH … DB.
std::string v_label(const std::string& label);
/// The w direction's halves (volumes) are named A (first, avant) and R (second, arrière), so that the
/// labels of a volume's product read GHA, GHR, GBA … DBR (u, v, w halves in that order).
std::string w_label(const std::string& label);

}  // namespace cifs::automata
