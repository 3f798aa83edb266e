// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.subdivision: schemes with exact masks (fractions.Fraction), refinement,
// IFS matrices, analysis.
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/io/json.hpp"
#include "cifs/subdivision/analysis.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/refine.hpp"
#include "cifs/subdivision/scheme.hpp"

namespace sd = cifs::subdivision;

namespace cifs::python {
/// What the exact-number parameters take, for messages.
constexpr const char* kExactNumber = "an exact number (a Fraction, an int, a float or a str such as '1/16')";
}  // namespace cifs::python

// Rational ↔ fractions.Fraction. Accepted: Fraction, int (and numpy integers), str in parse_rational
// syntax ("1/16", "0.0625"), and floats (Python and numpy): a float stands for the decimal it prints
// as, its shortest round-trip text, as the CLI reads `--param w=0.1` — so 0.1 is 1/10, not
// 3602879701896397/36028797018963968 (that exact binary value stays available as fractions.Fraction(x)).
// Anything else (None, an array, a complex number, True) is refused as the argument casters of bindings.hpp
// refuse, naming the parameter: "j_spline: s: expected an exact number (…), got an array of dtype …" (it
// raised RuntimeError "Unexpected character encountered in input." for an array: issue 33).
namespace pybind11::detail {
template <>
struct type_caster<sd::Rational> {
  PYBIND11_TYPE_CASTER(sd::Rational, const_name("fractions.Fraction"));

  bool load(handle src, bool /*convert*/) {
    using cifs::python::describe;
    // By the real type (PyObject_TypeCheck runs no __class__ of the value); the types are never released.
    static auto* const floating = type("numpy", "floating");
    static auto* const fraction = type("fractions", "Fraction");
    if (!src) return false;
    PyObject* p = src.ptr();
    if (PyUnicode_Check(p)) {
      value = sd::parse_rational(cifs::python::checked_cast<std::string>(src, "a str"), "rational");
      return true;
    }
    if (PyFloat_Check(p) || PyObject_TypeCheck(p, floating)) {
      const auto x = reinterpret_steal<object>(PyNumber_Float(p));
      if (!x) throw error_already_set();
      if (!std::isfinite(PyFloat_AsDouble(x.ptr())))
        throw cifs::python::ArgumentError(p, {}, "expected a finite number, got " + describe(src));
      // str, not repr: numpy 2's repr of a scalar is "np.float64(0.1)"; str is the shortest text of its type.
      const std::string text = str(src).cast<std::string>();
      try {
        value = sd::parse_rational(text, "rational");
      } catch (const cifs::InvalidInput&) {  // beyond the parser's exponent range (1e-310): the exact value
        const auto exact = module_::import("fractions").attr("Fraction")(x);
        value = ratio(exact.attr("numerator"), exact.attr("denominator"));
      }
      return true;
    }
    if (!PyBool_Check(p) && PyIndex_Check(p)) {  // an int, a numpy integer (an array has __index__ too)
      if (const auto index = reinterpret_steal<object>(PyNumber_Index(p))) {
        value = sd::Rational(integer(index));
        return true;
      }
      PyErr_Clear();
    }
    if (PyObject_TypeCheck(p, fraction)) {
      value = ratio(src.attr("numerator"), src.attr("denominator"));
      return true;
    }
    return cifs::python::refuse(
        src, "expected " + std::string(cifs::python::kExactNumber) + ", got " + describe(src), {}, true);
  }

  static handle cast(const sd::Rational& x, return_value_policy, handle) {
    const auto text = [](const boost::multiprecision::cpp_int& i) { return int_(str(i.str())); };
    return module_::import("fractions").attr("Fraction")(text(numerator(x)), text(denominator(x))).release();
  }

 private:
  /// The type module.attribute (a new reference).
  static PyTypeObject* type(const char* module, const char* attribute) {
    return reinterpret_cast<PyTypeObject*>(object(module_::import(module).attr(attribute)).release().ptr());
  }
  static boost::multiprecision::cpp_int integer(handle index) {
    return boost::multiprecision::cpp_int(str(index).cast<std::string>());
  }
  static sd::Rational ratio(handle p, handle q) {
    return sd::Rational(integer(reinterpret_steal<object>(PyNumber_Index(p.ptr()))),
                        integer(reinterpret_steal<object>(PyNumber_Index(q.ptr()))));
  }
};

// A mask (list of Rationals): its length is checked before any coefficient is converted, so that
// np.zeros(10**7) is refused at once (each conversion costs a microsecond or more: 22 s), and an
// array of several dimensions is named as such instead of failing on its rows. The coefficients are read
// as every list argument is (bindings.hpp): a refused one is named by its place, "mask[2]".
template <>
struct type_caster<sd::Polynomial> : CheckedListCaster<sd::Polynomial, sd::Rational> {
  bool load(handle src, bool convert) {
    if (src && hasattr(src, "ndim") && hasattr(src, "shape")) {
      const auto ndim = src.attr("ndim").cast<ssize_t>();
      if (ndim != 1)
        throw cifs::python::ArgumentError(src.ptr(), {},
                                          "an array of " + std::to_string(ndim) +
                                              " dimensions; give the coefficients as a list or a 1-D array");
    }
    if (src && PySequence_Check(src.ptr()) && !PyUnicode_Check(src.ptr()) && !PyBytes_Check(src.ptr())) {
      const Py_ssize_t n = PySequence_Size(src.ptr());
      if (n < 0) throw error_already_set();
      if (n > sd::kMaxMaskSize)
        throw cifs::python::ArgumentError(
            src.ptr(), {},
            std::to_string(n) + " coefficients exceed the limit of " + std::to_string(sd::kMaxMaskSize));
    }
    return CheckedListCaster<sd::Polynomial, sd::Rational>::load(src, convert);
  }
};
}  // namespace pybind11::detail

namespace cifs::python {
namespace {

/// Parameters (name → value, in order) as a dict of Fractions.
py::dict parameter_dict(const std::vector<sd::Parameter>& parameters) {
  py::dict out;
  for (const sd::Parameter& p : parameters) out[py::str(p.name)] = py::cast(p.value);
  return out;
}

std::vector<sd::Parameter> parameter_list(const py::dict& parameters) {
  std::vector<sd::Parameter> out;
  for (const auto& [key, value] : parameters)
    out.push_back({checked_cast<std::string>(key, "a str"), checked_cast<sd::Rational>(value, kExactNumber)});
  return out;
}

/// A named scheme's parameter as the CLI text: strings unchanged (named_scheme parses them and
/// names the scheme in its errors), numbers as their exact text.
std::string parameter_text(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return checked_cast<std::string>(value, "a str");
  return sd::to_string(checked_cast<sd::Rational>(value, kExactNumber));
}

void check_range(const char* where, const char* name, int value, int low, int high) {
  if (value < low || value > high)
    throw InvalidInput(std::string(where) + ": " + name + " = " + std::to_string(value) + " is outside [" +
                       std::to_string(low) + ", " + std::to_string(high) + "]");
}

py::array_t<std::complex<double>> complex_array(const std::vector<std::complex<double>>& values) {
  return py::array_t<std::complex<double>>(static_cast<py::ssize_t>(values.size()), values.data());
}

/// The Scheme type and the named schemes.
void bind_subdivision_schemes(py::module_& m) {
  py::class_<sd::Scheme>(m, "Scheme",
                         R"doc(A uniform binary subdivision scheme: a name, its parameters and its exact mask.

Scheme(name, mask, parameters={}) validates like make_scheme: mask a_0 … a_N (Fractions, ints, exact
decimal strings such as "0.0625" or "1/16", floats as the decimal they print as: 0.1 is 1/10) refines
q_i = Σ_j a_{i−2j} p_j; leading and trailing zeros are dropped. Raises cifs.InvalidInput when the mask
is empty or all zero, a single coefficient, longer than 512, or does not sum to 2 with even- and
odd-indexed halves summing to 1 each.)doc")
      .def(py::init([](std::string name, sd::Polynomial mask, const py::dict& parameters) {
             return sd::make_scheme(std::move(name), std::move(mask), parameter_list(parameters));
           }),
           py::arg("name"), py::arg("mask"), py::arg("parameters") = py::dict(),
           "Builds and validates a scheme (see the class docstring); parameters: dict name → exact value.")
      .def_readonly("name", &sd::Scheme::name, "Name of the scheme, e.g. 'four-point' or 'mask'.")
      .def_property_readonly(
          "parameters", [](const sd::Scheme& s) { return parameter_dict(s.parameters); },
          "The parameters the scheme was built from: dict name → fractions.Fraction, in order.")
      .def_readonly("mask", &sd::Scheme::mask,
                    "The mask a_0 … a_N as a list of fractions.Fraction (a_0, a_N ≠ 0).")
      .def_property_readonly(
          "weights", [](const sd::Scheme& s) { return vector_array(s.weights); },
          "The mask as float64 numpy array (N + 1,): the refinement kernel's taps.")
      .def("__repr__", [](const sd::Scheme& s) {
        return "Scheme('" + s.name + "', mask_degree=" + std::to_string(sd::mask_degree(s)) + ")";
      });

  m.def(
      "make_scheme",
      [](std::string name, sd::Polynomial mask, const py::dict& parameters) {
        return sd::make_scheme(std::move(name), std::move(mask), parameter_list(parameters));
      },
      py::arg("name"), py::arg("mask"), py::arg("parameters") = py::dict(),
      R"doc(Validates and trims a mask into a Scheme (same as the Scheme constructor).

name: str; mask: sequence of exact values a_0 … a_N; parameters: dict name → exact value.
Raises cifs.InvalidInput, e.g. "mask: coefficients sum to 1.5, a subdivision mask sums to 2".)doc");

  m.def("chaikin", &sd::chaikin, "Chaikin's scheme, mask (1, 3, 3, 1)/4.");
  m.def(
      "corner_cutting", &sd::corner_cutting, py::arg("a"), py::arg("b"),
      R"doc(Corner cutting x_{2i} = (1−a)x_i + a·x_{i+1}, x_{2i+1} = (1−b)x_i + b·x_{i+1}; mask (a, b, 1−a, 1−b).

a, b: exact values. Raises cifs.InvalidInput when the mask is degenerate.)doc");
  m.def("four_point", &sd::four_point,
        "The Dyn–Levin–Gregory 4-point scheme, mask (−1, 0, 9, 16, 9, 0, −1)/16.");
  m.def("generalized_four_point", &sd::generalized_four_point, py::arg("w"),
        "The 4-point scheme with tension w (exact): x_{2i+1} = −w(x_{i−1} + x_{i+2}) + (½ + w)(x_i + "
        "x_{i+1}).");
  m.def("six_point", &sd::six_point, "The interpolating 6-point scheme (3, −25, 150, 150, −25, 3)/256.");
  m.def("lane_riesenfeld", &sd::lane_riesenfeld, py::arg("degree"),
        "Uniform B-spline of degree n (0 … 64) by Lane–Riesenfeld, symbol (1+z)^{n+1}/2^n. Raises "
        "cifs.InvalidInput out of range.");
  m.def("lr_four_point", &sd::lr_four_point, py::arg("stages"),
        "Generalised Lane–Riesenfeld on the 4-point rule with `stages` (0 … 64) smoothing stages. Raises "
        "cifs.InvalidInput out of range.");
  m.def("lr_six_point", &sd::lr_six_point, py::arg("stages"),
        "Generalised Lane–Riesenfeld on the 6-point rule with `stages` (0 … 64) smoothing stages. Raises "
        "cifs.InvalidInput out of range.");
  m.def(
      "two_tension", &sd::two_tension, py::arg("n"), py::arg("s"), py::arg("t"),
      "The two-tension family S(n, s, t): symbol (1+z)^{n+1}/2^n·(s(1+z⁴) + t(z+z³) + (1−2s−2t)z²); n in 0 … "
      "64, s, t exact. Raises cifs.InvalidInput for a bad n or mask.");
  m.def("b_spline", &sd::b_spline, py::arg("degree"),
        "Uniform B-spline of degree n (0 … 64) as S(n, 0, 0). Raises cifs.InvalidInput out of range.");
  m.def("j_spline", &sd::j_spline, py::arg("s"), "The J-spline J_s = S(1, (s−1)/8, 1/4) (s exact).");
  m.def("romani", &sd::romani, py::arg("n"), py::arg("w"),
        "Romani's family a_{n,w} = S(n, −(n+3)w/2, 4w); n in 0 … 64, w exact. Raises cifs.InvalidInput.");
  m.def("cubic_precision", &sd::cubic_precision, py::arg("n"), py::arg("s"),
        "The cubic-precision line S(n, s, −(n+1)/8 − 4s); n in 0 … 64, s exact. Raises cifs.InvalidInput.");
  m.def("hormann_sabin", &sd::hormann_sabin, py::arg("n"),
        "Hormann–Sabin S(n, 0, −(n+1)/8), n in 3 … 64 (n = 3 is the 4-point scheme). Raises "
        "cifs.InvalidInput.");
  m.def("dual_four_point", &sd::dual_four_point,
        "The dual 4-point scheme (−5, −7, 35, 105, 105, 35, −7, −5)/128.");
  m.def("from_mask", &sd::from_mask, py::arg("mask"),
        "A user mask a_0 … a_N (exact values), named 'mask'. Raises cifs.InvalidInput like make_scheme.");
  m.def("from_symbol", &sd::from_symbol, py::arg("expression"),
        "A user symbol in z, e.g. '(1+z)^4*(-1+4z-z^2)/16', named 'symbol'. Raises cifs.InvalidInput "
        "pointing at "
        "the offending character, or like make_scheme.");
  m.def("parse_symbol", &sd::parse_symbol, py::arg("expression"),
        "The polynomial of a symbol expression (list of Fractions, lowest power first, shifted to start at "
        "z^0), "
        "without the mask checks. Raises cifs.InvalidInput.");
}

/// The catalogue of named schemes, mask properties.
void bind_subdivision_catalogue(py::module_& m) {
  py::class_<sd::ParameterSpec>(m, "ParameterSpec", "A parameter of a named scheme in the catalogue.")
      .def_readonly("name", &sd::ParameterSpec::name, "Parameter name, e.g. 'w'.")
      .def_readonly("default_value", &sd::ParameterSpec::default_value, "Default as text ('' when required).")
      .def_readonly("meaning", &sd::ParameterSpec::meaning, "What the parameter means.")
      .def("__repr__", [](const sd::ParameterSpec& p) {
        return "ParameterSpec('" + p.name + "', default='" + p.default_value + "')";
      });
  py::class_<sd::SchemeSpec>(m, "SchemeSpec",
                             "A named scheme of the catalogue (the names `cifs scheme` accepts).")
      .def_readonly("name", &sd::SchemeSpec::name, "Catalogue name, e.g. 'generalized-four-point'.")
      .def_readonly("parameters", &sd::SchemeSpec::parameters, "List of ParameterSpec.")
      .def_readonly("summary", &sd::SchemeSpec::summary, "One-line description.")
      .def("__repr__", [](const sd::SchemeSpec& s) { return "SchemeSpec('" + s.name + "')"; });
  m.def("scheme_catalogue", &sd::scheme_catalogue,
        "Every named scheme (list of SchemeSpec), in the order of docs/schemes.md.");

  m.def(
      "named_scheme",
      [](const std::string& name, const std::optional<py::dict>& parameters, const py::kwargs& kwargs) {
        std::map<std::string, std::string> given;
        // A value refused is named where it was given, "parameters['w']" or the keyword "w" (checked_call
        // finds arguments by identity, which cannot tell the keyword w=None from parameters=None).
        const auto add = [&](const py::handle& key, const py::handle& value, bool keyword) {
          const auto k = checked_cast<std::string>(key, "a str");
          std::string text;
          try {
            text = parameter_text(value);
          } catch (const ArgumentError& e) {
            const std::string where = keyword ? k : "parameters[" + std::string(py::repr(key)) + "]";
            if (e.wrong_type) throw py::type_error("named_scheme: " + where + ": " + e.detail);
            throw InvalidInput("named_scheme: " + where + ": " + e.detail);
          }
          if (!given.emplace(k, std::move(text)).second)
            throw InvalidInput("named_scheme: parameter '" + k + "' is given twice");
        };
        if (parameters)
          for (const auto& [key, value] : *parameters) add(key, value, false);
        for (const auto& [key, value] : kwargs) add(key, value, true);
        return sd::named_scheme(name, given);
      },
      py::arg("name"), py::arg("parameters") = py::none(),
      R"doc(A scheme from its catalogue name and parameters, like `cifs scheme NAME --param k=v`.

name: catalogue name ('four-point', 'mask', …); parameters: dict name → value and/or keyword
arguments (named_scheme('romani', n=2, w='1/32')). Values: text as on the command line, or exact
numbers (Fraction, int, a Python or numpy float read as the decimal it prints as: 0.1 is 1/10). Missing parameters take their defaults.
Raises cifs.InvalidInput with the CLI's message for an unknown scheme or parameter, a missing or
repeated one, a value that does not parse, a non-integer or out-of-range integer.)doc");

  m.def("mask_degree", &sd::mask_degree, py::arg("scheme"),
        "N: the mask has N + 1 coefficients (support [0, N], IFS matrices N by N).");
  m.def("is_symmetric", &sd::is_symmetric, py::arg("scheme"),
        "True when a_k = a_{N−k} for every k (exactly).");
}

/// Refinement, IFS matrices, automata and limit points.
void bind_subdivision_refinement(py::module_& m) {
  py::enum_<sd::Ends> end_rule(m, "Ends", "End rule of open polygons in refine (docs/schemes.md).");
  end_rule.value("automatic", sd::Ends::automatic, "reflect for symmetric masks, keep otherwise")
      .value("reflect", sd::Ends::reflect,
             "extend by point reflection through the end points (symmetric masks)")
      .value("keep", sd::Ends::keep,
             "keep the new points whose stencil lies in the polygon, plus the end points");
  end_rule.attr("value").attr("__doc__") = "The integer value of the end rule.";

  m.def(
      "refine",
      [](const sd::Scheme& scheme, const Points& P, bool closed, int steps, sd::Ends ends,
         std::size_t max_points) {
        return sd::refine(scheme, P, closed, steps,
                          sd::RefineOptions{.ends = ends, .max_points = max_points});
      },
      py::arg("scheme"), py::arg("P"), py::arg("closed").noconvert(), py::arg("steps") = 1, py::kw_only(),
      py::arg("ends") = sd::Ends::automatic, py::arg("max_points") = sd::RefineOptions{}.max_points,
      py::call_guard<py::gil_scoped_release>(),
      R"doc(Refines a polygon `steps` ≥ 0 times by the scheme's mask.

P: float64 array (n, dim), rows are points (any dim; homogeneous rows refine unchanged); closed:
whether the polygon is closed (n ≥ 1) or open (n ≥ 2, end rule `ends`); max_points: refuse a
result with more points before any work. Returns the refined points (m, dim). Raises
cifs.InvalidInput for an empty or too short polygon, non-finite coordinates, negative steps,
Ends.reflect with an asymmetric mask, or a result beyond max_points.)doc");

  m.def(
      "ifs_matrix",
      [](const std::vector<double>& mask, int epsilon) { return sd::ifs_matrix(mask, epsilon); },
      py::arg("mask"), py::arg("epsilon"),
      R"doc(S_ε of a mask given as floats (N + 1 ≥ 2 values): the N by N matrix S_ε[s][r] = a_{s−2r+N−1+ε}.

epsilon: 0 (left half) or 1 (right half). Raises cifs.InvalidInput otherwise.)doc");
  m.def(
      "ifs_matrices",
      [](const sd::Scheme& scheme) {
        const auto S = sd::ifs_matrices(scheme);
        return py::make_tuple(S[0], S[1]);
      },
      py::arg("scheme"), "(S_0, S_1) of the scheme, each a float64 array (N, N) with rows summing to 1.");
  m.def(
      "padded_ifs_matrices",
      [](const sd::Scheme& scheme, int window) {
        const auto S = sd::padded_ifs_matrices(scheme, window);
        return py::make_tuple(S[0], S[1]);
      },
      py::arg("scheme"), py::arg("window"),
      "(S_0, S_1) of the mask padded with zeros to windows of `window` points (docs/junctions.md): the same "
      "curve on wider windows, so that schemes of different supports share cells of one size.");
  m.def(
      "scheme_bcifs",
      [](const sd::Scheme& scheme, int window, int pieces, int layer, bool free) {
        return sd::scheme_bcifs(scheme, window, {.pieces = pieces, .layer = layer, .free = free});
      },
      py::arg("scheme"), py::arg("window") = 0, py::arg("pieces") = 1, py::arg("layer") = 0,
      py::arg("free").noconvert() = false,
      "BC-IFS of an open curve of the scheme on windows of `window` points (0: its own N): "
      "cifs.ifs.uniform_curve_bcifs of padded_ifs_matrices.");
  m.def(
      "scheme_automaton", &sd::scheme_automaton, py::arg("scheme"), py::arg("segments") = 1,
      R"doc(The one-state automaton of the scheme: transitions '0' (S_0) and '1' (S_1), `segments` initial entries.

Returns a cifs.automata.Automaton. Raises cifs.InvalidInput for negative segments.)doc");
  m.def(
      "closed_windows", &sd::closed_windows, py::arg("scheme"), py::arg("P"),
      "The n windows of a closed polygon P (n, dim): list of arrays (N, dim), window k = rows k … k+N−1 (mod "
      "n). Raises cifs.InvalidInput for an empty polygon.");
  m.def("limit_points", &sd::limit_points, py::arg("scheme"), py::arg("P"), py::arg("depth"),
        py::call_guard<py::gil_scoped_release>(),
        R"doc(Points of the limit curve of the closed polygon P (n, dim) through the IFS: (n·2^depth, dim).

Piece k (window k) gives 2^depth points at parameters j/2^depth. Raises cifs.InvalidInput for an
empty polygon, a negative depth or too many points.)doc");
}

/// Smoothness analysis, difference masks, exact numbers.
void bind_subdivision_analysis(py::module_& m) {
  py::class_<sd::ContinuityProof>(m, "ContinuityProof", "The certificate of C^k: ‖S_{d_k}^L‖_∞ = norm < 1.")
      .def_readonly("k", &sd::ContinuityProof::k, "The order k proved (−1: none).")
      .def_readonly("power", &sd::ContinuityProof::power, "The power L of the difference scheme.")
      .def_readonly("norm", &sd::ContinuityProof::norm, "The exact norm (fractions.Fraction) < 1.")
      .def("__repr__", [](const sd::ContinuityProof& p) {
        return "ContinuityProof(k=" + std::to_string(p.k) + ", power=" + std::to_string(p.power) +
               ", norm=" + sd::to_string(p.norm) + ")";
      });

  py::class_<sd::SchemeAnalysis>(m, "SchemeAnalysis", "Result of analyze: the properties of a scheme's mask.")
      .def_readonly("mask", &sd::SchemeAnalysis::mask, "The mask a_0 … a_N (Fractions).")
      .def_readonly("support", &sd::SchemeAnalysis::support, "N: the basic limit function lives on [0, N].")
      .def_readonly("symmetric", &sd::SchemeAnalysis::symmetric, "a_k = a_{N−k}.")
      .def_readonly("kind", &sd::SchemeAnalysis::kind, "'primal', 'dual' or 'asymmetric'.")
      .def_readonly("interpolating", &sd::SchemeAnalysis::interpolating,
                    "One parity of the mask is a single 1.")
      .def_readonly("multiplicity", &sd::SchemeAnalysis::multiplicity, "m, the power of (1+z) in the symbol.")
      .def_readonly("generation_degree", &sd::SchemeAnalysis::generation_degree,
                    "m − 1: polynomials generated.")
      .def_readonly("reproduction_degree", &sd::SchemeAnalysis::reproduction_degree,
                    "Degree of polynomial "
                    "reproduction.")
      .def_readonly("continuity", &sd::SchemeAnalysis::continuity, "Largest k with C^k proved (−1: none).")
      .def_readonly("proof", &sd::SchemeAnalysis::proof, "The ContinuityProof of `continuity`.")
      .def_readonly("holder_low", &sd::SchemeAnalysis::holder_low,
                    "Lower bound of the Hölder exponent (float), None when no continuity is proved.")
      .def_readonly("holder_high", &sd::SchemeAnalysis::holder_high,
                    "Upper bound of the Hölder exponent (float), None when m = 0.")
      .def_readonly("holder_low_power", &sd::SchemeAnalysis::holder_low_power, "The L of the best norm.")
      .def_readonly("holder_high_word", &sd::SchemeAnalysis::holder_high_word,
                    "The word (list of 0/1) of the largest ρ(T_w)^{1/|w|}.")
      .def_readonly("symbol", &sd::SchemeAnalysis::symbol, "The expanded symbol, e.g. '(1+3z+3z^2+z^3)/4'.")
      .def_readonly("symbol_factored", &sd::SchemeAnalysis::symbol_factored, "The symbol as (1+z)^m·b(z).")
      .def_property_readonly(
          "eigenvalues",
          [](const sd::SchemeAnalysis& a) {
            return py::make_tuple(complex_array(a.eigenvalues[0]), complex_array(a.eigenvalues[1]));
          },
          "Eigenvalues of S_0 and S_1: a tuple of two complex128 arrays (N,).")
      .def("__repr__", [](const sd::SchemeAnalysis& a) {
        return "SchemeAnalysis(support=" + std::to_string(a.support) + ", kind='" + a.kind +
               "', continuity=" + std::to_string(a.continuity) + ")";
      });

  m.def(
      "analyze",
      [](const sd::Scheme& scheme, int max_power, std::size_t max_coefficients, int max_word_length) {
        check_range("analyze", "max_power", max_power, 1, 26);
        check_range("analyze", "max_word_length", max_word_length, 1, 20);
        return sd::analyze(scheme, sd::AnalysisOptions{.max_power = max_power,
                                                       .max_coefficients = max_coefficients,
                                                       .max_word_length = max_word_length});
      },
      py::arg("scheme"), py::kw_only(), py::arg("max_power") = sd::AnalysisOptions{}.max_power,
      py::arg("max_coefficients") = sd::AnalysisOptions{}.max_coefficients,
      py::arg("max_word_length") = sd::AnalysisOptions{}.max_word_length,
      py::call_guard<py::gil_scoped_release>(),
      R"doc(Analyses a scheme: symbol, support, kind, generation/reproduction, continuity (Dyn), Hölder bracket, spectra.

max_power: largest power L of the difference schemes tried (1 … 26, as the CLI's --max-power);
max_coefficients: cap on the coefficients of c^[L]; max_word_length: longest word (1 … 20) for the
upper Hölder bound. Returns a SchemeAnalysis. Raises cifs.InvalidInput for options out of range.)doc");
  m.def("analysis_json", &io::analysis_json, py::arg("scheme"), py::arg("analysis"),
        "JSON text of an analysis, as printed by `cifs scheme NAME --analyze`.");
  m.def(
      "difference_mask",
      [](const sd::Polynomial& a, int k) {
        return sd::difference_mask(a, non_negative(k, "difference_mask: k"));
      },
      py::arg("a"), py::arg("k"),
      "d_k(z) = 2^k a(z)/(1+z)^{k+1} (list of Fractions). Raises cifs.InvalidInput unless (1+z)^{k+1} "
      "divides "
      "a(z).");
  m.def("power_norm", &sd::power_norm, py::arg("c"), py::arg("L"),
        py::arg("max_coefficients") = std::size_t{1} << 22, py::call_guard<py::gil_scoped_release>(),
        "‖S_c^L‖_∞ exactly (Fraction) for a mask c (exact values), L ≥ 1. Raises cifs.InvalidInput for L < 1 "
        "or "
        "when c^[L] has more than max_coefficients coefficients.");
  m.def("polynomial_text", &sd::polynomial_text, py::arg("p"),
        "Expanded text of a polynomial (exact coefficients, lowest power first), e.g. '(1+3z+3z^2+z^3)/4'.");
  m.def("parse_rational", &sd::parse_rational, py::arg("text"), py::arg("what") = "value",
        R"doc(Exact value (Fraction) of an integer '3', a decimal '-0.0625' or '1e-3', or a fraction '1/16'.

what: the name used in the error message. Raises cifs.InvalidInput for anything else.)doc");
  m.def("to_string", &sd::to_string, py::arg("x"),
        "Shortest exact text of a rational: a decimal when finite ('0.0625'), else a fraction ('1/3').");
}

}  // namespace

void bind_subdivision(py::module_& m) {
  bind_subdivision_schemes(m);
  bind_subdivision_catalogue(m);
  bind_subdivision_refinement(m);
  bind_subdivision_analysis(m);
}

}  // namespace cifs::python
