// SPDX-License-Identifier: MIT
// cifs Python bindings — checked arguments for every bound function. After the module is built, each
// function's pybind11 reader (function_record::impl) is wrapped by checked_call, which
// - marks the reading strict when the function has no overloads (strict_arguments): the checked casters of
//   bindings.hpp then throw ArgumentError instead of letting pybind11 try the next overload;
// - refuses a bool parameter given anything but True, False or a numpy bool (pybind11 took 2, "yes" as an
//   error only, and None as False); with overloads such parameters are noconvert instead (a TypeError);
// - turns an ArgumentError into cifs.InvalidInput naming the function and the parameter:
//   "surface_mesh: nets[1]: expected an array of real numbers, got dtype complex128";
// - when pybind11 could not read the arguments of a function without overloads (a bound class, str, path,
//   callable or dict parameter given another object: pybind11's casters for those refuse by returning false),
//   finds the argument refused from the signature's types and raises a TypeError naming it:
//   "render_mesh: camera: expected a cifs.render.Camera, got int 3". pybind11 reads the arguments in order
//   and stops at the first refused one, so the first argument that does not fit its type is the one.
// It reads pybind11's internals (pybind11::detail): python/CMakeLists.txt pins their minor version.
#include <Python.h>

#include <cstddef>
#include <optional>
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

/// A parameter's type as the signature spells it, as far as checked_call tests arguments against it.
/// `any` for the types whose casters refuse with a message of their own (numbers, arrays, lists:
/// bindings.hpp) or take everything (object).
struct Type {
  enum class Kind {
    any,
    bound,
    str,
    path,
    function,
    callable,
    dict,
    iterable,
    list,
    tuple,
    map,
    optional,
    one_of
  };
  Kind kind = Kind::any;
  PyTypeObject* bound = nullptr;  // a bound class (none when it converts implicitly from other types)
  std::string text;               // what a refusal says was expected: "a cifs.render.Camera", "a str"
  std::vector<Type> items = {};   // list, optional: the item; tuple: each; map: key, value; one_of: each
};

/// The bound classes by the names signatures give them: "cifs._cifs.render.Camera" (module and qualified
/// name), and "cifs::Mesh" for a class bound after the function whose signature names it.
using Classes = std::unordered_map<std::string, PyTypeObject*>;

/// What checked_call knows of one overload of a bound function.
struct Entry {
  Impl impl = nullptr;  // pybind11's reader of the arguments, which then calls the function
  std::string who;      // "surface_mesh", "MeshStencilTable.apply", "Curve" (constructors), "Camera.fov_y"
  bool overloaded = false;              // other overloads share the name: conversions may not throw
  std::vector<std::string> names = {};  // per argument, from the signature (a setter's value: the property)
  std::vector<bool> flags = {};         // per argument: declared bool
  std::vector<long long> members = {};  // an enum's __init__ and __setstate__: the values of its members
  std::vector<Type> expected = {};      // per argument: its type in the signature, read (see Type)
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

/// "A, B[C, D], E" split at its top-level commas.
std::vector<std::string_view> split_top(std::string_view text) {
  std::vector<std::string_view> out;
  int depth = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '[') ++depth;
    if (text[i] == ']') --depth;
    if (text[i] == ',' && depth == 0) {
      out.push_back(text.substr(start, i - start));
      start = i + 1;
      while (start < text.size() && text[start] == ' ') ++start;
    }
  }
  out.push_back(text.substr(start));
  return out;
}

/// `text` as a Type ("Optional[List[cifs._cifs.ifs.AffineMap]]", "os.PathLike", "function", …).
Type read_type(std::string_view text, const Classes& classes) {
  using Kind = Type::Kind;
  const auto generic = [&](std::string_view name) {  // "List[" … "]": the inner text, or empty
    return text.size() > name.size() + 2 && text.substr(0, name.size()) == name && text[name.size()] == '[' &&
                   text.back() == ']'
               ? text.substr(name.size() + 1, text.size() - name.size() - 2)
               : std::string_view();
  };
  const auto read_all = [&](std::string_view inner) {
    std::vector<Type> out;
    for (const std::string_view item : split_top(inner)) out.push_back(read_type(item, classes));
    return out;
  };
  if (const auto inner = generic("Optional"); !inner.empty()) {
    Type item = read_type(inner, classes);
    return {.kind = Kind::optional, .text = item.text + " or None", .items = {item}};
  }
  if (const auto inner = generic("List"); !inner.empty())
    return {.kind = Kind::list, .text = "a list", .items = {read_type(inner, classes)}};
  if (auto inner = generic("Tuple"); !inner.empty() || !(inner = generic("tuple")).empty()) {
    std::vector<Type> items = read_all(inner);
    const std::string expected = "a sequence of " + std::to_string(items.size()) + " items";
    return {.kind = Kind::tuple, .text = expected, .items = std::move(items)};
  }
  if (const auto inner = generic("Dict"); !inner.empty()) {
    std::vector<Type> items = read_all(inner);
    if (items.size() == 2) return {.kind = Kind::map, .text = "a dict", .items = std::move(items)};
  }
  if (const auto inner = generic("Union"); !inner.empty()) {
    Type type{.kind = Kind::one_of, .text = {}, .items = read_all(inner)};
    for (const Type& item : type.items) {
      if (item.kind == Kind::any) return {};
      type.text += (type.text.empty() ? "" : " or ") + item.text;
    }
    return type;
  }
  if (text == "str") return {.kind = Kind::str, .text = "a str"};
  if (text == "os.PathLike") return {.kind = Kind::path, .text = "a str or os.PathLike"};
  if (text == "function") return {.kind = Kind::function, .text = "a callable"};  // py::function: not None
  if (!generic("Callable").empty()) return {.kind = Kind::callable, .text = "a callable"};
  if (text == "dict") return {.kind = Kind::dict, .text = "a dict"};
  if (text == "Iterable") return {.kind = Kind::iterable, .text = "an iterable"};
  if (const auto it = classes.find(std::string(text)); it != classes.end() && it->second)
    return {.kind = Kind::bound, .bound = it->second, .text = "a " + class_name(it->second)};
  return {};
}

/// Where `value` does not fit `type`: the place inside it ("", "[1]", "['key']") and what was expected.
/// `value` is owned: an item read from a sequence (`__getitem__`) may exist only as long as it is held.
struct Misfit {
  std::string path, expected;
  py::object value;
};

/// repr(value), or a placeholder when its __repr__ raises or returns text that is not UTF-8 (the error is
/// cleared: a message about a wrong argument must not become the error of its repr).
std::string safe_repr(py::handle value) {
  try {
    return py::repr(value);
  } catch (const py::error_already_set&) {  // fetched, so cleared
    return std::string("<") + Py_TYPE(value.ptr())->tp_name + " object, repr failed>";
  }
}

/// The first place where `value` does not fit `type`, as pybind11's casters read it. None fits a bound class
/// (read as a null pointer) unless `none_refused`: pybind11 then failed to pass a null pointer as a
/// reference.
std::optional<Misfit> misfit(const Type& type, py::handle value, bool none_refused) {
  using Kind = Type::Kind;
  const auto refused = [&] {
    return std::optional<Misfit>(
        Misfit{.path = {}, .expected = type.text, .value = py::reinterpret_borrow<py::object>(value)});
  };
  const auto inside = [&](std::optional<Misfit> m, const std::string& at) {
    if (m) m->path = at + m->path;
    return m;
  };
  PyObject* object = value.ptr();
  switch (type.kind) {
    case Kind::any:
      return std::nullopt;
    case Kind::bound:  // by the real type, as pybind11 reads it (PyObject_IsInstance runs __class__)
      if (value.is_none()) return none_refused ? refused() : std::nullopt;
      return PyObject_TypeCheck(object, type.bound) ? std::nullopt : refused();
    case Kind::str:  // pybind11's std::string caster: a str (UTF-8 encodable), bytes or bytearray
      if (PyBytes_Check(object) || PyByteArray_Check(object)) return std::nullopt;
      if (PyUnicode_Check(object) && PyUnicode_AsUTF8AndSize(object, nullptr)) return std::nullopt;
      PyErr_Clear();
      return refused();
    case Kind::path: {  // pybind11's path caster: os.fspath, then a file system encoding without NUL
      const py::object path = py::reinterpret_steal<py::object>(PyOS_FSPath(object));
      PyObject* bytes = nullptr;
      const bool encoded = path && PyUnicode_FSConverter(path.ptr(), &bytes) != 0;
      Py_XDECREF(bytes);
      PyErr_Clear();
      if (encoded) return std::nullopt;
      if (!path) return refused();
      return Misfit{.path = {},
                    .expected = type.text + " without NUL characters",
                    .value = py::reinterpret_borrow<py::object>(value)};
    }
    case Kind::function:
      return PyCallable_Check(object) ? std::nullopt : refused();
    case Kind::callable:  // None is an empty std::function
      return value.is_none() || PyCallable_Check(object) ? std::nullopt : refused();
    case Kind::dict:
      return PyDict_Check(object) ? std::nullopt : refused();
    case Kind::iterable: {
      const py::object iterator = py::reinterpret_steal<py::object>(PyObject_GetIter(object));
      PyErr_Clear();
      return iterator ? std::nullopt : refused();
    }
    case Kind::optional:
      return value.is_none() ? std::nullopt : misfit(type.items.front(), value, none_refused);
    case Kind::one_of:
      for (const Type& item : type.items)
        if (!misfit(item, value, none_refused)) return std::nullopt;
      return refused();
    case Kind::list:
    case Kind::tuple: {
      if (!PySequence_Check(object) || PyUnicode_Check(object) || PyBytes_Check(object)) return refused();
      const auto items = py::reinterpret_borrow<py::sequence>(value);
      if (type.kind == Kind::tuple && items.size() != type.items.size()) return refused();
      for (std::size_t k = 0; k < items.size(); ++k) {
        const Type& item = type.kind == Kind::list ? type.items.front() : type.items[k];
        if (auto m = inside(misfit(item, items[k], none_refused), "[" + std::to_string(k) + "]")) return m;
      }
      return std::nullopt;
    }
    case Kind::map: {
      if (!PyDict_Check(object)) return refused();
      for (const auto& [key, item] : py::reinterpret_borrow<py::dict>(value)) {
        auto m = misfit(type.items[0], key, none_refused);
        if (!m) m = misfit(type.items[1], item, none_refused);
        if (m) return inside(std::move(m), "[" + safe_repr(key) + "]");  // the key's repr only for a misfit
      }
      return std::nullopt;
    }
  }
  return std::nullopt;
}

/// pybind11 could not read the arguments of `call` (a function without overloads): a TypeError naming the
/// first argument that does not fit its type, or none when no argument can be blamed (pybind11's message).
std::optional<py::type_error> refusal(const detail::function_call& call, const Entry& entry,
                                      bool none_refused) {
  // A constructor's first argument is the instance being made, not a Python object.
  const std::size_t first = call.func.is_new_style_constructor ? 1 : 0;
  for (std::size_t i = first; i < call.args.size() && i < entry.expected.size(); ++i) {
    if (const auto m = misfit(entry.expected[i], call.args[i], none_refused))
      return py::type_error(entry.who + ": " + entry.names[i] + m->path + ": expected " + m->expected +
                            ", got " + describe(m->value));
  }
  return std::nullopt;
}

bool is_bool(py::handle value) {
  static auto* numpy_bool = reinterpret_cast<PyTypeObject*>(
      py::object(py::module_::import("numpy").attr("bool_")).release().ptr());      // never released
  return PyBool_Check(value.ptr()) || PyObject_TypeCheck(value.ptr(), numpy_bool);  // runs no __class__
}

/// The parameter holding `value` (or `value` as an item of a list or tuple argument, "nets[1]", or as a key
/// or value of a dict argument, "values['a']": pybind11's dict caster does not say where it failed).
std::string parameter_of(const detail::function_call& call, const Entry& entry, PyObject* value) {
  const auto name = [&](std::size_t i) { return i < entry.names.size() ? entry.names[i] : "argument"; };
  // A constructor's first argument is the instance being made, not a Python object: never read it (an
  // element of a list given to a constructor was looked for in it, a crash found by test_hostile.py).
  const std::size_t first = call.func.is_new_style_constructor ? 1 : 0;
  for (std::size_t i = first; i < call.args.size(); ++i)
    if (call.args[i].ptr() == value) return name(i);
  for (std::size_t i = first; i < call.args.size(); ++i) {
    const py::handle arg = call.args[i];
    if (PyDict_Check(arg.ptr()))
      for (const auto& [key, item] : py::reinterpret_borrow<py::dict>(arg))
        if (key.ptr() == value || item.ptr() == value) return name(i) + "[" + safe_repr(key) + "]";
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
    const py::handle result = entry.impl(call);
    if (result.ptr() == PYBIND11_TRY_NEXT_OVERLOAD && !entry.overloaded)
      if (auto error = refusal(call, entry, false)) throw *std::move(error);
    return result;
  } catch (const ArgumentError& e) {
    const std::string message =
        entry.who + ": " + parameter_of(call, entry, e.value) + e.path + ": " + e.detail;
    if (e.wrong_type) throw py::type_error(message);
    throw InvalidInput(message);
  } catch (const py::reference_cast_error&) {  // None read for a class taken by reference
    if (!entry.overloaded)
      if (auto error = refusal(call, entry, true)) throw *std::move(error);
    throw;
  }
}

/// Wraps every overload of `function` (a pybind11 function, method or property accessor) once.
void wrap(py::handle function, const std::string& who, const std::string& value_name, const Classes& classes,
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
      entry.expected.push_back(read_type(p.type, classes));
    }
    if (!value_name.empty() && !entry.names.empty()) entry.names.back() = value_name;
    if (entry.overloaded)  // pybind11 then refuses anything but True, False and numpy bools (a TypeError)
      for (std::size_t i = 0; i < entry.flags.size() && i < rec->args.size(); ++i)
        if (entry.flags[i]) rec->args[i].convert = false;
    entries().emplace(rec, std::move(entry));
    rec->impl = checked_call;
  }
}

void wrap_class(py::handle type, const Classes& classes) {
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
      wrap(value.attr("fget"), qualified, {}, classes);
      wrap(value.attr("fset"), name, attribute, classes);
    } else if (PyObject_TypeCheck(value.ptr(), &PyStaticMethod_Type)) {
      wrap(value.attr("__func__"), qualified, {}, classes);
    } else {
      const bool construct = attribute == "__init__" || attribute == "__setstate__";
      wrap(value, attribute == "__init__" ? name : qualified, {}, classes,
           construct ? members : std::vector<long long>{});
    }
  }
}

void wrap_module(py::module_ m, const Classes& classes, std::unordered_set<PyObject*>& seen) {
  if (!seen.insert(m.ptr()).second) return;
  const std::string prefix = py::str(m.attr("__name__"));
  for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(m.attr("__dict__"))) {
    if (py::isinstance<py::module_>(value)) {
      if (std::string(py::str(value.attr("__name__"))).rfind(prefix, 0) == 0)
        wrap_module(py::reinterpret_borrow<py::module_>(value), classes, seen);
    } else if (PyType_Check(value.ptr())) {
      if (std::string(py::str(py::getattr(value, "__module__", py::str("")))).rfind("cifs", 0) == 0)
        wrap_class(value, classes);
    } else {
      wrap(value, py::str(key), {}, classes);
    }
  }
}

/// Every bound class by its signature names (see Classes). A class that converts implicitly from other types
/// maps to null: an argument of another type may be one it converts.
Classes bound_classes() {
  Classes classes;
  for (const auto& [type, infos] : detail::get_internals().registered_types_py) {
    const py::handle handle(reinterpret_cast<PyObject*>(type));
    const std::string module = py::str(py::getattr(handle, "__module__", py::str("")));
    const std::string qualified = py::str(py::getattr(handle, "__qualname__", py::str(type->tp_name)));
    bool implicit = false;
    for (const detail::type_info* info : infos) implicit = implicit || !info->implicit_conversions.empty();
    PyTypeObject* bound = implicit ? nullptr : type;
    std::string name = module;
    name.append(1, '.').append(qualified);
    classes[name] = bound;
    for (const detail::type_info* info : infos) {
      std::string cpp = info->cpptype->name();
      detail::clean_type_id(cpp);
      classes[cpp] = bound;
    }
  }
  return classes;
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
  std::string text = safe_repr(value);
  if (text.size() > 40) {  // cut at a character boundary: the message must stay valid UTF-8
    std::size_t n = 37;
    while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n;
    text = text.substr(0, n) + "...";
  }
  std::string type = Py_TYPE(value.ptr())->tp_name;
  if (type.rfind("cifs._cifs.", 0) == 0) type = class_name(Py_TYPE(value.ptr()));  // as the user names it
  return type + " " + text;
}

std::string class_name(PyTypeObject* type) {
  const py::handle handle(reinterpret_cast<PyObject*>(type));
  std::string module = py::str(py::getattr(handle, "__module__", py::str("")));
  if (module.rfind("cifs._cifs", 0) == 0) module.erase(4, 6);  // "cifs._cifs.render" → "cifs.render"
  const std::string name = py::str(py::getattr(handle, "__qualname__", py::str(type->tp_name)));
  return module.empty() ? name : module + "." + name;
}

void check_arguments(py::module_& m) {
  std::unordered_set<PyObject*> seen;
  wrap_module(m, bound_classes(), seen);
}

}  // namespace cifs::python
