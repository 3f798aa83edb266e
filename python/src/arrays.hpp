// SPDX-License-Identifier: MIT
// cifs Python bindings — checked conversions of numpy inputs (nurbs.cpp, io.cpp): a wrong shape is
// an InvalidInput naming the argument, never a silent reinterpretation of the data.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "bindings.hpp"
#include "cifs/errors.hpp"
#include "cifs/types.hpp"

namespace cifs::python {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

inline std::string shape_text(const py::array& a) {
  std::string out = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) out += (k ? ", " : "") + std::to_string(a.shape(k));
  return out + (a.ndim() == 1 ? ",)" : ")");
}

/// A `(n, dim)` array as Points (copy); `where` names the argument in the message.
inline Points to_points(const DoubleArray& a, std::string_view where) {
  if (a.ndim() != 2)
    throw InvalidInput(std::string(where) + ": expected a 2-D array (n, dim), got shape " + shape_text(a));
  Points P(a.shape(0), a.shape(1));
  std::copy_n(a.data(), a.size(), P.data());
  return P;
}

/// A 1-D array as a vector (copy).
inline Eigen::VectorXd to_vector(const DoubleArray& a, std::string_view where) {
  if (a.ndim() != 1)
    throw InvalidInput(std::string(where) + ": expected a 1-D array, got shape " + shape_text(a));
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.size());
}

/// A `(n, N)` integer array as index tuples (an empty list for None).
template <typename T, std::size_t N>
std::vector<std::array<T, N>> to_rows(const py::object& obj, std::string_view where) {
  std::vector<std::array<T, N>> rows;
  if (obj.is_none()) return rows;
  const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a)
    throw InvalidInput(std::string(where) + ": expected an integer array (n, " + std::to_string(N) + ")");
  // An empty list has shape (0,): no rows, whatever N.
  if (a.size() == 0 && a.ndim() <= 2) return rows;
  if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(N))
    throw InvalidInput(std::string(where) + ": expected an integer array (n, " + std::to_string(N) +
                       "), got shape " + shape_text(a));
  rows.resize(static_cast<std::size_t>(a.shape(0)));
  std::copy_n(a.data(), a.size(), rows.front().data());
  return rows;
}

}  // namespace cifs::python
