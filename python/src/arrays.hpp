// SPDX-License-Identifier: MIT
// cifs Python bindings — checked conversions of numpy inputs, for every binding file: a wrong shape or dtype
// is an InvalidInput naming the argument, never a silent reinterpretation of the data.
#pragma once

#include <array>
#include <climits>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "bindings.hpp"
#include "cifs/errors.hpp"
#include "cifs/mesh.hpp"
#include "cifs/types.hpp"

namespace cifs::python {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Int64s = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

inline std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) text += (i ? ", " : "") + std::to_string(a.shape(i));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

/// `object` as a numpy array, or a null array (and no pending Python error) when numpy cannot convert it.
inline py::array as_array(const py::handle& object) {
  py::array a = py::array::ensure(object);
  if (!a) PyErr_Clear();
  return a;
}

/// `object` as a numpy array whose dtype kind is one of `kinds` ('i', 'u', 'f'); InvalidInput otherwise.
inline py::array numeric(const py::handle& object, const std::string& where, const char* kinds) {
  py::array a = as_array(object);
  if (!a) throw InvalidInput(where + ": expected an array of numbers");
  const char kind = a.dtype().kind();
  if (!std::strchr(kinds, kind))
    throw InvalidInput(where + ": expected an array of " +
                       (std::strchr(kinds, 'f') ? std::string("numbers") : std::string("integers")) +
                       ", got dtype " + std::string(py::str(a.dtype())));
  return a;
}

/// A `(n, dim)` array as Points (copy).
inline Points points_from(const py::handle& object, const std::string& where) {
  const py::array a = numeric(object, where, "iuf");
  if (a.ndim() != 2)
    throw InvalidInput(where + ": expected a 2-D array (n, dim), got shape " + shape_text(a));
  const auto d = DoubleArray::ensure(a);
  Points P(d.shape(0), d.shape(1));
  if (P.size() > 0) std::memcpy(P.data(), d.data(), sizeof(double) * static_cast<std::size_t>(P.size()));
  return P;
}

/// A list of `(n, dim)` arrays.
inline std::vector<Points> nets_from(const py::handle& object, const std::string& where) {
  if (!py::isinstance<py::sequence>(object) || py::isinstance<py::str>(object))
    throw InvalidInput(where + ": expected a list of 2-D arrays");
  std::vector<Points> nets;
  std::size_t i = 0;
  for (const py::handle item : object)
    nets.push_back(points_from(item, where + "[" + std::to_string(i++) + "]"));
  return nets;
}

/// An integer table `(n, N)` (segments, triangles, quads); None or an empty array give no rows.
template <std::size_t N>
std::vector<std::array<int, N>> index_rows(const py::handle& object, const std::string& where) {
  std::vector<std::array<int, N>> rows;
  if (object.is_none()) return rows;
  const py::array any = as_array(object);
  if (any && any.size() == 0) return rows;
  const py::array a = numeric(object, where, "iu");
  if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(N))
    throw InvalidInput(where + ": expected an integer array of shape (n, " + std::to_string(N) +
                       "), got shape " + shape_text(a));
  const Int64s ints = Int64s::ensure(a);  // keep the converted copy alive while reading it
  const auto v = ints.unchecked<2>();
  rows.resize(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    for (std::size_t j = 0; j < N; ++j) {
      const std::int64_t x = v(i, static_cast<py::ssize_t>(j));
      if (x < INT_MIN || x > INT_MAX)
        throw InvalidInput(where + "[" + std::to_string(i) + "][" + std::to_string(j) +
                           "] = " + std::to_string(x) + " is out of range");
      rows[static_cast<std::size_t>(i)][j] = static_cast<int>(x);
    }
  return rows;
}

/// One uint32 per item (states); None or an empty array give none.
inline std::vector<std::uint32_t> states_from(const py::handle& object, const std::string& where) {
  std::vector<std::uint32_t> states;
  if (object.is_none()) return states;
  const py::array any = as_array(object);
  if (any && any.size() == 0) return states;
  const py::array a = numeric(object, where, "iu");
  if (a.ndim() != 1) throw InvalidInput(where + ": expected a 1-D integer array, got shape " + shape_text(a));
  const Int64s ints = Int64s::ensure(a);
  const auto v = ints.unchecked<1>();
  states.resize(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    if (v(i) < 0 || v(i) > std::int64_t{UINT32_MAX})
      throw InvalidInput(where + "[" + std::to_string(i) + "] = " + std::to_string(v(i)) +
                         " is outside 0 … 4294967295");
    states[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(v(i));
  }
  return states;
}

/// One int per item (face offsets, corners); None or an empty array give none.
inline std::vector<int> ints_from(const py::handle& object, const std::string& where) {
  std::vector<int> out;
  if (object.is_none()) return out;
  const py::array any = as_array(object);
  if (any && any.size() == 0) return out;
  const py::array a = numeric(object, where, "iu");
  if (a.ndim() != 1) throw InvalidInput(where + ": expected a 1-D integer array, got shape " + shape_text(a));
  const Int64s ints = Int64s::ensure(a);
  const auto v = ints.unchecked<1>();
  out.resize(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    if (v(i) < INT_MIN || v(i) > INT_MAX)
      throw InvalidInput(where + "[" + std::to_string(i) + "] = " + std::to_string(v(i)) +
                         " is out of range");
    out[static_cast<std::size_t>(i)] = static_cast<int>(v(i));
  }
  return out;
}

/// A mesh from the index tables of the Python API: triangles first, then quads (the order of the
/// states). Vertices are checked first, then the tables, with their own names in the messages
/// ("who: quads[0][3] = 5 is out of range (4 vertices)"), then the rest (check_mesh).
inline Mesh mesh_from_tables(Points vertices, const std::vector<std::array<int, 3>>& triangles,
                             const std::vector<std::array<int, 4>>& quads, Points normals,
                             std::vector<std::uint32_t> states, const std::string& who) {
  Mesh mesh;
  mesh.vertices = std::move(vertices);
  check_mesh(mesh, who);  // columns and finite coordinates
  const auto check_range = [&](const auto& rows, const char* what) {
    for (std::size_t f = 0; f < rows.size(); ++f)
      for (std::size_t k = 0; k < rows[f].size(); ++k)
        if (rows[f][k] < 0 || rows[f][k] >= mesh.vertices.rows())
          throw InvalidInput(who + ": " + what + "[" + std::to_string(f) + "][" + std::to_string(k) +
                             "] = " + std::to_string(rows[f][k]) + " is out of range (" +
                             std::to_string(mesh.vertices.rows()) + " vertices)");
  };
  check_range(triangles, "triangles");
  check_range(quads, "quads");
  for (const auto& t : triangles) add_face(mesh, t);
  for (const auto& q : quads) add_face(mesh, q);
  mesh.normals = std::move(normals);
  mesh.states = std::move(states);
  check_mesh(mesh, who);
  return mesh;
}

/// A size or count from a Python int: negative values are refused, not wrapped around.
inline std::size_t count_arg(std::int64_t value, const std::string& where) {
  if (value < 0) throw InvalidInput(where + " = " + std::to_string(value) + " is negative");
  return static_cast<std::size_t>(value);
}

/// An index, depth or degree from a Python int: negative values are refused.
inline int non_negative(int value, const std::string& where) {
  if (value < 0) throw InvalidInput(where + " = " + std::to_string(value) + " is negative");
  return value;
}

/// A 1-D array as a vector (copy).
inline Eigen::VectorXd to_vector(const DoubleArray& a, std::string_view where) {
  if (a.ndim() != 1)
    throw InvalidInput(std::string(where) + ": expected a 1-D array, got shape " + shape_text(a));
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.size());
}

}  // namespace cifs::python
