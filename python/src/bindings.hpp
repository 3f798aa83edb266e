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
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/types.hpp"

namespace cifs::python {

/// A value a checked conversion refused (the casters below), thrown before the parameter it was given for is
/// known: `value` is the Python object refused (a whole argument, or an item of a list or tuple argument),
/// `path` the place of the refused item inside it ("[2][0]", prefixed by each list caster on the way out).
/// The bound function reading its arguments names the parameter (checked_call, arguments.cpp):
/// cifs.InvalidInput "surface_mesh: nets[2]: expected an array of real numbers, got dtype complex128".
/// A refused item of a bound class (a wrong type, not a wrong value) is `wrong_type`: raised as TypeError.
struct ArgumentError : InvalidInput {
  ArgumentError(PyObject* refused, std::string where, const std::string& what, bool type = false)
      : InvalidInput(what), value(refused), path(std::move(where)), detail(what), wrong_type(type) {}
  PyObject* value;  // borrowed: compared with the call's arguments, never dereferenced
  std::string path;
  std::string detail;
  bool wrong_type;
};

/// True while a bound function without overloads reads its arguments (arguments.cpp): a conversion then
/// refuses a value by throwing ArgumentError. With overloads it returns false, so that pybind11 tries the
/// next overload and raises TypeError (listing the signatures) when none takes the arguments.
bool strict_arguments() noexcept;

/// A refused value for messages: "str 'abc'", "float 1.5", "an array of dtype complex128 and shape (3,)".
std::string describe(pybind11::handle value);

/// Refuses `value` (see strict_arguments): throws ArgumentError, or returns false for the next overload.
inline bool refuse(pybind11::handle value, const std::string& what, std::string path = {},
                   bool wrong_type = false) {
  if (strict_arguments()) throw ArgumentError(value.ptr(), std::move(path), what, wrong_type);
  return false;
}

/// A bound class as a message names it: "cifs.render.Camera" (the public module, not cifs._cifs.render).
std::string class_name(PyTypeObject* type);

/// `src` as a numpy array of real numbers (dtype kind f, i or u). A complex or bool array throws
/// ArgumentError (never cast, even for another overload); anything else is refused (see refuse) and
/// gives a null array.
inline pybind11::array real_array(pybind11::handle src) {
  pybind11::array a = pybind11::array::ensure(src);
  if (!a) PyErr_Clear();
  const char kind = a ? a.dtype().kind() : '\0';
  if (kind == 'c' || kind == 'b')
    throw ArgumentError(
        src.ptr(), {},
        "expected an array of real numbers, got dtype " + std::string(pybind11::str(a.dtype())));
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    refuse(src, "expected an array of real numbers, got " + describe(src));
    return pybind11::reinterpret_steal<pybind11::array>(
        pybind11::handle());  // null (array{} is a 0-size array)
  }
  return a;
}

}  // namespace cifs::python

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
// a matrix a 2-D array (a 1-D one is a column); results are new arrays that own their copy. Other
// values (a string, a ragged list, a wrong shape) are refused as `cifs::python::refuse` says.
template <class Type>
class RealArrayCaster {
  static constexpr bool kRow = Type::RowsAtCompileTime == 1, kColumn = Type::ColsAtCompileTime == 1;
  static constexpr bool kFixed = Type::SizeAtCompileTime != Eigen::Dynamic;

 public:
  PYBIND11_TYPE_CASTER(
      Type, const_name<kRow>(const_name("numpy.ndarray[numpy.float64[1, n]]"),
                             const_name<kColumn>(const_name("numpy.ndarray[numpy.float64[m, 1]]"),
                                                 const_name("numpy.ndarray[numpy.float64[m, n]]"))));

  bool load(handle src, bool convert) {
    using cifs::python::refuse;
    // The first overload pass takes float64 arrays only, as pybind11's own caster.
    if (!convert && !isinstance<array_t<double>>(src)) return false;
    const array a = cifs::python::real_array(src);
    if (!a) return false;
    Eigen::Index rows = 0, cols = 0;
    if (a.ndim() == 1) {
      rows = kRow ? 1 : a.shape(0);
      cols = kRow ? a.shape(0) : 1;
    } else if (a.ndim() == 2 && !(kRow && a.shape(0) != 1) && !(kColumn && a.shape(1) != 1)) {
      rows = a.shape(0);
      cols = a.shape(1);
    } else {
      return refuse(src, std::string(kRow || kColumn ? "expected a 1-D array" : "expected a 2-D array") +
                             ", got " + cifs::python::describe(src));
    }
    if (kFixed && (rows != Type::RowsAtCompileTime || cols != Type::ColsAtCompileTime))
      return refuse(src, "expected " + std::to_string(Type::SizeAtCompileTime) + " numbers, got " +
                             cifs::python::describe(src));
    const auto c = array_t<double, array::c_style | array::forcecast>::ensure(a);
    if (!c) {
      PyErr_Clear();
      return refuse(src, "expected an array of real numbers, got " + cifs::python::describe(src));
    }
    if constexpr (!kFixed) value.resize(rows, cols);
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
// Fixed sizes (results such as nurbs.normal, and any future parameter): the same checks and the size.
template <>
class type_caster<Eigen::Vector2d> : public RealArrayCaster<Eigen::Vector2d> {};
template <>
class type_caster<Eigen::Vector3d> : public RealArrayCaster<Eigen::Vector3d> {};
template <>
class type_caster<Eigen::Matrix2d> : public RealArrayCaster<Eigen::Matrix2d> {};
template <>
class type_caster<Eigen::Matrix3d> : public RealArrayCaster<Eigen::Matrix3d> {};

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

// Integers: Python ints and objects with __index__ (numpy integers), range-checked for the C++ type.
// pybind11's caster refused -1 for a size_t, 2**64 and 1.5 only with a TypeError listing the signatures;
// these name the value and its range. numpy booleans are refused (Python's True stays the int 1).
template <class T>
class IntegerCaster {
 public:
  PYBIND11_TYPE_CASTER(T, const_name("int"));

  bool load(handle src, bool /*convert*/) {
    using cifs::python::refuse;
    PyObject* p = src.ptr();
    const auto integer = [&] { return "expected an integer, got " + cifs::python::describe(src); };
    if (!p || PyFloat_Check(p) || !(PyLong_Check(p) || PyIndex_Check(p)) ||
        (!PyLong_Check(p) && hasattr(src, "dtype") &&
         str(src.attr("dtype").attr("kind")).cast<std::string>() == "b"))
      return refuse(src, integer());
    const auto index = reinterpret_steal<object>(PyNumber_Index(p));
    if (!index) {
      PyErr_Clear();
      return refuse(src, integer());
    }
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if (overflow == 0 && v == -1 && PyErr_Occurred()) {
      PyErr_Clear();
      return refuse(src, integer());
    }
    using Limits = std::numeric_limits<T>;
    if (overflow == 0 && (!std::is_unsigned_v<T> || v >= 0) &&
        (std::is_unsigned_v<T> || v >= static_cast<long long>(Limits::min())) &&
        (v < 0 || static_cast<unsigned long long>(v) <= static_cast<unsigned long long>(Limits::max()))) {
      value = static_cast<T>(v);
      return true;
    }
    if (overflow > 0 && std::is_unsigned_v<T>) {
      const unsigned long long u = PyLong_AsUnsignedLongLong(index.ptr());
      if (!PyErr_Occurred() && u <= static_cast<unsigned long long>(Limits::max())) {
        value = static_cast<T>(u);
        return true;
      }
      PyErr_Clear();
    }
    return refuse(src, "expected an integer in " + std::to_string(Limits::min()) + " … " +
                           std::to_string(Limits::max()) + ", got " + str(index).cast<std::string>());
  }

  static handle cast(T src, return_value_policy /*policy*/, handle /*parent*/) {
    if constexpr (std::is_unsigned_v<T>) return PyLong_FromUnsignedLongLong(src);
    return PyLong_FromLongLong(src);
  }
};

template <>
class type_caster<int> : public IntegerCaster<int> {};
template <>
class type_caster<unsigned> : public IntegerCaster<unsigned> {};
template <>
class type_caster<long> : public IntegerCaster<long> {};
template <>
class type_caster<unsigned long> : public IntegerCaster<unsigned long> {};
template <>
class type_caster<long long> : public IntegerCaster<long long> {};
template <>
class type_caster<unsigned long long> : public IntegerCaster<unsigned long long> {};

// Real numbers: Python floats and ints, numpy real scalars, and other numbers with __float__ (Fraction,
// Decimal). pybind11's caster also took numpy complex scalars (dropping the imaginary part with a
// ComplexWarning), numpy booleans and one-element arrays; those are refused. Finiteness is the library's
// check.
template <class T>
class RealCaster {
 public:
  PYBIND11_TYPE_CASTER(T, const_name("float"));

  bool load(handle src, bool convert) {
    using cifs::python::refuse;
    PyObject* p = src.ptr();
    if (!p) return false;
    if (PyFloat_Check(p)) {
      value = static_cast<T>(PyFloat_AsDouble(p));
      return true;
    }
    if (!convert) return false;  // the first overload pass, as pybind11's caster
    const auto number = [&] { return "expected a real number, got " + cifs::python::describe(src); };
    if (hasattr(src, "dtype")) {  // numpy scalars and arrays: real scalars only
      const auto kind = str(src.attr("dtype").attr("kind")).cast<std::string>();
      if ((kind != "f" && kind != "i" && kind != "u") || getattr(src, "ndim", int_(0)).cast<long>() != 0)
        return refuse(src, number());
    } else if (!PyLong_Check(p) &&
               (PyComplex_Check(p) || !PyNumber_Check(p) || Py_TYPE(p)->tp_as_number->nb_float == nullptr)) {
      return refuse(src, number());
    }
    const auto f = reinterpret_steal<object>(PyNumber_Float(p));
    if (!f) {
      PyErr_Clear();
      return refuse(src, number());
    }
    value = static_cast<T>(PyFloat_AsDouble(f.ptr()));
    return true;
  }

  static handle cast(T src, return_value_policy /*policy*/, handle /*parent*/) {
    return PyFloat_FromDouble(static_cast<double>(src));
  }
};

template <>
class type_caster<double> : public RealCaster<double> {};
template <>
class type_caster<float> : public RealCaster<float> {};

// Arrays taken as numpy arrays (arrays.hpp's DoubleArray: points of polylines, polygons, meshes): pybind11
// force-casts any dtype, so complex lost its imaginary part and booleans became 0/1; here as RealArrayCaster,
// any shape (the binding checks it and names the argument).
template <>
class type_caster<array_t<double, array::c_style | array::forcecast>> {
  using Type = array_t<double, array::c_style | array::forcecast>;

 public:
  PYBIND11_TYPE_CASTER(Type, handle_type_name<Type>::name);

  bool load(handle src, bool convert) {
    if (!convert && !Type::check_(src)) return false;
    const array a = cifs::python::real_array(src);
    if (!a) return false;
    value = Type::ensure(a);
    if (!value) PyErr_Clear();
    return static_cast<bool>(value);
  }

  static handle cast(const handle& src, return_value_policy /*policy*/, handle /*parent*/) {
    return src.inc_ref();
  }
};

/// What a list item must be, for messages.
template <class Value>
std::string expected_item() {
  if constexpr (std::is_same_v<Value, bool>) return "True or False";
  if constexpr (std::is_integral_v<Value>) return "an integer";
  if constexpr (std::is_floating_point_v<Value>) return "a real number";
  if constexpr (std::is_base_of_v<type_caster_generic,
                                  make_caster<Value>>) {  // a bound class: its Python name
    const type_info* info = get_type_info(typeid(Value));
    return "a " + (info ? cifs::python::class_name(info->type) : type_id<Value>());
  }
  return std::string(make_caster<Value>::name.text);
}

/// `item`, the `k`-th of `whole`, loaded and handed to `store`; a refusal of the item (its own, or here) is
/// rebased onto `whole` with the place `[k]`. An item that is no instance of a bound class is a wrong type.
template <class Value, class Store>
bool load_item(handle whole, handle item, std::size_t k, bool convert, Store&& store) {
  make_caster<Value> conv;
  const std::string at = "[" + std::to_string(k) + "]";
  bool loaded = false;
  try {  // a bound class reads None as a null pointer, which cast_op then refuses (reference_cast_error)
    loaded = !(std::is_base_of_v<type_caster_generic, make_caster<Value>> && item.is_none()) &&
             conv.load(item, convert);
  } catch (cifs::python::ArgumentError& e) {
    e.value = whole.ptr();
    e.path = at + e.path;
    throw;
  }
  if (!loaded)
    return cifs::python::refuse(
        whole, "expected " + expected_item<Value>() + ", got " + cifs::python::describe(item), at,
        std::is_base_of_v<type_caster_generic, make_caster<Value>>);
  store(cast_op<Value&&>(std::move(conv)));
  return true;
}

/// A list, tuple or array as a sequence of items; strings, bytes, scalars and complex arrays refused.
template <class Value>
bool check_sequence(handle src) {
  using cifs::python::refuse;
  if (!isinstance<sequence>(src) || isinstance<bytes>(src) || isinstance<str>(src)) {
    constexpr bool kBound = std::is_base_of_v<type_caster_generic, make_caster<Value>>;  // a wrong type
    const std::string list = kBound ? "a list of " + expected_item<Value>().substr(2) : "a list";
    return refuse(src, "expected " + list + ", got " + cifs::python::describe(src), {}, kBound);
  }
  if (isinstance<array>(src)) {
    const auto a = reinterpret_borrow<array>(src);
    const char kind = a.dtype().kind();
    if (kind == 'c')
      throw cifs::python::ArgumentError(src.ptr(), {},
                                        "expected real numbers, got dtype " + std::string(str(a.dtype())));
    if constexpr (std::is_arithmetic_v<Value> && !std::is_same_v<Value, bool>) {
      const bool integral = std::is_integral_v<Value>;
      if (a.ndim() != 1 || !std::strchr(integral ? "iu" : "iuf", kind))
        return refuse(src, std::string(integral ? "expected a 1-D array of integers"
                                                : "expected a 1-D array of numbers") +
                               ", got " + cifs::python::describe(src));
    }
  }
  return true;
}

// Lists (List[float], List[int], lists of arrays, of pairs, …): pybind11's list caster refused a string or a
// wrong item with a TypeError listing the signatures, and took the rows of a 2-D array or the items of a
// complex array one by one; here the items are checked and a refusal names the item ("knots[3]").
template <class Vector, class Value>
struct CheckedListCaster : list_caster<Vector, Value> {
  bool load(handle src, bool convert) {
    if (!check_sequence<Value>(src)) return false;
    const auto items = reinterpret_borrow<sequence>(src);
    this->value.clear();
    this->value.reserve(items.size());
    std::size_t k = 0;
    for (const auto& item : items)
      if (!load_item<Value>(src, item, k++, convert,
                            [&](auto&& v) { this->value.push_back(std::forward<decltype(v)>(v)); }))
        return false;
    return true;
  }
};

template <class Value>
struct type_caster<std::vector<Value, std::allocator<Value>>> : CheckedListCaster<std::vector<Value>, Value> {
};

/// std::array<Value, N> from a sequence of exactly N items, checked as the lists above.
template <class Value, std::size_t N>
struct StrictArrayCaster : array_caster<std::array<Value, N>, Value, false, N> {
  bool load(handle src, bool convert) {
    if (!check_sequence<Value>(src)) return false;
    const auto items = reinterpret_borrow<sequence>(src);
    if (items.size() != N)
      return cifs::python::refuse(
          src, "expected " + std::to_string(N) + " items, got " + cifs::python::describe(src));
    for (std::size_t k = 0; k < N; ++k)
      if (!load_item<Value>(src, items[k], k, convert,
                            [&](auto&& v) { this->value[k] = std::forward<decltype(v)>(v); }))
        return false;
    return true;
  }
};

template <std::size_t N>
struct type_caster<std::array<int, N>> : StrictArrayCaster<int, N> {};
template <std::size_t N>
struct type_caster<std::array<long, N>> : StrictArrayCaster<long, N> {};
template <std::size_t N>
struct type_caster<std::array<double, N>> : StrictArrayCaster<double, N> {};
template <std::size_t N>
struct type_caster<std::array<std::vector<double>, N>> : StrictArrayCaster<std::vector<double>, N> {};
}  // namespace pybind11::detail

namespace cifs::python {

namespace py = pybind11;

/// `value`, read inside a function's body (a key or value of a dict argument), as T, checked as the argument
/// casters check arguments: a refusal is the TypeError naming the parameter and the place holding `value`
/// ("named_scheme: parameters[1]: expected a str, got int 1", checked_call), never pybind11's RuntimeError
/// "Unable to cast Python instance". `expected` says what is taken: "a str".
template <class T>
T checked_cast(py::handle value, const std::string& expected) {
  py::detail::make_caster<T> conv;
  if (!conv.load(value, true)) {
    const std::string what = "expected " + expected + ", got " + describe(value);
    refuse(value, what, {}, true);
    throw py::type_error(what);  // outside a checked call
  }
  return py::detail::cast_op<T>(std::move(conv));
}

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
void bind_io_types(py::module_& m);  // cifs.Mesh and cifs.Segments, before every signature that names them
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
/// Wraps every function of the built module `m` so that its arguments are checked (arguments.cpp); last.
void check_arguments(py::module_& m);

}  // namespace cifs::python
