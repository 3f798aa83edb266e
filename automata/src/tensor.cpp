// SPDX-License-Identifier: MIT
#include "cifs/automata/tensor.hpp"

namespace cifs::automata {

Eigen::MatrixXd kron(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  Eigen::MatrixXd K(A.rows() * B.rows(), A.cols() * B.cols());
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      K.block(i * B.rows(), j * B.cols(), B.rows(), B.cols()) = A(i, j) * B;
  return K;
}

std::string v_label(const std::string& label) {
  return label == "G" ? "H" : label == "D" ? "B" : label;
}

std::string w_label(const std::string& label) {
  return label == "G" ? "A" : label == "D" ? "R" : label;
}

}  // namespace cifs::automata
