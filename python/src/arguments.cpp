// SPDX-License-Identifier: MIT
// cifs Python bindings — checked arguments for every bound function. After the module is built, each
// function's pybind11 reader (function_record::impl) is wrapped by checked_call, which
// - marks the reading strict when the function has no overloads (strict_arguments): the checked casters of
//   bindings.hpp then throw ArgumentError instead of letting pybind11 try the next overload;
// - refuses a bool parameter given anything but True, False or a numpy bool (pybind11 took 2, "yes" as an
//   error only, and None as False); with overloads such parameters are noconvert instead (a TypeError);
// - turns an ArgumentError into cifs.InvalidInput naming the function and the parameter:
//   "surface_mesh: nets[1]: expected an array of real numbers, got dtype complex128".
#include <Python.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "bindings.hpp"

namespace cifs::python {
namespace {

namespace detail = pybind11::detail;
using Impl = py::handle (*)(detail::function_call&);

thread_local bool strict = false;

/// What checked_call knows of one overload of a bound function.
struct Entry {
  Impl impl = nullptr;  // pybind11's reader of the arguments, which then calls the function
  std::string who;      // "surface_mesh", "MeshStencilTable.apply", "Curve" (constructors), "Camera.fov_y"
  bool overloaded = false;              // other overloads share the name: conversions may not throw
  std::vector<std::string> names = {};  // per argument, from the signature (a setter's value: the property)
  std::vector<bool> flags = {};         // per argument: declared bool
  std::vector<long long> members = {};  // an enum's __init__ and __setstate__: the values of its members
};

/// Filled while the module is imported, read-only afterwards.
std::unordered_map<const detail::function_record*, Entry>& entries() {
  static auto* table = new std::unordered_map<const detail::function_record*, Entry>();  // never destroyed
  return *table;
}

struct Parameter {
  std::string name, type;
};

/// The parameters of a pybind11 signature "(self: X, a: int, *, b: bool = False) -> T" (markers * and /
/// dropped): split at the top-level commas, brackets and quotes of types and default values respected.
std::vector<Parameter> parameters(std::string_view signature) {
  std::vector<Parameter> out;
  if (signature.empty() || signature.front() != '(') return out;
  int depth = 0;
  char quote = 0;
  std::size_t start = 1;
  const auto add = [&](std::string_view text) {
    const std::size_t colon = text.find(": ");
    if (colon == std::string_view::npos) return;  // "*", "/"
    std::string_view type = text.substr(colon + 2);
    type = type.substr(0, type.find(" = "));
    out.push_back({std::string(text.substr(0, colon)), std::string(type)});
  };
  for (std::size_t i = 1; i < signature.size(); ++i) {
    const char c = signature[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '(' || c == '[' || c == '{' || c == '<') {
      ++depth;
    } else if ((c == ']' || c == '}' || c == '>') && depth > 0) {
      --depth;
    } else if (c == ')') {
      if (depth == 0) {
        add(signature.substr(start, i - start));
        break;
      }
      --depth;
    } else if (c == ',' && depth == 0) {
      add(signature.substr(start, i - start));
      start = i + 2;  // ", "
    }
  }
  return out;
}

bool is_bool(py::handle value) {
  static PyObject* numpy_bool =
      py::object(py::module_::import("numpy").attr("bool_")).release().ptr();  // never released
  return PyBool_Check(value.ptr()) || PyObject_IsInstance(value.ptr(), numpy_bool) == 1;
}

/// The parameter holding `value` (or `value` as an item of a list or tuple argument: "nets[1]").
std::string parameter_of(const detail::function_call& call, const Entry& entry, PyObject* value) {
  const auto name = [&](std::size_t i) { return i < entry.names.size() ? entry.names[i] : "argument"; };
  for (std::size_t i = 0; i < call.args.size(); ++i)
    if (call.args[i].ptr() == value) return name(i);
  for (std::size_t i = 0; i < call.args.size(); ++i) {
    const py::handle arg = call.args[i];
    if (!PyList_Check(arg.ptr()) && !PyTuple_Check(arg.ptr())) continue;
    const auto items = py::reinterpret_borrow<py::sequence>(arg);
    for (std::size_t k = 0; k < items.size(); ++k)
      if (items[k].ptr() == value) return name(i) + "[" + std::to_string(k) + "]";
  }
  return "argument";
}

/// pybind11 builds an enum from any integer of its underlying type (Direction(-1)): only its members' values.
void check_member(const Entry& entry, py::handle value) {
  std::string values;
  for (const long long v : entry.members) {
    if (PyLong_Check(value.ptr()) && PyLong_AsLongLong(value.ptr()) == v && !PyErr_Occurred()) return;
    values += (values.empty() ? "" : ", ") + std::to_string(v);
  }
  PyErr_Clear();
  throw InvalidInput(entry.who + ": " + entry.names.back() + ": expected one of " + values + ", got " +
                     describe(value));
}

/// Sets strict_arguments() for one call, restoring the caller's (a callback may call another function).
class StrictScope {
 public:
  explicit StrictScope(bool on) : saved_(std::exchange(strict, on)) {}
  StrictScope(const StrictScope&) = delete;
  StrictScope& operator=(const StrictScope&) = delete;
  ~StrictScope() { strict = saved_; }

 private:
  bool saved_;
};

py::handle checked_call(detail::function_call& call) {
  const Entry& entry = entries().at(&call.func);
  const StrictScope scope(!entry.overloaded);
  if (!entry.overloaded)
    for (std::size_t i = 0; i < call.args.size() && i < entry.flags.size(); ++i)
      if (entry.flags[i] && !is_bool(call.args[i]))
        throw InvalidInput(entry.who + ": " + entry.names[i] + ": expected True or False, got " +
                           describe(call.args[i]));
  if (!entry.members.empty() && !call.args.empty()) check_member(entry, call.args.back());
  try {
    return entry.impl(call);
  } catch (const ArgumentError& e) {
    throw InvalidInput(entry.who + ": " + parameter_of(call, entry, e.value) + e.path + ": " + e.detail);
  }
}

/// Wraps every overload of `function` (a pybind11 function, method or property accessor) once.
void wrap(py::handle function, const std::string& who, const std::string& value_name,
          const std::vector<long long>& members = {}) {
  function = detail::get_function(function);
  if (!function || !PyCFunction_Check(function.ptr())) return;
  const py::handle self = PyCFunction_GET_SELF(function.ptr());
  if (!self || !py::isinstance<py::capsule>(self)) return;
  const auto capsule = py::reinterpret_borrow<py::capsule>(self);
  if (!detail::is_function_record_capsule(capsule)) return;
  auto* head = capsule.get_pointer<detail::function_record>();
  if (entries().count(head)) return;
  for (auto* rec = head; rec; rec = rec->next) {
    Entry entry{.impl = rec->impl, .who = who, .overloaded = head->next != nullptr, .members = members};
    for (const Parameter& p : parameters(rec->signature ? rec->signature : "")) {
      entry.names.push_back(p.name);
      entry.flags.push_back(p.type == "bool");
    }
    if (!value_name.empty() && !entry.names.empty()) entry.names.back() = value_name;
    if (entry.overloaded)  // pybind11 then refuses anything but True, False and numpy bools (a TypeError)
      for (std::size_t i = 0; i < entry.flags.size() && i < rec->args.size(); ++i)
        if (entry.flags[i]) rec->args[i].convert = false;
    entries().emplace(rec, std::move(entry));
    rec->impl = checked_call;
  }
}

void wrap_class(py::handle type) {
  const std::string name = py::str(type.attr("__name__"));
  const py::dict dict(type.attr("__dict__"));  // a copy of the mappingproxy
  std::vector<long long> members;              // a py::enum_: its values, for __init__ and __setstate__
  if (py::hasattr(type, "__members__"))
    for (const auto& [key, member] : py::dict(type.attr("__members__")))
      members.push_back(py::int_(py::reinterpret_borrow<py::object>(member)));
  for (const auto& [key, value] : dict) {
    const std::string attribute = py::str(key);
    std::string qualified = name;
    qualified.append(1, '.').append(attribute);
    if (PyObject_TypeCheck(value.ptr(), &PyProperty_Type)) {  // the setter's value is named for the property
      wrap(value.attr("fget"), qualified, {});
      wrap(value.attr("fset"), name, attribute);
    } else if (PyObject_TypeCheck(value.ptr(), &PyStaticMethod_Type)) {
      wrap(value.attr("__func__"), qualified, {});
    } else {
      const bool construct = attribute == "__init__" || attribute == "__setstate__";
      wrap(value, attribute == "__init__" ? name : qualified, {},
           construct ? members : std::vector<long long>{});
    }
  }
}

void wrap_module(py::module_ m, std::unordered_set<PyObject*>& seen) {
  if (!seen.insert(m.ptr()).second) return;
  const std::string prefix = py::str(m.attr("__name__"));
  for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(m.attr("__dict__"))) {
    if (py::isinstance<py::module_>(value)) {
      if (std::string(py::str(value.attr("__name__"))).rfind(prefix, 0) == 0)
        wrap_module(py::reinterpret_borrow<py::module_>(value), seen);
    } else if (PyType_Check(value.ptr())) {
      if (std::string(py::str(py::getattr(value, "__module__", py::str("")))).rfind("cifs", 0) == 0)
        wrap_class(value);
    } else {
      wrap(value, py::str(key), {});
    }
  }
}

}  // namespace

bool strict_arguments() noexcept {
  return strict;
}

std::string describe(py::handle value) {
  if (value.is_none()) return "None";
  if (py::isinstance<py::array>(value)) {
    const auto a = py::reinterpret_borrow<py::array>(value);
    std::string shape = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    return "an array of dtype " + std::string(py::str(a.dtype())) + " and shape " + shape +
           (a.ndim() == 1 ? ",)" : ")");
  }
  std::string text = py::repr(value);
  if (text.size() > 40) {  // cut at a character boundary: the message must stay valid UTF-8
    std::size_t n = 37;
    while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n;
    text = text.substr(0, n) + "...";
  }
  return std::string(Py_TYPE(value.ptr())->tp_name) + " " + text;
}

void check_arguments(py::module_& m) {
  std::unordered_set<PyObject*> seen;
  wrap_module(m, seen);
}

}  // namespace cifs::python
