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
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/nurbs/knot_automaton.hpp"

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
