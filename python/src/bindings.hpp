// SPDX-License-Identifier: MIT
// cifs Python bindings — what every binding file shares. Conventions (docs/python.md):
// - one submodule per C++ namespace (cifs.nurbs, cifs.automata, …); functions keep their C++ names;
// - an options struct becomes keyword-only arguments with the struct's field names and defaults;
// - plain-data inputs (Curve, Surface, Automaton, Scheme, …) are classes whose constructors
//   validate; results are read-only classes with properties and a __repr__;
// - Points ↔ float64 numpy arrays `(n, dim)` (copies); index lists ↔ integer numpy arrays;
// - library errors reach Python as cifs.InvalidInput (a ValueError) and cifs.IoError (an OSError)
//   with the C++ message unchanged; checks made here raise the same types, in the same style;
// - long computations release the GIL;
// - every function, class and property has a docstring.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/types.hpp"

// Python has one automaton class, cifs.automata.Automaton, bound to nurbs::KnotAutomaton (an
// automaton with its knot data; hand-made ones have none), so that `state.window` and
// `initial[i].start` stay where Python users find them. Every binding that takes a C++
// automata::Automaton reads it from that class (a reference to its `automaton` member: in-place
// changes such as mark_recurrent reach the Python object); one returned becomes an Automaton
// without knot data. The specialisation is seen by every binding file (they all include this one).
namespace pybind11::detail {
template <>
class type_caster<cifs::automata::Automaton> {
  using Knots = cifs::nurbs::KnotAutomaton;
  type_caster_base<Knots> knots_;

 public:
  // NOLINTNEXTLINE(readability-identifier-naming): the member pybind11 reads for signatures
  static constexpr auto name = type_caster_base<Knots>::name;

  bool load(handle src, bool convert) { return knots_.load(src, convert); }

  static handle cast(const cifs::automata::Automaton& automaton, return_value_policy /*policy*/,
                     handle parent) {
    return type_caster_base<Knots>::cast(cifs::nurbs::without_knots(automaton), return_value_policy::move,
                                         parent);
  }
  static handle cast(const cifs::automata::Automaton* automaton, return_value_policy policy, handle parent) {
    return automaton ? cast(*automaton, policy, parent) : none().release();
  }

  template <typename T>
  using cast_op_type = pybind11::detail::cast_op_type<T>;
  // NOLINTNEXTLINE(google-explicit-constructor): pybind11's caster protocol
  operator cifs::automata::Automaton*() {
    Knots* knots = knots_;
    return knots ? &knots->automaton : nullptr;
  }
  // NOLINTNEXTLINE(google-explicit-constructor): pybind11's caster protocol
  operator cifs::automata::Automaton&() { return static_cast<Knots&>(knots_).automaton; }
};

// Real arrays: the float64 matrices and vectors of the library (Points, Point, MatrixXd, VectorXd)
// cross as numpy arrays, copied. pybind11's Eigen caster converts any dtype numpy can cast to
// float64, so a complex array lost its imaginary part with a mere ComplexWarning and a boolean one
// became 0/1; here numbers (float, int, unsigned) convert and complex or boolean arrays are
// refused with InvalidInput. Shapes as pybind11's: a vector takes a 1-D array (or one row / column),
// a matrix a 2-D array (a 1-D one is a column); results are new arrays that own their copy.
template <class Type>
class RealArrayCaster {
  static constexpr bool kRow = Type::RowsAtCompileTime == 1, kColumn = Type::ColsAtCompileTime == 1;

 public:
  PYBIND11_TYPE_CASTER(
      Type, const_name<kRow>(const_name("numpy.ndarray[numpy.float64[1, n]]"),
                             const_name<kColumn>(const_name("numpy.ndarray[numpy.float64[m, 1]]"),
                                                 const_name("numpy.ndarray[numpy.float64[m, n]]"))));

  bool load(handle src, bool convert) {
    // The first overload pass takes float64 arrays only, as pybind11's own caster.
    if (!convert && !isinstance<array_t<double>>(src)) return false;
    array a = array::ensure(src);
    if (!a) {
      PyErr_Clear();
      return false;
    }
    const char kind = a.dtype().kind();
    if (kind == 'c' || kind == 'b')
      throw cifs::InvalidInput("expected an array of real numbers, got dtype " + std::string(str(a.dtype())));
    if (kind != 'f' && kind != 'i' && kind != 'u') return false;
    Eigen::Index rows = 0, cols = 0;
    if (a.ndim() == 1) {
      rows = kRow ? 1 : a.shape(0);
      cols = kRow ? a.shape(0) : 1;
    } else if (a.ndim() == 2) {
      rows = a.shape(0);
      cols = a.shape(1);
      if ((kRow && rows != 1) || (kColumn && cols != 1)) return false;
    } else {
      return false;
    }
    const auto c = array_t<double, array::c_style | array::forcecast>::ensure(a);
    if (!c) {
      PyErr_Clear();
      return false;
    }
    value.resize(rows, cols);
    const double* in = c.data();
    for (Eigen::Index i = 0; i < rows; ++i)
      for (Eigen::Index j = 0; j < cols; ++j) value(i, j) = in[i * cols + j];
    return true;
  }

  static handle cast(const Type& src, return_value_policy /*policy*/, handle /*parent*/) {
    return owned(new Type(src));
  }
  static handle cast(Type&& src, return_value_policy /*policy*/, handle /*parent*/) {
    return owned(new Type(std::move(src)));
  }

 private:
  /// An array over `heap`, which a capsule deletes with the array.
  static handle owned(Type* heap) {
    const capsule owner(heap, [](void* p) { delete static_cast<Type*>(p); });
    constexpr auto kItem = static_cast<ssize_t>(sizeof(double));
    if constexpr (kRow || kColumn)
      return array_t<double>({static_cast<ssize_t>(heap->size())}, {kItem}, heap->data(), owner).release();
    const auto rows = static_cast<ssize_t>(heap->rows()), cols = static_cast<ssize_t>(heap->cols());
    const std::vector<ssize_t> strides = Type::IsRowMajor ? std::vector<ssize_t>{cols * kItem, kItem}
                                                          : std::vector<ssize_t>{kItem, rows * kItem};
    return array_t<double>({rows, cols}, strides, heap->data(), owner).release();
  }
};

template <>
class type_caster<cifs::Points> : public RealArrayCaster<cifs::Points> {};
template <>
class type_caster<Eigen::MatrixXd> : public RealArrayCaster<Eigen::MatrixXd> {};
template <>
class type_caster<Eigen::VectorXd> : public RealArrayCaster<Eigen::VectorXd> {};
template <>
class type_caster<cifs::Point> : public RealArrayCaster<cifs::Point> {};

// Functions bound by pointer that read points through Eigen::Ref (ifs::cartesian, …) take the same
// checked copy.
template <>
class type_caster<Eigen::Ref<const cifs::Points>> {
  type_caster<cifs::Points> points_;
  std::optional<Eigen::Ref<const cifs::Points>> ref_;

 public:
  // NOLINTNEXTLINE(readability-identifier-naming): the member pybind11 reads for signatures
  static constexpr auto name = type_caster<cifs::Points>::name;

  bool load(handle src, bool convert) {
    if (!points_.load(src, convert)) return false;
    ref_.emplace(static_cast<cifs::Points&>(points_));
    return true;
  }

  template <typename>
  using cast_op_type = Eigen::Ref<const cifs::Points>&;
  // NOLINTNEXTLINE(google-explicit-constructor): pybind11's caster protocol
  operator Eigen::Ref<const cifs::Points>&() { return *ref_; }
};
}  // namespace pybind11::detail

namespace cifs::python {

namespace py = pybind11;

/// A list of fixed-size index tuples as an integer array `(n, N)` (quads, segments, …).
template <typename T, std::size_t N>
py::array_t<T> index_array(const std::vector<std::array<T, N>>& rows) {
  py::array_t<T> out({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(N)});
  auto view = out.template mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < N; ++j)
      view(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = rows[i][j];
  return out;
}

/// `a` marked read-only. Arrays read from an object are copies, so a write into one would be lost: the
/// attributes of every bound type return read-only arrays (python/cifs/__init__.py applies it to every
/// property), and so do dict-like views such as Image.channels (docs/python.md, "Arrays").
template <typename Array>
Array read_only(Array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

/// A vector as a 1-D numpy array (copy).
template <typename T>
py::array_t<T> vector_array(const std::vector<T>& values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

void bind_nurbs(py::module_& m);
void bind_io(py::module_& m);
void bind_verify(py::module_& m);
void bind_experiment(py::module_& m);
void bind_automata(py::module_& m);
void bind_ifs(py::module_& m);
void bind_bcifs(py::module_& m);        // into cifs.ifs
void bind_bcifs_io(py::module_& m);     // BC-IFS files, into cifs.io
void bind_io_dispatch(py::module_& m);  // the format table, write and encode, into cifs.io
void bind_subdivision(py::module_& m);
void bind_mesh_subdivision(py::module_& m);  // into cifs.subdivision
void bind_render(py::module_& m);

}  // namespace cifs::python
