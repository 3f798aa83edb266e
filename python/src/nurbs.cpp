// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.nurbs: knot vectors, curves, refinement, surfaces, knot doubling.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <utility>

#include "arrays.hpp"
#include "cifs/ifs/shape_attractor.hpp"
#include "cifs/nurbs/construct.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/nurbs/fit.hpp"
#include "cifs/nurbs/knots.hpp"
#include "cifs/nurbs/measure.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/volume.hpp"

namespace cifs::python {
namespace {

using namespace cifs::nurbs;
using Release = py::call_guard<py::gil_scoped_release>;
using DomainTuple = std::pair<double, double>;

DomainTuple as_tuple(Domain d) {
  return {d.start, d.end};
}

Eigen::VectorXd optional_weights(const std::optional<DoubleArray>& weights) {
  return weights ? to_vector(*weights, "weights") : Eigen::VectorXd();
}

/// The knot functions of the C++ API are unchecked (noexcept); Python callers get the checks first.
void check_knots(const Knots& knots, int degree) {
  validate_knots(knots, degree, control_count(knots, degree));
}

void check_span(const Knots& knots, int degree, int span) {
  check_knots(knots, degree);
  if (span < degree || span >= control_count(knots, degree) ||
      !(knots[static_cast<std::size_t>(span)] < knots[static_cast<std::size_t>(span) + 1]))
    throw InvalidInput("span " + std::to_string(span) + " is not a non-empty span of the domain");
}

void check_finite(double u, const char* what) {
  if (!std::isfinite(u)) throw InvalidInput(std::string(what) + " is not finite");
}

void check_breakpoints(const Knots& b, int degree) {
  validate_degree(degree);
  if (b.size() < 2)
    throw InvalidInput("breakpoints: " + std::to_string(b.size()) + " given, need at least 2");
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (!std::isfinite(b[i]))
      throw InvalidInput("breakpoints[" + std::to_string(i) + "]: knot is not finite");
    if (i > 0 && b[i] < b[i - 1])
      throw InvalidInput("breakpoints[" + std::to_string(i) + "]: is less than the previous breakpoint");
  }
  if (!(b.back() > b.front())) throw InvalidInput("breakpoints: the period is empty");
}

/// Up to 12 values in full, else the first and last four around an ellipsis.
void write_values(std::ostream& out, const Knots& values) {
  const std::size_t n = values.size();
  out << "[";
  for (std::size_t i = 0; i < n; ++i) {
    if (n > 12 && i == 4) {
      out << ", …";
      i = n - 4;
    }
    out << (i ? ", " : "") << values[i];
  }
  out << "]";
}

std::string curve_repr(const Curve& c) {
  std::ostringstream out;
  out << "Curve(degree=" << c.degree << ", knots=";
  write_values(out, defining_knots(c));
  out << ", points=" << distinct_count(c) << ", dimension=" << dimension(c) << ", domain=(" << domain(c).start
      << ", " << domain(c).end << ")" << (c.rational ? ", rational" : "") << (c.closed ? ", closed" : "")
      << ")";
  return out.str();
}

std::string surface_repr(const Surface& s) {
  std::ostringstream out;
  out << "Surface(degree=(" << s.degree[0] << ", " << s.degree[1] << "), knots=(";
  write_values(out, s.knots[0]);
  out << ", ";
  write_values(out, s.knots[1]);
  out << "), count=(" << s.count[0] << ", " << s.count[1] << "), dimension=" << dimension(s) << ", domain=(("
      << domain(s, Direction::u).start << ", " << domain(s, Direction::u).end << "), ("
      << domain(s, Direction::v).start << ", " << domain(s, Direction::v).end << "))"
      << (s.rational ? ", rational" : "") << ")";
  return out.str();
}

/// Parameters from a number or an array: ndim 0 gives one value, 1-D many; `scalar` says which.
std::vector<double> parameters_from(const py::object& object, const std::string& where, bool& scalar) {
  const DoubleArray a = DoubleArray::ensure(numeric(object, where, "iuf"));
  if (a.ndim() > 1)
    throw InvalidInput(where + ": expected a number or a 1-D array, got shape " + shape_text(a));
  scalar = a.ndim() == 0;
  return {a.data(), a.data() + a.size()};
}

/// A grid of points (row a·nv + b = S(us[a], vs[b])) as the array (nu, nv, dim) that Surface takes.
py::array grid_points(Points&& points, std::size_t nu, std::size_t nv) {
  auto* heap = new Points(std::move(points));
  const py::capsule owner(heap, [](void* p) { delete static_cast<Points*>(p); });
  constexpr auto kItem = static_cast<py::ssize_t>(sizeof(double));
  const auto dim = static_cast<py::ssize_t>(heap->cols());
  return py::array_t<double>({static_cast<py::ssize_t>(nu), static_cast<py::ssize_t>(nv), dim},
                             {static_cast<py::ssize_t>(nv) * dim * kItem, dim * kItem, kItem}, heap->data(),
                             owner);
}

py::array surface_grid(const Surface& s, const std::vector<double>& us, const std::vector<double>& vs) {
  Points points;
  {
    const py::gil_scoped_release release;
    points = evaluate_grid(s, us, vs);
  }
  return grid_points(std::move(points), us.size(), vs.size());
}

/// Pickled state: the stored fields, so that a curve comes back bit for bit (re-validated on load).
py::tuple curve_state(const Curve& c) {
  return py::make_tuple(c.degree, c.knots, c.P, c.rational, c.closed);
}

Curve curve_from_state(const py::tuple& t) {
  if (t.size() != 5)
    throw InvalidInput("Curve: pickled state has " + std::to_string(t.size()) + " items, expected 5");
  Curve c{.degree = t[0].cast<int>(),
          .knots = t[1].cast<Knots>(),
          .P = t[2].cast<Points>(),
          .rational = t[3].cast<bool>(),
          .closed = t[4].cast<bool>()};
  validate(c);
  return c;
}

py::tuple surface_state(const Surface& s) {
  return py::make_tuple(s.degree, s.knots, s.count, s.P, s.rational);
}

Surface surface_from_state(const py::tuple& t) {
  if (t.size() != 5)
    throw InvalidInput("Surface: pickled state has " + std::to_string(t.size()) + " items, expected 5");
  Surface s{.degree = t[0].cast<std::array<int, 2>>(),
            .knots = t[1].cast<std::array<Knots, 2>>(),
            .count = t[2].cast<std::array<Eigen::Index, 2>>(),
            .P = t[3].cast<Points>(),
            .rational = t[4].cast<bool>()};
  validate(s);
  return s;
}

/// Surface control points `(nu, nv, dim)`, or `(nu·nv, dim)` with `count`; weights `(nu, nv)` or `(nu·nv,)`.
Surface make_surface_from(std::array<int, 2> degree, std::array<Knots, 2> knots, const DoubleArray& points,
                          const std::optional<DoubleArray>& weights,
                          std::optional<std::array<Eigen::Index, 2>> count) {
  Points P;
  if (points.ndim() == 3) {
    const std::array<Eigen::Index, 2> net{points.shape(0), points.shape(1)};
    if (count && *count != net)
      throw InvalidInput("count: (" + std::to_string((*count)[0]) + ", " + std::to_string((*count)[1]) +
                         ") does not match the points' shape " + shape_text(points));
    count = net;
    P = Eigen::Map<const Points>(points.data(), net[0] * net[1], points.shape(2));
  } else {
    if (points.ndim() != 2)
      throw InvalidInput("points: expected (nu, nv, dim) or (nu*nv, dim), got shape " + shape_text(points));
    if (!count) throw InvalidInput("count: give (nu, nv) with points of shape (nu*nv, dim)");
    P = points_from(points, "points");
  }
  Eigen::VectorXd w;
  if (weights) {
    if (weights->ndim() == 2) {
      if (weights->shape(0) != (*count)[0] || weights->shape(1) != (*count)[1])
        throw InvalidInput("weights: shape " + shape_text(*weights) + " does not match the " +
                           std::to_string((*count)[0]) + " by " + std::to_string((*count)[1]) + " net");
      w = Eigen::Map<const Eigen::VectorXd>(weights->data(), weights->size());
    } else {
      w = to_vector(*weights, "weights");
    }
  }
  return make_surface(degree, std::move(knots), *count, P, w);
}

/// The bytes of a vector or matrix, for hashing: == compares values exactly, and x + 0.0 maps −0.0 to
/// 0.0 (equal values, different bytes); no NaN gets past validation.
template <typename Values>
py::bytes raw_bytes(const Values& values) {
  std::vector<double> v(values.data(), values.data() + values.size());
  for (double& x : v) x += 0.0;
  return {reinterpret_cast<const char*>(v.data()), sizeof(double) * v.size()};
}

py::int_ curve_hash(const Curve& c) {
  return py::int_(py::hash(
      py::make_tuple(c.degree, c.rational, c.closed, raw_bytes(c.knots), c.P.cols(), raw_bytes(c.P))));
}

py::int_ surface_hash(const Surface& s) {
  return py::int_(py::hash(py::make_tuple(s.degree[0], s.degree[1], s.count[0], s.count[1], s.rational,
                                          raw_bytes(s.knots[0]), raw_bytes(s.knots[1]), raw_bytes(s.P))));
}

void bind_knots(py::module_& m) {
  m.attr("kMaxDegree") = kMaxDegree;
  m.def("validate_degree", &validate_degree, py::arg("degree"), py::arg("where") = "degree",
        "Checks 1 ≤ degree ≤ kMaxDegree.\n\nRaises InvalidInput (message prefixed by `where`) otherwise.");
  m.def(
      "validate_knots",
      [](const Knots& knots, int degree, Eigen::Index count, std::string_view where) {
        validate_knots(knots, degree, count, where);
      },
      py::arg("knots"), py::arg("degree"), py::arg("count"), py::arg("where") = "knots",
      "Checks that `knots` is a knot vector of `count` control points of `degree`.\n\n"
      "Finite, non-decreasing, count + degree + 1 values, multiplicities ≤ degree + 1, non-empty domain.\n"
      "Raises InvalidInput (message prefixed by `where`) otherwise.");
  m.def(
      "control_count",
      [](const Knots& knots, int degree) {
        return control_count(knots, non_negative(degree, "control_count: degree"));
      },
      py::arg("knots"), py::arg("degree"),
      "Number of control points a knot vector serves: len(knots) − degree − 1.");
  m.def(
      "domain",
      [](const Knots& knots, int degree) {
        check_knots(knots, degree);
        return as_tuple(domain(knots, degree));
      },
      py::arg("knots"), py::arg("degree"),
      "The domain (t_d, t_n) of a knot vector of `degree`, as a tuple.\n\nRaises InvalidInput for invalid "
      "knots.");
  m.def(
      "find_span",
      [](const Knots& knots, int degree, double u) {
        check_knots(knots, degree);
        check_finite(u, "u");
        return find_span(knots, degree, u);
      },
      py::arg("knots"), py::arg("degree"), py::arg("u"),
      "The span k in [d, n−1] with t_k ≤ u < t_{k+1} (the domain end belongs to the last non-empty span).\n\n"
      "Parameters outside the domain are clamped to the first/last span. Raises InvalidInput for invalid\n"
      "knots or a non-finite u.");
  m.def(
      "multiplicity", [](const Knots& knots, double u) { return multiplicity(knots, u); }, py::arg("knots"),
      py::arg("u"), "Multiplicity of the value u in the (sorted) knots; 0 when absent.");
  m.def(
      "breakpoints",
      [](const Knots& knots, int degree) {
        check_knots(knots, degree);
        return vector_array(breakpoints(knots, degree));
      },
      py::arg("knots"), py::arg("degree"),
      "Distinct knot values inside the domain, in order (1-D array).\n\nRaises InvalidInput for invalid "
      "knots.");
  m.def(
      "basis_functions",
      [](const Knots& knots, int degree, int span, double u) {
        validate_span_query(knots, degree, span);
        check_finite(u, "u");
        std::vector<double> N(static_cast<std::size_t>(degree) + 1);
        basis_functions(knots, degree, span, u, N.data());
        return vector_array(N);
      },
      py::arg("knots"), py::arg("degree"), py::arg("span"), py::arg("u"),
      "The degree + 1 non-zero basis functions N_{span−d..span}(u) (1-D array; Cox–de Boor).\n\n"
      "Any degree 0 … kMaxDegree on any knot vector where they are defined (validate_span_query). Raises\n"
      "InvalidInput for knots that are not finite and non-decreasing or an empty or out-of-range span.");
  m.def(
      "blossom_weights",
      [](const Knots& knots, int degree, int span, const std::vector<double>& args) {
        validate_span_query(knots, degree, span);
        if (static_cast<int>(args.size()) != degree)
          throw InvalidInput("blossom: " + std::to_string(args.size()) + " arguments given, degree " +
                             std::to_string(degree) + " takes " + std::to_string(degree));
        for (double a : args) check_finite(a, "blossom: argument");
        std::vector<double> W(static_cast<std::size_t>(degree) + 1);
        blossom_weights(knots, degree, span, args, W.data());
        return vector_array(W);
      },
      py::arg("knots"), py::arg("degree"), py::arg("span"), py::arg("args"),
      "Weights W_0..W_d with blossom(args) = Σ W_j P_{span−d+j} (1-D array of degree + 1 values).\n\n"
      "`args`: `degree` parameters, any order. Raises InvalidInput for invalid knots, span or arguments.");
  m.def(
      "basis_derivatives",
      [](const Knots& knots, int degree, int span, double u, int order) {
        validate_span_query(knots, degree, span);
        check_finite(u, "u");
        if (order < 0 || order > kMaxDegree)
          throw InvalidInput("derivative order " + std::to_string(order) + " is outside 0 … " +
                             std::to_string(kMaxDegree));
        return basis_derivatives(knots, degree, span, u, order);
      },
      py::arg("knots"), py::arg("degree"), py::arg("span"), py::arg("u"), py::arg("order"),
      "Basis functions and derivatives up to `order`: array (order + 1, degree + 1).\n\n"
      "Row r holds the r-th derivatives of N_{span−d..span}(u). Raises InvalidInput for invalid knots,\n"
      "span or an order outside 0 … kMaxDegree.");
  m.def(
      "periodic_knots",
      [](const Knots& b, int degree) {
        check_breakpoints(b, degree);
        return vector_array(periodic_knots(b, degree));
      },
      py::arg("breakpoints"), py::arg("degree"),
      "Knot vector (1-D array, m + 2d + 1 values) of a closed curve with period breakpoints b_0..b_m.\n\n"
      "Raises InvalidInput for fewer than 2, non-finite or decreasing breakpoints or an empty period.");
}

void bind_curve(py::module_& m) {
  py::class_<Curve>(
      m, "Curve",
      "A B-spline or NURBS curve (immutable). Build with Curve(...) or uniform_bspline.\n\n"
      "A closed curve of m control points is stored expanded: m + degree rows of P, periodic knots.")
      .def(py::init([](int degree, Knots knots, const DoubleArray& points,
                       const std::optional<DoubleArray>& weights, bool closed) {
             const Points P = points_from(points, "points");
             const Eigen::VectorXd w = optional_weights(weights);
             return closed ? make_closed_curve(degree, std::move(knots), P, w)
                           : make_curve(degree, std::move(knots), P, w);
           }),
           py::arg("degree"), py::arg("knots"), py::arg("points"), py::arg("weights") = py::none(),
           py::arg("closed").noconvert() = false,
           "Validated curve (make_curve / make_closed_curve).\n\n"
           "degree: 1..kMaxDegree. knots: n + degree + 1 knots (open), or the m + 1 breakpoints of the "
           "period\n"
           "(closed). points: (n, dim) Cartesian control points. weights: None or n positive values "
           "(rational).\n"
           "Raises InvalidInput with the library's message for any invalid input.")
      .def_readonly("degree", &Curve::degree, "Polynomial degree.")
      .def_property_readonly(
          "knots", [](const Curve& c) { return vector_array(c.knots); },
          "The full knot vector (1-D array; periodic knots for closed curves).")
      .def_property_readonly(
          "P", [](const Curve& c) { return Points(c.P); },
          "Stored control rows (n, dim + rational): homogeneous (w·x, w) when rational; closed curves\n"
          "repeat their first `degree` points at the end.")
      .def_readonly("rational", &Curve::rational, "True for a NURBS (weighted) curve.")
      .def_readonly("closed", &Curve::closed, "True for a closed (periodic) curve.")
      .def_property_readonly(
          "points", [](const Curve& c) { return cartesian_points(c); },
          "Cartesian control points (distinct_count, dim): divided by w when rational, without the\n"
          "repeated points of a closed curve (what the constructor takes; P keeps the stored rows).")
      .def_property_readonly(
          "weights", [](const Curve& c) { return weights(c); },
          "Weights (distinct_count,); ones for a non-rational curve.")
      .def_property_readonly(
          "domain", [](const Curve& c) { return as_tuple(domain(c)); },
          "The parameter domain (start, end); one period for closed curves.")
      .def_property_readonly(
          "dimension", [](const Curve& c) { return dimension(c); }, "Cartesian dimension.")
      .def(
          "attractor",
          [](const Curve& c, int depth, std::int64_t max_points) {
            const std::size_t limit = count_arg(max_points, "Curve.attractor: max_points");
            py::gil_scoped_release unlocked;
            return cifs::ifs::attractor(c, depth, limit);
          },
          py::arg("depth"), py::kw_only(), py::arg("max_points") = std::int64_t{1} << 27,
          "The curve as the attractor of its knot-doubling automaton at `depth` (ifs::attractor): Cartesian\n"
          "points (n, dimension) in curve order, 2^depth per segment plus the end point unless closed — the\n"
          "curve at the dyadic parameters, rational or not. Raises InvalidInput for a negative depth or "
          "more\n"
          "than max_points points.")
      .def(
          "evaluate",
          [](const Curve& c, const py::object& u) -> py::object {
            bool scalar = false;
            const std::vector<double> us = parameters_from(u, "Curve.evaluate: u", scalar);
            if (scalar) return py::cast(evaluate(c, us[0]));
            Points points;
            {
              const py::gil_scoped_release release;
              points = evaluate(c, us);
            }
            return py::cast(std::move(points));
          },
          py::arg("u"),
          "The curve at u: a number gives one point (1-D array of dim values), a 1-D array (or list) of\n"
          "parameters the points (len(u), dim), in order. Same as nurbs.evaluate(curve, u).\n\n"
          "Closed curves wrap u; open curves raise InvalidInput outside the domain.")
      .def(
          "insert", [](const Curve& c, double knot, int times) { return insert_knot(c, knot, times); },
          py::arg("knot"), py::arg("times") = 1,
          "A new curve with `knot` inserted `times` times (nurbs.insert_knot); this one is unchanged.\n\n"
          "Raises InvalidInput when the knot is outside the domain or its multiplicity would exceed the "
          "degree.")
      .def(
          "__eq__",
          [](const Curve& a, const py::object& other) -> py::object {
            if (!py::isinstance<Curve>(other)) return py::reinterpret_borrow<py::object>(Py_NotImplemented);
            const auto& b = other.cast<const Curve&>();
            return py::bool_(a.degree == b.degree && a.rational == b.rational && a.closed == b.closed &&
                             a.knots == b.knots && a.P.rows() == b.P.rows() && a.P.cols() == b.P.cols() &&
                             a.P == b.P);
          },
          py::arg("other"),
          "Exact equality: same degree, knots, stored control rows, rational and closed flags.")
      .def("__hash__", &curve_hash, "A hash consistent with == (curves are immutable).")
      .def(
          "__copy__", [](const Curve& c) { return c; }, "A copy (curves are immutable).")
      .def(
          "__deepcopy__", [](const Curve& c, const py::object& /*memo*/) { return c; }, py::arg("memo"),
          "A copy (curves are immutable).")
      .def(py::pickle(&curve_state, &curve_from_state))
      .def("__repr__", &curve_repr,
           "Short description: degree, knots, control point count, dimension, domain.");

  m.def(
      "uniform_bspline",
      [](const DoubleArray& polygon, int degree, bool closed) {
        return uniform_bspline(points_from(polygon, "uniform_bspline: polygon"), degree, closed);
      },
      py::arg("polygon"), py::arg("degree"), py::arg("closed").noconvert(),
      "The uniform B-spline of `degree` on a control polygon (n, dim).\n\n"
      "closed: periodic with breakpoints 0..n (n ≥ 2); open: clamped with interior knots 1..n − d − 1.\n"
      "Raises InvalidInput for too few points or a bad degree.");
  m.def("dimension", py::overload_cast<const Curve&>(&dimension), py::arg("curve"), "Cartesian dimension.");
  m.def(
      "domain", [](const Curve& c) { return as_tuple(domain(c)); }, py::arg("curve"),
      "The parameter domain (start, end); one period for closed curves.");
  m.def("distinct_count", &distinct_count, py::arg("curve"),
        "Number of distinct control points: n, or m for a closed curve.");
  m.def(
      "defining_knots", [](const Curve& c) { return vector_array(defining_knots(c)); }, py::arg("curve"),
      "The knots given to the constructor: the period's breakpoints (closed) or the knot vector (open).");
  m.def("cartesian_points", py::overload_cast<const Curve&>(&cartesian_points), py::arg("curve"),
        "Cartesian control points (distinct_count, dim).");
  m.def("weights", py::overload_cast<const Curve&>(&weights), py::arg("curve"),
        "Weights (distinct_count,); ones for a non-rational curve.");
  m.def("segment_count", &segment_count, py::arg("curve"),
        "Number of polynomial segments (non-empty spans).");
  m.def("domain_parameter", &domain_parameter, py::arg("curve"), py::arg("u"),
        "Maps u into the domain: wrapped by the period for closed curves.\n\n"
        "Raises InvalidInput for an open curve when u is outside the domain or not finite.");
  m.def("evaluate", py::overload_cast<const Curve&, double>(&evaluate), py::arg("curve"), py::arg("u"),
        "Curve point at u (1-D array of dim values; de Boor).\n\n"
        "Closed curves wrap u; open curves raise InvalidInput outside the domain.");
  m.def(
      "evaluate", [](const Curve& c, const std::vector<double>& us) { return evaluate(c, us); }, Release(),
      py::arg("curve"), py::arg("us"),
      "Curve points at many parameters: array (len(us), dim), in order.\n\nRaises InvalidInput as "
      "evaluate(curve, u).");
  m.def("evaluate_basis", &evaluate_basis, py::arg("curve"), py::arg("u"),
        "Curve point by the basis form Σ N_i(u) P_i (1-D array); an independent route to evaluate.");
  m.def(
      "uniform_parameters",
      [](DomainTuple dom, int count) {
        if (count < 0) throw InvalidInput("count " + std::to_string(count) + " is negative");
        return vector_array(uniform_parameters({dom.first, dom.second}, count));
      },
      py::arg("domain"), py::arg("count"),
      "`count` parameters evenly spaced over domain = (start, end), both ends included (1-D array).\n\n"
      "count = 1 gives the start. Raises InvalidInput for a negative count.");
  m.def("derivatives", py::overload_cast<const Curve&, double, int>(&derivatives), py::arg("curve"),
        py::arg("u"), py::arg("order"),
        "Derivatives of order 0..order at u: array (order + 1, dim), Cartesian.\n\n"
        "Raises InvalidInput for an order outside 0 … kMaxDegree or u outside an open curve's domain.");
  m.def(
      "blossom",
      [](const Curve& c, const std::vector<double>& args, std::optional<int> span) {
        return span ? blossom(c, args, *span) : blossom(c, args);
      },
      py::arg("curve"), py::arg("args"), py::arg("span") = py::none(),
      "Blossom (polar form) at `degree` arguments, in stored coordinates (homogeneous when rational).\n\n"
      "span: the piece to use (default: the span containing the arguments' mean). blossom(c, [u]*d) is\n"
      "the (stored) curve point. Raises InvalidInput for a wrong argument count or span.");
  m.def("to_cartesian", &to_cartesian, py::arg("curve"), py::arg("row"),
        "Cartesian projection of a stored-coordinate row (divides by w when rational).");
}

void bind_refine(py::module_& m) {
  m.def("insert_knot", py::overload_cast<const Curve&, double, int>(&insert_knot), py::arg("curve"),
        py::arg("u"), py::arg("times") = 1,
        "Inserts u `times` times (Boehm); the curve is unchanged.\n\n"
        "Raises InvalidInput when u is outside the domain or its multiplicity would exceed the degree.");
  m.def(
      "refine", [](const Curve& c, const std::vector<double>& knots) { return refine(c, knots); }, Release(),
      py::arg("curve"), py::arg("new_knots"),
      "Inserts many knots at once (any order, repeats allowed); the curve is unchanged.\n\n"
      "Raises InvalidInput as insert_knot.");
  m.def("refine_midpoints", py::overload_cast<const Curve&>(&refine_midpoints), Release(), py::arg("curve"),
        "Inserts the midpoint of every non-empty span (one knot-doubling step).");
  m.def("split_bezier", py::overload_cast<const Curve&>(&split_bezier), Release(), py::arg("curve"),
        "The polynomial pieces as clamped Bézier curves (list of Curve), one per segment, in order.");
  m.def(
      "split",
      [](const Curve& c, double u) {
        auto parts = split(c, u);
        return py::make_tuple(std::move(parts[0]), std::move(parts[1]));
      },
      py::arg("curve"), py::arg("u"),
      "The open curve cut at u (strictly inside the domain): (left, right), on [start, u] and [u, end],\n"
      "each clamped at u and keeping the original parameters. Raises InvalidInput for a closed curve or u\n"
      "not strictly inside the domain.");
  m.def("reverse", py::overload_cast<const Curve&>(&reverse), py::arg("curve"),
        "The same curve traversed backwards: C'(a + b − u) = C(u) on the same domain [a, b]; closed curves\n"
        "stay closed.");
  m.def("elevate_degree", py::overload_cast<const Curve&, int>(&elevate_degree), Release(), py::arg("curve"),
        py::arg("times") = 1,
        "Raises the degree by `times`; the curve is unchanged.\n\n"
        "Raises InvalidInput for negative times or a degree above kMaxDegree.");
  py::class_<Removal>(m, "Removal", "Result of remove_knot.")
      .def_readonly("curve", &Removal::curve, "The curve after removal.")
      .def_readonly("removed", &Removal::removed, "How many copies of the knot were removed.")
      .def_readonly("deviation_bound", &Removal::deviation_bound,
                    "Proven bound on the distance between the old and the new curve.")
      .def(
          "__repr__",
          [](const Removal& r) {
            return "Removal(removed=" + std::to_string(r.removed) +
                   ", deviation_bound=" + py::repr(py::float_(r.deviation_bound)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def(
      "remove_knot", py::overload_cast<const Curve&, double, int, double>(&remove_knot), Release(),
      py::arg("curve"), py::arg("u"), py::arg("times"), py::arg("tolerance"),
      "Removes up to `times` copies of the interior knot u while the curve moves by at most `tolerance`.\n\n"
      "Returns a Removal. Open curves only: raises InvalidInput for closed curves, knots that are not\n"
      "interior, negative times or tolerance.");
  m.def(
      "reparametrize", py::overload_cast<const Curve&, double, double>(&reparametrize), py::arg("curve"),
      py::arg("start"), py::arg("end"),
      "The same curve on the domain [start, end]: every knot mapped by the affine map of the domain onto it\n"
      "(the ends exactly). Raises InvalidInput unless start < end are finite, or when two distinct knots\n"
      "would round to one value.");
  m.def("normalize_knots", py::overload_cast<const Curve&>(&normalize_knots), py::arg("curve"),
        "The same curve on the domain [0, 1].");
  py::class_<Reduction>(m, "Reduction", "Result of reduce_degree on a curve.")
      .def_readonly("curve", &Reduction::curve, "The curve one degree lower.")
      .def_readonly("deviation_bound", &Reduction::deviation_bound,
                    "Proven bound on the distance between the reduced and the original curve.")
      .def(
          "__repr__",
          [](const Reduction& r) {
            return "Reduction(degree=" + std::to_string(r.curve.degree) +
                   ", deviation_bound=" + py::repr(py::float_(r.deviation_bound)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def(
      "reduce_degree", py::overload_cast<const Curve&, double>(&reduce_degree), Release(), py::arg("curve"),
      py::arg("tolerance"),
      "Lowers the degree by one (each Bézier piece by the inverse of elevation, onto the knots with one\n"
      "copy less: by blossoms or by knot removal, the smaller proven bound kept): returns a Reduction whose\n"
      "bound is proven by elevating back.\n\n"
      "Raises InvalidInput for a closed curve, degree 1, a bad tolerance, and when the bound exceeds the\n"
      "tolerance (the message names both); reduce_degree(elevate_degree(c), t) is c.");
}

void bind_surface_operations(py::module_& m) {
  py::class_<SurfaceRemoval>(m, "SurfaceRemoval", "Result of remove_knot on a surface.")
      .def_readonly("surface", &SurfaceRemoval::surface, "The surface after removal.")
      .def_readonly("removed", &SurfaceRemoval::removed, "How many copies of the knot were removed.")
      .def_readonly("deviation_bound", &SurfaceRemoval::deviation_bound,
                    "Proven bound on the distance between the old and the new surface.")
      .def(
          "__repr__",
          [](const SurfaceRemoval& r) {
            return "SurfaceRemoval(removed=" + std::to_string(r.removed) +
                   ", deviation_bound=" + py::repr(py::float_(r.deviation_bound)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def("remove_knot", py::overload_cast<const Surface&, Direction, double, int, double>(&remove_knot),
        Release(), py::arg("surface"), py::arg("direction"), py::arg("t"), py::arg("times"),
        py::arg("tolerance"),
        "Removes up to `times` copies of the interior knot t of `direction` while the surface moves by at\n"
        "most `tolerance` (every line of the net along it at once). Returns a SurfaceRemoval.");
  m.def("elevate_degree", py::overload_cast<const Surface&, Direction, int>(&elevate_degree), Release(),
        py::arg("surface"), py::arg("direction"), py::arg("times") = 1,
        "Raises the degree of `direction` by `times`; the surface is unchanged.");
  py::class_<SurfaceReduction>(m, "SurfaceReduction", "Result of reduce_degree on a surface.")
      .def_readonly("surface", &SurfaceReduction::surface, "The surface one degree lower in the direction.")
      .def_readonly("deviation_bound", &SurfaceReduction::deviation_bound,
                    "Proven bound on the distance between the reduced and the original surface.")
      .def(
          "__repr__",
          [](const SurfaceReduction& r) {
            return "SurfaceReduction(degree=(" + std::to_string(r.surface.degree[0]) + ", " +
                   std::to_string(r.surface.degree[1]) +
                   "), deviation_bound=" + py::repr(py::float_(r.deviation_bound)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def("reduce_degree", py::overload_cast<const Surface&, Direction, double>(&reduce_degree), Release(),
        py::arg("surface"), py::arg("direction"), py::arg("tolerance"),
        "Lowers the degree of `direction` by one (the curve algorithm on every line of the net). Returns a\n"
        "SurfaceReduction; raises InvalidInput when the bound exceeds the tolerance.");
  m.def(
      "split_bezier", py::overload_cast<const Surface&>(&split_bezier), Release(), py::arg("surface"),
      "The Bézier patches (list of Surface): patch (a, b) of the a-th span of u and the b-th of v at index\n"
      "a·(spans of v) + b.");
  m.def("reverse", py::overload_cast<const Surface&, Direction>(&reverse), py::arg("surface"),
        py::arg("direction"), "The same surface traversed backwards in `direction` (on the same domain).");
  m.def("swap_uv", &swap_uv, py::arg("surface"),
        "The same surface with u and v exchanged: S'(v, u) = S(u, v).");
  m.def("reparametrize", py::overload_cast<const Surface&, Direction, double, double>(&reparametrize),
        py::arg("surface"), py::arg("direction"), py::arg("start"), py::arg("end"),
        "The same surface on [start, end] in `direction` (its knots mapped affinely, the ends exactly).");
  m.def("normalize_knots", py::overload_cast<const Surface&>(&normalize_knots), py::arg("surface"),
        "The same surface on [0, 1] × [0, 1].");
  py::class_<Curvature>(
      m, "Curvature",
      "Curvatures of a 3-D surface at a point (curvature): positive where the surface bends\n"
      "towards `normal`.")
      .def_readonly("point", &Curvature::point, "S(u, v).")
      .def_readonly("normal", &Curvature::normal, "The unit normal S_u × S_v / |S_u × S_v|.")
      .def_readonly("gaussian", &Curvature::gaussian, "K = k1·k2 = (LN − M²) / (EG − F²).")
      .def_readonly("mean", &Curvature::mean, "H = (k1 + k2) / 2 = (EN − 2FM + GL) / (2(EG − F²)).")
      .def_property_readonly(
          "principal", [](const Curvature& k) { return py::make_tuple(k.principal[0], k.principal[1]); },
          "(k1, k2), k1 ≥ k2.")
      .def_property_readonly(
          "directions", [](const Curvature& k) { return py::make_tuple(k.directions[0], k.directions[1]); },
          "The unit principal directions in space (of k1, then k2 = normal × the first); at an umbilic the\n"
          "first is S_u's.")
      .def(
          "__repr__",
          [](const Curvature& k) {
            return "Curvature(gaussian=" + py::repr(py::float_(k.gaussian)).cast<std::string>() +
                   ", mean=" + py::repr(py::float_(k.mean)).cast<std::string>() + ", principal=(" +
                   py::repr(py::float_(k.principal[0])).cast<std::string>() + ", " +
                   py::repr(py::float_(k.principal[1])).cast<std::string>() + "))";
          },
          "Short description.");
  m.def("curvature", &curvature, py::arg("surface"), py::arg("u"), py::arg("v"),
        "Gaussian, mean and principal curvatures and directions at (u, v), from the fundamental forms.\n\n"
        "Raises InvalidInput outside the domain, for a surface that is not 3-D, and where the first\n"
        "fundamental form is singular (a pole, a collapsed edge).");
}

void bind_surface(py::module_& m) {
  py::enum_<Direction>(m, "Direction", "Parameter direction of a surface.")
      .value("u", Direction::u, "First direction (rows of the control net).")
      .value("v", Direction::v, "Second direction (columns of the control net).")
      // enum_'s own `value` property has no docstring.
      .def_property_readonly(
          "value", [](Direction d) { return static_cast<int>(d); }, "The integer value (u = 0, v = 1).");
  py::class_<Surface>(
      m, "Surface",
      "A tensor-product B-spline or NURBS surface (immutable). Control point (i, j) — i along u,\n"
      "j along v — is row i·nv + j of P.")
      .def(py::init(&make_surface_from), py::arg("degree"), py::arg("knots"), py::arg("points"),
           py::arg("weights") = py::none(), py::arg("count") = py::none(),
           "Validated surface (make_surface).\n\n"
           "degree: (p, q). knots: (knots_u, knots_v). points: (nu, nv, dim), or (nu·nv, dim) with\n"
           "count=(nu, nv). weights: None, (nu, nv) or (nu·nv,) positive values.\n"
           "Raises InvalidInput with the library's message for any invalid input.")
      .def_property_readonly(
          "degree", [](const Surface& s) { return py::make_tuple(s.degree[0], s.degree[1]); },
          "Degrees (p, q).")
      .def_property_readonly(
          "knots",
          [](const Surface& s) { return py::make_tuple(vector_array(s.knots[0]), vector_array(s.knots[1])); },
          "Knot vectors (knots_u, knots_v) as 1-D arrays.")
      .def_property_readonly(
          "count", [](const Surface& s) { return py::make_tuple(s.count[0], s.count[1]); },
          "Control net size (nu, nv).")
      .def_property_readonly(
          "P", [](const Surface& s) { return Points(s.P); },
          "Stored control rows (nu·nv, dim + rational), homogeneous (w·x, w) when rational.")
      .def_readonly("rational", &Surface::rational, "True for a NURBS (weighted) surface.")
      .def_property_readonly(
          "points",
          [](const Surface& s) {
            return grid_points(cartesian_points(s), static_cast<std::size_t>(s.count[0]),
                               static_cast<std::size_t>(s.count[1]));
          },
          "Cartesian control points (nu, nv, dim), divided by w when rational (what the constructor takes).")
      .def_property_readonly(
          "weights",
          [](const Surface& s) {
            const Eigen::VectorXd w = weights(s);
            py::array_t<double> out(
                {static_cast<py::ssize_t>(s.count[0]), static_cast<py::ssize_t>(s.count[1])});
            std::copy(w.data(), w.data() + w.size(), out.mutable_data());
            return out;
          },
          "Weights (nu, nv); ones for a non-rational surface.")
      .def_property_readonly(
          "domain",
          [](const Surface& s) {
            return py::make_tuple(as_tuple(domain(s, Direction::u)), as_tuple(domain(s, Direction::v)));
          },
          "The parameter domains ((u0, u1), (v0, v1)).")
      .def_property_readonly(
          "dimension", [](const Surface& s) { return dimension(s); }, "Cartesian dimension.")
      .def(
          "attractor",
          [](const Surface& s, int depth, std::int64_t max_bytes) {
            const std::size_t limit = count_arg(max_bytes, "Surface.attractor: max_bytes");
            py::gil_scoped_release unlocked;
            return cifs::ifs::attractor(s, depth, limit);
          },
          py::arg("depth"), py::kw_only(), py::arg("max_bytes") = std::int64_t{1} << 30,
          "The surface as the attractor of its tensor-product automaton at `depth` (ifs::attractor): its\n"
          "watertight quad mesh (io.Mesh, the layout of ifs.surface_mesh) with Cartesian vertices, rational "
          "or\n"
          "not. Raises InvalidInput for a negative depth or a mesh above max_bytes.")
      .def(
          "evaluate",
          [](const Surface& s, const py::object& u, const py::object& v) -> py::object {
            bool u_scalar = false, v_scalar = false;
            const std::vector<double> us = parameters_from(u, "Surface.evaluate: u", u_scalar);
            const std::vector<double> vs = parameters_from(v, "Surface.evaluate: v", v_scalar);
            if (u_scalar && v_scalar) return py::cast(evaluate(s, us[0], vs[0]));
            if (us.size() != vs.size())
              throw InvalidInput("Surface.evaluate: u and v hold " + std::to_string(us.size()) + " and " +
                                 std::to_string(vs.size()) + " parameters (use evaluate_grid for a grid)");
            Points points(static_cast<Eigen::Index>(us.size()), dimension(s));
            for (std::size_t i = 0; i < us.size(); ++i)
              points.row(static_cast<Eigen::Index>(i)) = evaluate(s, us[i], vs[i]);
            return py::cast(std::move(points));
          },
          py::arg("u"), py::arg("v"),
          "The surface at (u, v): numbers give one point (1-D array), 1-D arrays of equal length the points\n"
          "(len(u), dim) at the pairs (u[i], v[i]) (nurbs.evaluate(surface, u, v) for each).\n\n"
          "Raises InvalidInput outside the domain.")
      .def(
          "evaluate_grid",
          [](const Surface& s, const std::vector<double>& us, const std::vector<double>& vs) {
            return surface_grid(s, us, vs);
          },
          py::arg("us"), py::arg("vs"),
          "Points on the grid us × vs: array (len(us), len(vs), dim), [a, b] = S(us[a], vs[b])\n"
          "(nurbs.evaluate_grid). Raises InvalidInput for parameters outside the domain.")
      .def(
          "insert",
          [](const Surface& s, Direction direction, double knot, int times) {
            return insert_knot(s, direction, knot, times);
          },
          py::arg("direction"), py::arg("knot"), py::arg("times") = 1,
          "A new surface with `knot` inserted `times` times in `direction` (nurbs.insert_knot); this one is\n"
          "unchanged. Raises InvalidInput outside the domain or beyond multiplicity degree.")
      .def(
          "__eq__",
          [](const Surface& a, const py::object& other) -> py::object {
            if (!py::isinstance<Surface>(other)) return py::reinterpret_borrow<py::object>(Py_NotImplemented);
            const auto& b = other.cast<const Surface&>();
            return py::bool_(a.degree == b.degree && a.count == b.count && a.rational == b.rational &&
                             a.knots == b.knots && a.P.rows() == b.P.rows() && a.P.cols() == b.P.cols() &&
                             a.P == b.P);
          },
          py::arg("other"),
          "Exact equality: same degrees, knots, net size, stored control rows and rational flag.")
      .def("__hash__", &surface_hash, "A hash consistent with == (surfaces are immutable).")
      .def(
          "__copy__", [](const Surface& s) { return s; }, "A copy (surfaces are immutable).")
      .def(
          "__deepcopy__", [](const Surface& s, const py::object& /*memo*/) { return s; }, py::arg("memo"),
          "A copy (surfaces are immutable).")
      .def(py::pickle(&surface_state, &surface_from_state))
      .def("__repr__", &surface_repr, "Short description: degrees, knots, net size, dimension, domains.");

  m.def("dimension", py::overload_cast<const Surface&>(&dimension), py::arg("surface"),
        "Cartesian dimension.");
  m.def(
      "domain", [](const Surface& s, Direction dir) { return as_tuple(domain(s, dir)); }, py::arg("surface"),
      py::arg("direction"), "The parameter domain (start, end) in one direction.");
  m.def("cartesian_points", py::overload_cast<const Surface&>(&cartesian_points), py::arg("surface"),
        "Cartesian control points (nu·nv, dim).");
  m.def("weights", py::overload_cast<const Surface&>(&weights), py::arg("surface"),
        "Weights (nu·nv,); ones for a non-rational surface.");
  m.def("evaluate", py::overload_cast<const Surface&, double, double>(&evaluate), py::arg("surface"),
        py::arg("u"), py::arg("v"),
        "Surface point at (u, v) (1-D array).\n\nRaises InvalidInput outside the domain.");
  m.def(
      "evaluate_grid",
      [](const Surface& s, const std::vector<double>& us, const std::vector<double>& vs) {
        return surface_grid(s, us, vs);
      },
      py::arg("surface"), py::arg("us"), py::arg("vs"),
      "Points on the grid us × vs: array (len(us), len(vs), dim), [a, b] = S(us[a], vs[b]) — the shape\n"
      "Surface takes. Raises InvalidInput for parameters outside the domain.");
  m.def("derivatives", py::overload_cast<const Surface&, double, double, int>(&derivatives),
        py::arg("surface"), py::arg("u"), py::arg("v"), py::arg("order"),
        "Partial derivatives ∂^{k+l}S/∂u^k∂v^l for k + l ≤ order: array ((order+1)², dim),\n"
        "row k·(order + 1) + l (rows with k + l > order are zero).\n\n"
        "Raises InvalidInput for an order outside 0 … kMaxDegree or (u, v) outside the domain.");
  m.def("normal", &normal, py::arg("surface"), py::arg("u"), py::arg("v"),
        "Unit normal S_u × S_v / |S_u × S_v| (3 values).\n\n"
        "Raises InvalidInput where it is undefined or when the surface is not 3-D.");
  m.def("insert_knot", py::overload_cast<const Surface&, Direction, double, int>(&insert_knot),
        py::arg("surface"), py::arg("direction"), py::arg("t"), py::arg("times") = 1,
        "Inserts t `times` times in one direction; the surface is unchanged.\n\n"
        "Raises InvalidInput outside the domain or beyond multiplicity degree.");
  m.def(
      "refine",
      [](const Surface& s, Direction dir, const std::vector<double>& knots) { return refine(s, dir, knots); },
      Release(), py::arg("surface"), py::arg("direction"), py::arg("new_knots"),
      "Inserts many knots in one direction; the surface is unchanged.\n\nRaises InvalidInput as "
      "insert_knot.");
  m.def("refine_midpoints", py::overload_cast<const Surface&>(&refine_midpoints), Release(),
        py::arg("surface"), "Inserts the midpoint of every non-empty span in both directions.");
  m.def("direction_curve", py::overload_cast<const Surface&, Direction>(&direction_curve), py::arg("surface"),
        py::arg("direction"),
        "The curve of control lines along `direction`: each row of its points is a whole line of the net,\n"
        "flattened (stored coordinates).");
  m.def(
      "split",
      [](const Surface& s, Direction dir, double t) {
        auto parts = split(s, dir, t);
        return py::make_tuple(std::move(parts[0]), std::move(parts[1]));
      },
      py::arg("surface"), py::arg("direction"), py::arg("t"),
      "The surface cut at t in `direction` (strictly inside its domain): (first, second), on [start, t]\n"
      "and [t, end], each clamped at t and keeping the original parameters.");
  m.def("iso_curve", &iso_curve, Release(), py::arg("surface"), py::arg("direction"), py::arg("t"),
        "The iso-parametric curve at parameter t of `direction`, running along the other one:\n"
        "iso_curve(s, Direction.u, t) evaluated at v is S(t, v), exactly. Raises InvalidInput outside the "
        "domain.");
  bind_surface_operations(m);
}

void bind_doubling(py::module_& m) {
  py::enum_<Half>(m, "Half", "Halves of a segment after inserting its midpoint.")
      .value("G", Half::G, "Left half.")
      .value("D", Half::D, "Right half.")
      .def_property_readonly(
          "value", [](Half h) { return static_cast<int>(h); }, "The integer value (G = 0, D = 1).");
  m.def(
      "validate_window", [](const Window& w, int degree) { validate_window(w, degree); }, py::arg("window"),
      py::arg("degree"),
      "Checks a window: 2d − 1 finite non-negative inter-knot lengths with a positive centre.\n\n"
      "Raises InvalidInput otherwise.");
  m.def(
      "child_window",
      [](const Window& w, int degree, Half half) { return vector_array(child_window(w, degree, half)); },
      py::arg("window"), py::arg("degree"), py::arg("half"),
      "Window (1-D array) of the G or D half after knot doubling, scaled by 2.\n\nRaises InvalidInput for a "
      "bad window.");
  m.def(
      "subdivision_matrix",
      [](const Window& w, int degree, Half half) { return subdivision_matrix(w, degree, half); },
      py::arg("window"), py::arg("degree"), py::arg("half"),
      "(d + 1, d + 1) matrix M with Q = M·P: the control points of the G or D half from the segment's.\n\n"
      "Raises InvalidInput for a bad window.");
  m.def(
      "segment_window",
      [](const Knots& knots, int degree, int span) {
        check_span(knots, degree, span);
        return vector_array(segment_window(knots, degree, span));
      },
      py::arg("knots"), py::arg("degree"), py::arg("span"),
      "The window (2d − 1 inter-knot lengths, 1-D array) of the segment on the non-empty `span`.\n\n"
      "Raises InvalidInput for invalid knots or span.");
}

/// A grid of points (nu, nv, dim) as a fitting Grid.
Grid grid_from(const DoubleArray& points) {
  if (points.ndim() != 3)
    throw InvalidInput("points: expected a grid (nu, nv, dim), got shape " + shape_text(points));
  Grid g;
  g.count = {points.shape(0), points.shape(1)};
  g.points = Eigen::Map<const Points>(points.data(), g.count[0] * g.count[1], points.shape(2));
  return g;
}

Point optional_point(const std::optional<DoubleArray>& a, const char* where) {
  if (!a) return {};
  const Eigen::VectorXd v = to_vector(*a, where);
  return v.transpose();
}

void bind_fit(py::module_& m) {
  py::class_<CurveFit>(m, "CurveFit", "A fitted curve and its distances to the data (fit_distances).")
      .def_readonly("curve", &CurveFit::curve, "The curve.")
      .def_property_readonly(
          "parameters", [](const CurveFit& f) { return vector_array(f.parameters); },
          "The data points' parameters (1-D array).")
      .def_readonly("point_distance", &CurveFit::point_distance,
                    "max_k |C(u_k) − Q_k|: every data point is at most this far from the curve.")
      .def_readonly(
          "polyline_bound", &CurveFit::polyline_bound,
          "Proven bound on sup |C(u) − L(u)|, L the data polyline on its parameters: the curve and\n"
          "the polyline are within this (Hausdorff) distance of each other.")
      .def(
          "__repr__",
          [](const CurveFit& f) {
            return "CurveFit(control_points=" + std::to_string(distinct_count(f.curve)) +
                   ", point_distance=" + py::repr(py::float_(f.point_distance)).cast<std::string>() +
                   ", polyline_bound=" + py::repr(py::float_(f.polyline_bound)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def(
      "fit_parameters",
      [](const py::object& points, const std::string& parametrization, bool closed) {
        return vector_array(
            fit_parameters(points_from(points, "points"), parametrization_named(parametrization), closed));
      },
      py::arg("points"), py::arg("parametrization") = "chord_length", py::arg("closed") = false,
      "Parameters in [0, 1] of the rows of points (n, dim): 'uniform', 'chord_length' or 'centripetal'.\n\n"
      "closed: the chord back to the first point counts (the period is [0, 1]). Raises InvalidInput for\n"
      "fewer than 2 points or (chord kinds) coincident consecutive points.");
  m.def(
      "interpolate",
      [](const py::object& points, int degree, const std::string& parametrization,
         const std::optional<DoubleArray>& start_derivative, const std::optional<DoubleArray>& end_derivative,
         bool closed) {
        InterpolateOptions o;
        o.degree = degree;
        o.parametrization = parametrization_named(parametrization);
        o.start_derivative = optional_point(start_derivative, "start_derivative");
        o.end_derivative = optional_point(end_derivative, "end_derivative");
        o.closed = closed;
        const Points P = points_from(points, "points");
        const py::gil_scoped_release release;
        return interpolate(P, o);
      },
      py::arg("points"), py::arg("degree") = 3, py::arg("parametrization") = "chord_length",
      py::arg("start_derivative") = py::none(), py::arg("end_derivative") = py::none(),
      py::arg("closed") = false,
      "The curve of `degree` through every row of points (n, dim): C(u_k) = Q_k with u =\n"
      "fit_parameters(points, parametrization, closed). Open: clamped on [0, 1], averaged knots;\n"
      "start_derivative / end_derivative: dC/du at the ends (degree ≥ 2). closed: a periodic curve\n"
      "(a last point equal to the first is dropped). Raises InvalidInput for too few points, coincident\n"
      "consecutive points (chord kinds), or a singular system.");
  m.def(
      "approximate",
      [](const py::object& points, int degree, std::optional<Eigen::Index> control_points,
         std::optional<double> tolerance, const std::string& parametrization, const std::string& measure,
         const std::optional<DoubleArray>& weights, bool fix_ends) {
        ApproximateOptions o;
        o.degree = degree;
        o.control_points = control_points.value_or(0);
        o.tolerance = tolerance.value_or(0);
        if (control_points && *control_points <= 0)
          throw InvalidInput("control_points: " + std::to_string(*control_points) + " is not positive");
        if (tolerance && !(*tolerance > 0)) throw InvalidInput("tolerance: expected a positive number");
        if (!control_points && !tolerance)
          throw InvalidInput("approximate: give control_points or tolerance");
        o.parametrization = parametrization_named(parametrization);
        o.measure = fit_measure_named(measure);
        o.weights = optional_weights(weights);
        o.fix_ends = fix_ends;
        const Points P = points_from(points, "points");
        const py::gil_scoped_release release;
        return approximate(P, o).curve;
      },
      py::arg("points"), py::arg("degree") = 3, py::arg("control_points") = py::none(),
      py::arg("tolerance") = py::none(), py::arg("parametrization") = "chord_length",
      py::arg("measure") = "points", py::arg("weights") = py::none(), py::arg("fix_ends") = true,
      "Least-squares curve of `degree` near the rows of points (n, dim), clamped on [0, 1].\n\n"
      "control_points=N: N control points (degree + 1 … n; n interpolates). tolerance=E: the fewest\n"
      "knots, inserted where the error is largest, so that every point is within E of the curve\n"
      "(measure='points') or the curve within E of the data polyline (measure='polyline', a proven\n"
      "bound). weights: one positive weight per point. fix_ends: the curve starts and ends on the data.\n"
      "fit_distances(curve, points) gives the distances. Raises InvalidInput for bad input.");
  m.def(
      "fit_distances",
      [](const Curve& c, const py::object& points, std::optional<std::vector<double>> parameters,
         const std::string& parametrization) {
        const Points P = points_from(points, "points");
        std::vector<double> u = parameters
                                    ? std::move(*parameters)
                                    : fit_parameters(P, parametrization_named(parametrization), c.closed);
        const py::gil_scoped_release release;
        return measure_fit(c, P, std::move(u));
      },
      py::arg("curve"), py::arg("points"), py::arg("parameters") = py::none(),
      py::arg("parametrization") = "chord_length",
      "A CurveFit: the distances of a (non-rational) curve to points (n, dim) at parameters (default:\n"
      "fit_parameters(points, parametrization, curve.closed)).");
  m.def(
      "interpolate_surface",
      [](const DoubleArray& points, std::array<int, 2> degree, const std::string& parametrization) {
        SurfaceFitOptions o;
        o.degree = degree;
        o.parametrization = parametrization_named(parametrization);
        const Grid g = grid_from(points);
        const py::gil_scoped_release release;
        return interpolate_surface(g, o);
      },
      py::arg("points"), py::arg("degree") = std::array<int, 2>{3, 3},
      py::arg("parametrization") = "chord_length",
      "The surface of degree (p, q) through every point of the grid points (nu, nv, dim), clamped on\n"
      "[0, 1]²: curves through the lines in u, then through the control lines in v (parameters averaged\n"
      "over the lines). Raises InvalidInput for too few points or lines that coincide.");
  m.def(
      "approximate_surface",
      [](const DoubleArray& points, std::array<Eigen::Index, 2> control_points, std::array<int, 2> degree,
         const std::string& parametrization) {
        SurfaceFitOptions o;
        o.degree = degree;
        o.control_points = control_points;
        o.parametrization = parametrization_named(parametrization);
        const Grid g = grid_from(points);
        const py::gil_scoped_release release;
        return approximate_surface(g, o);
      },
      py::arg("points"), py::arg("control_points"), py::arg("degree") = std::array<int, 2>{3, 3},
      py::arg("parametrization") = "chord_length",
      "Least-squares surface with control_points (cu, cv) near the grid points (nu, nv, dim): fits with\n"
      "fixed ends in u, then in v; the corners are interpolated. Raises InvalidInput for bad counts.");
}

py::list interval_list(const std::vector<std::array<double, 2>>& intervals) {
  py::list out;
  for (const auto& iv : intervals) out.append(py::make_tuple(iv[0], iv[1]));
  return out;
}

Point point_from(const DoubleArray& a, const char* where) {
  const Eigen::VectorXd v = to_vector(a, where);
  return v.transpose();
}

void bind_measure(py::module_& m) {
  m.def(
      "length",
      [](const Curve& c, std::optional<double> a, std::optional<double> b, double tolerance) {
        const Domain dom = domain(c);
        return arc_length(c, a.value_or(dom.start), b.value_or(dom.end), tolerance).value;
      },
      Release(), py::arg("curve"), py::arg("a") = py::none(), py::arg("b") = py::none(),
      py::arg("tolerance") = 1e-12,
      "Arc length of the curve between the parameters a ≤ b (default: the domain's ends), to `tolerance`\n"
      "relative to the length (adaptive 8-point Gauss–Legendre per span; its error estimate is\n"
      "length_error). Raises InvalidInput for a or b outside the domain or a > b.");
  m.def(
      "length_error",
      [](const Curve& c, std::optional<double> a, std::optional<double> b, double tolerance) {
        const Domain dom = domain(c);
        return arc_length(c, a.value_or(dom.start), b.value_or(dom.end), tolerance).error;
      },
      Release(), py::arg("curve"), py::arg("a") = py::none(), py::arg("b") = py::none(),
      py::arg("tolerance") = 1e-12,
      "The error estimate of length(curve, a, b, tolerance): Σ |G(I) − G(left) − G(right)| over the\n"
      "accepted intervals (G the 8-point rule), an over-estimate where |C′| is smooth.");
  m.def(
      "parameter_at_length",
      [](const Curve& c, double length, std::optional<double> start, double tolerance) {
        return parameter_at_length(c, length, start.value_or(domain(c).start), tolerance);
      },
      Release(), py::arg("curve"), py::arg("length"), py::arg("start") = py::none(),
      py::arg("tolerance") = 1e-12,
      "The parameter u with length(curve, start, u) = length (start: the domain's start): Newton on the\n"
      "length inside a bisection bracket. Raises InvalidInput for a negative length or one beyond the end.");
  py::class_<Frenet>(m, "Frenet", "The Frenet frame of a 2-D or 3-D curve at a parameter (frenet_frame).")
      .def_readonly("point", &Frenet::point, "C(u).")
      .def_readonly("tangent", &Frenet::tangent, "C′/|C′|.")
      .def_property_readonly(
          "normal",
          [](const Frenet& f) -> py::object { return f.normal.size() ? py::cast(f.normal) : py::none(); },
          "The principal normal; None where the curvature is zero (undefined). 2-D: the tangent turned +90°.")
      .def_property_readonly(
          "binormal",
          [](const Frenet& f) -> py::object { return f.binormal.size() ? py::cast(f.binormal) : py::none(); },
          "T × N (3-D, where the normal is defined; else None).")
      .def_readonly("speed", &Frenet::speed, "|C′(u)|.")
      .def_readonly("curvature", &Frenet::curvature,
                    "|C′ × C″| / |C′|³ (2-D: signed, positive turning left).")
      .def_readonly("torsion", &Frenet::torsion,
                    "(C′ × C″)·C‴ / |C′ × C″|² (3-D; 0 where the normal is undefined).")
      .def(
          "__repr__",
          [](const Frenet& f) {
            return "Frenet(curvature=" + py::repr(py::float_(f.curvature)).cast<std::string>() +
                   ", torsion=" + py::repr(py::float_(f.torsion)).cast<std::string>() +
                   ", speed=" + py::repr(py::float_(f.speed)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def("frenet_frame", &frenet_frame, py::arg("curve"), py::arg("u"),
        "The Frenet frame at u: point, tangent, normal, binormal, speed, curvature, torsion (from the\n"
        "derivatives, quotient rule when rational). Raises InvalidInput outside the domain, for a curve\n"
        "that is not 2-D or 3-D, and where C′(u) = 0 (no tangent).");
  py::class_<ClosestPoints>(m, "ClosestPoints", "Every nearest point of a curve to a point (closest_point).")
      .def_readonly("distance", &ClosestPoints::distance, "The smallest distance.")
      .def_property_readonly(
          "parameters", [](const ClosestPoints& r) { return vector_array(r.parameters); },
          "Parameters of the isolated nearest points, ascending (1-D array).")
      .def_readonly("points", &ClosestPoints::points, "Their curve points (k, dim).")
      .def_property_readonly(
          "intervals", [](const ClosestPoints& r) { return interval_list(r.intervals); },
          "Parameter intervals (a, b) on which the curve stays at the distance (a circle about the point).")
      .def(
          "__repr__",
          [](const ClosestPoints& r) {
            return "ClosestPoints(distance=" + py::repr(py::float_(r.distance)).cast<std::string>() +
                   ", parameters=" + std::to_string(r.parameters.size()) +
                   ", intervals=" + std::to_string(r.intervals.size()) + ")";
          },
          "Short description.");
  m.def(
      "closest_point",
      [](const Curve& c, const DoubleArray& point, double tolerance) {
        const Point q = point_from(point, "point");
        const py::gil_scoped_release release;
        return closest_point(c, q, tolerance);
      },
      py::arg("curve"), py::arg("point"), py::arg("tolerance") = 1e-12,
      "The points of the curve nearest to `point`, every one whose distance is within tolerance·size of\n"
      "the smallest (global: convex hulls of the Bézier pieces prune, Newton finishes). Raises\n"
      "InvalidInput for a point of the wrong size.");
  py::class_<SurfaceClosestPoints>(m, "SurfaceClosestPoints",
                                   "Every nearest point of a surface to a point (closest_point).")
      .def_readonly("distance", &SurfaceClosestPoints::distance, "The smallest distance.")
      .def_property_readonly(
          "parameters",
          [](const SurfaceClosestPoints& r) {
            Eigen::MatrixXd uv(static_cast<Eigen::Index>(r.parameters.size()), 2);
            for (std::size_t i = 0; i < r.parameters.size(); ++i)
              uv.row(static_cast<Eigen::Index>(i)) << r.parameters[i][0], r.parameters[i][1];
            return uv;
          },
          "(u, v) of the isolated nearest points, ascending in u then v (k, 2); a pole once.")
      .def_readonly("points", &SurfaceClosestPoints::points, "Their surface points (k, dim).")
      .def_property_readonly(
          "regions",
          [](const SurfaceClosestPoints& r) {
            py::list out;
            for (const auto& x : r.regions) out.append(py::make_tuple(x[0], x[1], x[2], x[3]));
            return out;
          },
          "Parameter rectangles (u0, u1, v0, v1) on which the surface stays at the distance (the centre of "
          "a sphere: the whole domain; a circle: u0 = u1 or v0 = v1).")
      .def(
          "__repr__",
          [](const SurfaceClosestPoints& r) {
            return "SurfaceClosestPoints(distance=" + py::repr(py::float_(r.distance)).cast<std::string>() +
                   ", parameters=" + std::to_string(r.parameters.size()) +
                   ", regions=" + std::to_string(r.regions.size()) + ")";
          },
          "Short description.");
  m.def(
      "closest_point",
      [](const Surface& s, const DoubleArray& point, double tolerance) {
        const Point q = point_from(point, "point");
        const py::gil_scoped_release release;
        return closest_point(s, q, tolerance);
      },
      py::arg("surface"), py::arg("point"), py::arg("tolerance") = 1e-12,
      "The points of the surface nearest to `point`, every one whose distance is within tolerance·size of\n"
      "the smallest (global: the hulls of the Bézier patches prune, edges by the curve closest_point,\n"
      "inside by Newton's method on pieces that hold one critical point at most). Raises InvalidInput for\n"
      "a point of the wrong size or not finite.");
  m.def(
      "intersect_plane",
      [](const Curve& c, const DoubleArray& normal, double offset, double tolerance) {
        const Point n = point_from(normal, "normal");
        PlaneIntersection hit;
        {
          const py::gil_scoped_release release;
          hit = intersect_plane(c, n, offset, tolerance);
        }
        return py::make_tuple(vector_array(hit.parameters), interval_list(hit.intervals));
      },
      py::arg("curve"), py::arg("normal"), py::arg("offset"), py::arg("tolerance") = 1e-12,
      "Where the curve meets the plane normal·x = offset: (parameters, intervals) — every crossing and\n"
      "tangential contact once (1-D array, ascending), and the parameter intervals on which the curve lies\n"
      "in the plane.");
  m.def(
      "intersect_curves",
      [](const Curve& a, const Curve& b, double tolerance) {
        std::vector<CurveIntersection> hits;
        {
          const py::gil_scoped_release release;
          hits = intersect_curves(a, b, tolerance);
        }
        py::list out;
        for (const auto& h : hits) out.append(py::make_tuple(h.u, h.v, h.point));
        return out;
      },
      py::arg("a"), py::arg("b"), py::arg("tolerance") = 1e-9,
      "Where two curves meet, within tolerance·size: a list of (u, v, point), ordered by u; tangential\n"
      "contacts once. Raises InvalidInput for different dimensions or curves that overlap along an arc.");
  m.def(
      "bounding_box",
      [](const Curve& c) {
        Box box;
        {
          const py::gil_scoped_release release;
          box = bounding_box(c);
        }
        return py::make_tuple(box.lower, box.upper);
      },
      py::arg("curve"),
      "The smallest axis-aligned box that holds the curve: (lower, upper), from the extremes of its\n"
      "polynomial (or rational) pieces.");
  m.def(
      "transform", [](const Curve& c, const Eigen::MatrixXd& matrix) { return transform(c, matrix); },
      Release(), py::arg("curve"), py::arg("matrix"),
      "The curve mapped by a (dim + 1)² matrix acting on homogeneous points (x, 1): affine maps keep a\n"
      "polynomial curve polynomial, projective ones make it rational. Raises InvalidInput for a matrix of\n"
      "the wrong size or a weight that would become ≤ 0.");
}

Eigen::Vector3d vector3_from(const DoubleArray& a, const char* where) {
  const Eigen::VectorXd v = to_vector(a, where);
  if (v.size() != 3)
    throw InvalidInput(std::string(where) + ": " + std::to_string(v.size()) + " values, expected 3");
  return v;
}

void bind_construct(py::module_& m) {
  m.def(
      "make_compatible", [](const std::vector<Curve>& curves) { return make_compatible(curves); }, Release(),
      py::arg("curves"),
      "The curves (list of Curve) made compatible: clamped (closed ones opened at their seam), rational\n"
      "when any is, raised to the largest degree, mapped onto the first curve's domain and refined to the\n"
      "union of their knots. Each is the same point set on the affinely mapped parameters; all share\n"
      "degree, knots and number of control points. Raises InvalidInput for no curve or a dimension\n"
      "mismatch.");
  m.def("ruled", &ruled, Release(), py::arg("a"), py::arg("b"),
        "The ruled surface between curves a and b: linear in v on [0, 1], S(u, 0) = a(u) and S(u, 1) = b\n"
        "on its parameter mapped onto a's domain (make_compatible).");
  m.def(
      "extrude",
      [](const Curve& c, const DoubleArray& direction) {
        return extrude(c, point_from(direction, "direction"));
      },
      py::arg("curve"), py::arg("direction"),
      "The translational surface S(u, v) = C(u) + v·direction, v in [0, 1] (exact). Raises InvalidInput for\n"
      "a direction of the wrong size, zero, not finite, or along a straight curve.");
  m.def(
      "revolve",
      [](const Curve& profile, const DoubleArray& axis_point, const DoubleArray& axis_direction,
         double angle) {
        const Eigen::Vector3d o = vector3_from(axis_point, "axis_point"),
                              a = vector3_from(axis_direction, "axis_direction");
        const py::gil_scoped_release release;
        return revolve(profile, o, a, angle);
      },
      py::arg("profile"), py::arg("axis_point"), py::arg("axis_direction"),
      py::arg("angle") = 2 * std::numbers::pi,
      "The surface of revolution of a 3-D profile (u) turned by angle in (0, 2π] about the axis (v in\n"
      "[0, 1]): exact rational quadratic arcs of at most 90° (The NURBS Book A8.1); a full turn closes\n"
      "exactly. Raises InvalidInput for a profile that is not 3-D or lies on the axis, a zero axis, or an\n"
      "angle outside (0, 2π].");
  m.def(
      "loft",
      [](const std::vector<Curve>& curves, int degree_v, const std::string& parametrization) {
        LoftOptions o;
        o.degree_v = degree_v;
        o.parametrization = parametrization_named(parametrization);
        const py::gil_scoped_release release;
        return loft(curves, o);
      },
      py::arg("curves"), py::arg("degree_v") = 3, py::arg("parametrization") = "chord_length",
      "The surface through the curves (skinning, The NURBS Book 10.3): made compatible, then every column\n"
      "of control points interpolated across them (homogeneous when rational) at v-parameters averaged\n"
      "over the columns (loft_parameters); v in [0, 1]. Raises InvalidInput for fewer than 2 curves or\n"
      "degree_v outside 1 … len(curves) − 1.");
  m.def(
      "loft_parameters",
      [](const std::vector<Curve>& curves, const std::string& parametrization) {
        return vector_array(loft_parameters(curves, parametrization_named(parametrization)));
      },
      py::arg("curves"), py::arg("parametrization") = "chord_length",
      "The v-parameter of each curve in loft(curves, …): its iso-curve there is that curve.");
  py::class_<Sweep>(m, "Sweep", "Result of sweep: the surface and its deviation from the exact sweep.")
      .def_readonly("surface", &Sweep::surface, "The swept surface (u: profile, v: trajectory's domain).")
      .def_readonly(
          "deviation", &Sweep::deviation,
          "0 for the translational sweep (exact); for the skinned sweep the largest distance to the\n"
          "profile carried by the frames over a sample (8 parameters between instances, 8 per profile\n"
          "span): a measured figure, not a bound.")
      .def(
          "__repr__",
          [](const Sweep& s) {
            return "Sweep(degree=(" + std::to_string(s.surface.degree[0]) + ", " +
                   std::to_string(s.surface.degree[1]) +
                   "), deviation=" + py::repr(py::float_(s.deviation)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def(
      "sweep",
      [](const Curve& profile, const Curve& trajectory, int instances, int degree_v) {
        SweepOptions o;
        o.instances = instances;
        o.degree_v = degree_v;
        const py::gil_scoped_release release;
        return sweep(profile, trajectory, o);
      },
      py::arg("profile"), py::arg("trajectory"), py::arg("instances") = 0, py::arg("degree_v") = 3,
      "The profile (placed at the trajectory's start) swept along the trajectory; returns a Sweep.\n\n"
      "instances=0: the translational sweep C(u) + T(v) − T(v0), exact. instances=N ≥ 2: the profile\n"
      "carried by the trajectory's rotation-minimizing frames, skinned through N instances (degree_v ≤\n"
      "N − 1): an approximation whose measured deviation is reported.");
  m.def(
      "rotation_minimizing_frames",
      [](const Curve& c, int count, int steps) { return rotation_minimizing_frames(c, count, steps); },
      Release(), py::arg("curve"), py::arg("count"), py::arg("steps") = 64,
      "Rotation-minimizing frames of a 3-D curve at count equally spaced parameters (double reflection,\n"
      "`steps` steps between them): (count, 6), the unit tangent then the unit reference vector.");
}

void bind_volume(py::module_& m) {
  py::class_<Volume>(
      m, "Volume",
      "A trivariate tensor-product B-spline or NURBS volume (immutable). Control point (i, j, k) is row\n"
      "(i·nv + j)·nw + k of P.")
      .def(py::init([](std::array<int, 3> degree, std::array<Knots, 3> knots, const DoubleArray& points,
                       const std::optional<DoubleArray>& weights) {
             if (points.ndim() != 4)
               throw InvalidInput("points: expected (nu, nv, nw, dim), got shape " + shape_text(points));
             const std::array<Eigen::Index, 3> count{points.shape(0), points.shape(1), points.shape(2)};
             for (std::size_t d = 0; d < 3; ++d)
               if (count[d] != control_count(knots[d], degree[d]))
                 throw InvalidInput("points: shape " + shape_text(points) + " does not match the " +
                                    std::to_string(control_count(knots[d], degree[d])) +
                                    " control points of knots[" + std::to_string(d) + "] and degree[" +
                                    std::to_string(d) + "]");
             const Points P =
                 Eigen::Map<const Points>(points.data(), count[0] * count[1] * count[2], points.shape(3));
             Eigen::VectorXd w;
             if (weights) {
               if (weights->size() != count[0] * count[1] * count[2])
                 throw InvalidInput("weights: shape " + shape_text(*weights) + " does not match the " +
                                    std::to_string(count[0]) + " by " + std::to_string(count[1]) + " by " +
                                    std::to_string(count[2]) + " net");
               w = Eigen::Map<const Eigen::VectorXd>(weights->data(), weights->size());
             }
             return make_volume(degree, std::move(knots), count, P, w);
           }),
           py::arg("degree"), py::arg("knots"), py::arg("points"), py::arg("weights") = py::none(),
           "Validated volume (make_volume). degree: (p, q, r). knots: three knot vectors. points: (nu, nv,\n"
           "nw, dim). weights: None or (nu, nv, nw) positive values. Raises InvalidInput for invalid input.")
      .def_property_readonly(
          "degree", [](const Volume& v) { return py::make_tuple(v.degree[0], v.degree[1], v.degree[2]); },
          "Degrees (p, q, r).")
      .def_property_readonly(
          "knots",
          [](const Volume& v) {
            return py::make_tuple(vector_array(v.knots[0]), vector_array(v.knots[1]),
                                  vector_array(v.knots[2]));
          },
          "The three knot vectors.")
      .def_property_readonly(
          "count", [](const Volume& v) { return py::make_tuple(v.count[0], v.count[1], v.count[2]); },
          "(nu, nv, nw).")
      .def_property_readonly(
          "P", [](const Volume& v) { return Points(v.P); },
          "Stored control rows ((nu·nv·nw), dim + rational): homogeneous (w·x, w) when rational.")
      .def_readonly("rational", &Volume::rational, "Whether the volume has weights.")
      .def_property_readonly(
          "dimension", [](const Volume& v) { return dimension(v); }, "Cartesian dimension.")
      .def(
          "evaluate", [](const Volume& vol, double u, double v, double w) { return evaluate(vol, u, v, w); },
          py::arg("u"), py::arg("v"), py::arg("w"),
          "The volume point (Cartesian) at (u, v, w). Raises InvalidInput outside the domain.")
      .def(
          "__repr__",
          [](const Volume& v) {
            return "Volume(degree=(" + std::to_string(v.degree[0]) + ", " + std::to_string(v.degree[1]) +
                   ", " + std::to_string(v.degree[2]) + "), count=(" + std::to_string(v.count[0]) + ", " +
                   std::to_string(v.count[1]) + ", " + std::to_string(v.count[2]) +
                   "), dimension=" + std::to_string(dimension(v)) + (v.rational ? ", rational" : "") + ")";
          },
          "Short description.");
  m.def("insert_knot", py::overload_cast<const Volume&, int, double, int>(&insert_knot), py::arg("volume"),
        py::arg("direction"), py::arg("t"), py::arg("times") = 1,
        "Inserts t `times` times in direction 0 (u), 1 (v) or 2 (w) of a volume; the volume is unchanged.");
  m.def("evaluate", py::overload_cast<const Volume&, double, double, double>(&evaluate), py::arg("volume"),
        py::arg("u"), py::arg("v"), py::arg("w"),
        "Volume point at (u, v, w) (1-D array).\n\nRaises InvalidInput outside the domain.");
  m.def(
      "evaluate_grid",
      [](const Volume& vol, const std::vector<double>& us, const std::vector<double>& vs,
         const std::vector<double>& ws) {
        const Points grid = evaluate_grid(vol, us, vs, ws);
        py::array_t<double> out({static_cast<py::ssize_t>(us.size()), static_cast<py::ssize_t>(vs.size()),
                                 static_cast<py::ssize_t>(ws.size()), static_cast<py::ssize_t>(grid.cols())});
        std::copy(grid.data(), grid.data() + grid.size(), out.mutable_data());
        return out;
      },
      py::arg("volume"), py::arg("us"), py::arg("vs"), py::arg("ws"),
      "Points on the grid us × vs × ws: array (len(us), len(vs), len(ws), dim), [a, b, c] = V(us[a], vs[b],\n"
      "ws[c]). Raises InvalidInput for parameters outside the domain, naming the direction.");
  m.def("derivatives", py::overload_cast<const Volume&, double, double, double, int>(&derivatives),
        py::arg("volume"), py::arg("u"), py::arg("v"), py::arg("w"), py::arg("order"),
        "Partial derivatives ∂^{a+b+c}V/∂u^a∂v^b∂w^c for a + b + c ≤ order: array ((order+1)³, dim), row\n"
        "(a·(order + 1) + b)·(order + 1) + c (rows with a + b + c > order are zero). Quotient rule when "
        "rational.\n\n"
        "Raises InvalidInput for an order outside 0 … kMaxDegree or (u, v, w) outside the domain.");
  m.def("direction_curve", py::overload_cast<const Volume&, int>(&direction_curve), py::arg("volume"),
        py::arg("direction"),
        "The curve of control slabs along `direction` (0, 1, 2): each row of its points is a whole slab of\n"
        "the net (the other two directions in order, flattened stored coordinates).");
  m.def(
      "refine",
      [](const Volume& vol, int direction, const std::vector<double>& knots) {
        return refine(vol, direction, knots);
      },
      Release(), py::arg("volume"), py::arg("direction"), py::arg("new_knots"),
      "Inserts many knots in one direction (0, 1, 2) of a volume; the volume is unchanged.");
  py::class_<VolumeRemoval>(m, "VolumeRemoval", "Result of remove_knot on a volume.")
      .def_readonly("volume", &VolumeRemoval::volume, "The volume after removal.")
      .def_readonly("removed", &VolumeRemoval::removed, "How many copies of the knot were removed.")
      .def_readonly("deviation_bound", &VolumeRemoval::deviation_bound,
                    "Proven bound on the distance between the old and the new volume.")
      .def(
          "__repr__",
          [](const VolumeRemoval& r) {
            return "VolumeRemoval(removed=" + std::to_string(r.removed) +
                   ", deviation_bound=" + py::repr(py::float_(r.deviation_bound)).cast<std::string>() + ")";
          },
          "Short description.");
  m.def("remove_knot", py::overload_cast<const Volume&, int, double, int, double>(&remove_knot), Release(),
        py::arg("volume"), py::arg("direction"), py::arg("t"), py::arg("times"), py::arg("tolerance"),
        "Removes up to `times` copies of the interior knot t of `direction` while the volume moves by at\n"
        "most `tolerance` (every line of the net along it at once). Returns a VolumeRemoval.");
  m.def("elevate_degree", py::overload_cast<const Volume&, int, int>(&elevate_degree), Release(),
        py::arg("volume"), py::arg("direction"), py::arg("times") = 1,
        "Raises the degree of `direction` by `times`; the volume is unchanged.");
  m.def(
      "split",
      [](const Volume& vol, int direction, double t) {
        auto parts = split(vol, direction, t);
        return py::make_tuple(std::move(parts[0]), std::move(parts[1]));
      },
      py::arg("volume"), py::arg("direction"), py::arg("t"),
      "The volume cut at t in `direction` (strictly inside its domain): (first, second), on [start, t] and\n"
      "[t, end], each clamped at t and keeping the original parameters.");
  m.def("iso_surface", &iso_surface, Release(), py::arg("volume"), py::arg("direction"), py::arg("t"),
        "The Surface at parameter t of `direction`, in the other two directions in order: iso_surface(vol,\n"
        "0, t) evaluated at (v, w) is V(t, v, w), exactly. Raises InvalidInput outside the domain.");
  m.def("reverse", py::overload_cast<const Volume&, int>(&reverse), py::arg("volume"), py::arg("direction"),
        "The same volume traversed backwards in `direction` (on the same domain).");
  m.def("reparametrize", py::overload_cast<const Volume&, int, double, double>(&reparametrize),
        py::arg("volume"), py::arg("direction"), py::arg("start"), py::arg("end"),
        "The same volume on [start, end] in `direction` (its knots mapped affinely, the ends exactly).");
  m.def("normalize_knots", py::overload_cast<const Volume&>(&normalize_knots), py::arg("volume"),
        "The same volume on [0, 1]³.");
}
}  // namespace

void bind_nurbs(py::module_& m) {
  bind_knots(m);
  bind_curve(m);
  bind_refine(m);
  bind_surface(m);
  bind_doubling(m);
  bind_fit(m);
  bind_measure(m);
  bind_construct(m);
  bind_volume(m);
}

}  // namespace cifs::python
