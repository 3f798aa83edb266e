// SPDX-License-Identifier: MIT
// cifs::occt — STEP and IGES through OpenCASCADE: cifs curves and surfaces to Geom_BSpline* and back,
// and the files through OCCT's translators. The only source that includes OCCT headers.
#include "cifs/occt/occt.hpp"

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_Line.hxx>
#include <Geom_Plane.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <IGESData_IGESWriter.hxx>
#include <IGESSelect_WorkLibrary.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Precision.hxx>
#include <STEPConstruct_UnitContext.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <StepData_Protocol.hxx>
#include <StepData_StepModel.hxx>
#include <StepData_StepWriter.hxx>
#include <StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx.hxx>
#include <StepRepr_GlobalUnitAssignedContext.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <variant>

#include "cifs/errors.hpp"

namespace cifs::occt {
namespace {

// ---- cifs → OCCT ----------------------------------------------------------------------------------

/// Distinct knots and their multiplicities, from a full knot vector (equal doubles are one knot).
void compress_knots(const nurbs::Knots& flat, TColStd_Array1OfReal& knots, TColStd_Array1OfInteger& mults) {
  std::vector<double> values;
  std::vector<int> counts;
  for (double t : flat) {
    if (!values.empty() && values.back() == t) {
      ++counts.back();
    } else {
      values.push_back(t);
      counts.push_back(1);
    }
  }
  knots.Resize(1, static_cast<int>(values.size()), false);
  mults.Resize(1, static_cast<int>(values.size()), false);
  for (std::size_t i = 0; i < values.size(); ++i) {
    knots(static_cast<int>(i) + 1) = values[i];
    mults(static_cast<int>(i) + 1) = counts[i];
  }
}

/// Stored row `row` of a net as an OCCT point: Cartesian (divided by its weight when rational), padded
/// with zeros up to 3-D.
gp_Pnt point_of(const Points& P, Eigen::Index row, int dim, bool rational) {
  const double w = rational ? P(row, dim) : 1.0;
  double xyz[3] = {0, 0, 0};
  for (int k = 0; k < dim; ++k) xyz[k] = P(row, k) / w;
  return {xyz[0], xyz[1], xyz[2]};
}

void check_dimension(int dim, std::string_view what) {
  if (dim > 3)
    throw InvalidInput(std::string(what) + " is " + std::to_string(dim) +
                       "-D: STEP and IGES hold points of 1 to 3 coordinates");
}

/// The curve as OCCT's non-periodic B-spline with the same knots and control points. A closed cifs curve
/// is stored expanded (its last d points repeat the first d, its knot vector periodic): that is already a
/// non-periodic unclamped B-spline of the same points.
Handle(Geom_BSplineCurve) to_occt(const nurbs::Curve& c) {
  const int dim = nurbs::dimension(c);
  const auto n = static_cast<int>(c.P.rows());
  TColgp_Array1OfPnt poles(1, n);
  TColStd_Array1OfReal weights(1, n);
  for (int i = 0; i < n; ++i) {
    poles(i + 1) = point_of(c.P, i, dim, c.rational);
    weights(i + 1) = c.rational ? c.P(i, dim) : 1.0;
  }
  TColStd_Array1OfReal knots(1, 1);
  TColStd_Array1OfInteger mults(1, 1);
  compress_knots(c.knots, knots, mults);
  if (c.rational) return new Geom_BSplineCurve(poles, weights, knots, mults, c.degree);
  return new Geom_BSplineCurve(poles, knots, mults, c.degree);
}

Handle(Geom_BSplineSurface) to_occt(const nurbs::Surface& s) {
  const int dim = nurbs::dimension(s);
  const auto nu = static_cast<int>(s.count[0]), nv = static_cast<int>(s.count[1]);
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  TColStd_Array2OfReal weights(1, nu, 1, nv);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const Eigen::Index row = Eigen::Index{i} * nv + j;
      poles(i + 1, j + 1) = point_of(s.P, row, dim, s.rational);
      weights(i + 1, j + 1) = s.rational ? s.P(row, dim) : 1.0;
    }
  TColStd_Array1OfReal uknots(1, 1), vknots(1, 1);
  TColStd_Array1OfInteger umults(1, 1), vmults(1, 1);
  compress_knots(s.knots[0], uknots, umults);
  compress_knots(s.knots[1], vknots, vmults);
  if (s.rational)
    return new Geom_BSplineSurface(poles, weights, uknots, vknots, umults, vmults, s.degree[0], s.degree[1]);
  return new Geom_BSplineSurface(poles, uknots, vknots, umults, vmults, s.degree[0], s.degree[1]);
}

// ---- OCCT → cifs ----------------------------------------------------------------------------------

nurbs::Knots flat_knots(const TColStd_Array1OfReal& sequence) {
  return {sequence.begin(), sequence.end()};
}

/// A non-periodic OCCT B-spline curve, or a periodic one as a closed cifs curve (one period).
nurbs::Curve from_occt(const Geom_BSplineCurve& c) {
  const int n = c.NbPoles();
  Points P(n, 3);
  Eigen::VectorXd w;
  if (c.IsRational()) w.resize(n);
  if (!c.IsPeriodic()) {
    for (int i = 0; i < n; ++i) {
      const gp_Pnt& p = c.Pole(i + 1);
      P.row(i) << p.X(), p.Y(), p.Z();
      if (c.IsRational()) w(i) = c.Weight(i + 1);
    }
    return nurbs::make_curve(c.Degree(), flat_knots(c.KnotSequence()), P, w);
  }
  // Periodic: the period's breakpoints are the knots but the last, each as often as its multiplicity,
  // then the last once. OCCT's pole 1 is cifs's point a − 1 of the period (a: the multiplicity of the
  // first knot): point i is pole (i − a + 1 mod n) + 1.
  nurbs::Knots breakpoints;
  for (int k = 1; k < c.NbKnots(); ++k) breakpoints.insert(breakpoints.end(), c.Multiplicity(k), c.Knot(k));
  breakpoints.push_back(c.Knot(c.NbKnots()));
  const int shift = c.Multiplicity(1) - 1;
  for (int i = 0; i < n; ++i) {
    const int pole = ((i - shift) % n + n) % n + 1;
    const gp_Pnt& p = c.Pole(pole);
    P.row(i) << p.X(), p.Y(), p.Z();
    if (c.IsRational()) w(i) = c.Weight(pole);
  }
  return nurbs::make_closed_curve(c.Degree(), std::move(breakpoints), P, w);
}

nurbs::Surface from_occt(Geom_BSplineSurface s) {  // by value: made non-periodic in place
  if (s.IsUPeriodic()) s.SetUNotPeriodic();        // cifs has no closed surfaces: the clamped equivalent
  if (s.IsVPeriodic()) s.SetVNotPeriodic();
  const int nu = s.NbUPoles(), nv = s.NbVPoles();
  Points P(Eigen::Index{nu} * nv, 3);
  Eigen::VectorXd w;
  if (s.IsURational() || s.IsVRational()) w.resize(P.rows());
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const Eigen::Index row = Eigen::Index{i} * nv + j;
      const gp_Pnt& p = s.Pole(i + 1, j + 1);
      P.row(row) << p.X(), p.Y(), p.Z();
      if (w.size() != 0) w(row) = s.Weight(i + 1, j + 1);
    }
  return nurbs::make_surface({s.UDegree(), s.VDegree()},
                             {flat_knots(s.UKnotSequence()), flat_knots(s.VKnotSequence())}, {nu, nv}, P, w);
}

/// The name of an OCCT geometry type in messages: "Geom_CylindricalSurface" → "a cylindrical surface".
std::string geometry_name(const Handle(Standard_Transient) & g) {
  static const std::map<std::string, std::string, std::less<>> names = {
      {"Geom_CylindricalSurface", "a cylindrical surface"},
      {"Geom_ConicalSurface", "a conical surface"},
      {"Geom_SphericalSurface", "a spherical surface"},
      {"Geom_ToroidalSurface", "a toroidal surface"},
      {"Geom_SurfaceOfRevolution", "a surface of revolution"},
      {"Geom_SurfaceOfLinearExtrusion", "a surface of linear extrusion"},
      {"Geom_OffsetSurface", "an offset surface"},
      {"Geom_Circle", "a circle"},
      {"Geom_Ellipse", "an ellipse"},
      {"Geom_Hyperbola", "a hyperbola"},
      {"Geom_Parabola", "a parabola"},
      {"Geom_OffsetCurve", "an offset curve"},
  };
  const std::string type = g->DynamicType()->Name();
  const auto found = names.find(type);
  return found != names.end() ? found->second : "a " + type;
}

/// A degree-1 B-spline through two points on [t0, t1]: a line over an edge's range, exactly.
nurbs::Curve segment(const gp_Pnt& a, const gp_Pnt& b, double t0, double t1) {
  Points P(2, 3);
  P << a.X(), a.Y(), a.Z(), b.X(), b.Y(), b.Z();
  return nurbs::make_curve(1, {t0, t0, t1, t1}, P);
}

/// What the readers skip, counted for the message of a file that holds nothing cifs reads.
struct Skipped {
  std::map<std::string, int> kinds;
  std::string summary() const {
    std::string out;
    for (const auto& [kind, count] : kinds)
      out += (out.empty() ? "" : ", ") + std::to_string(count) + " × " + kind.substr(kind.find(' ') + 1);
    return out;
  }
};

/// The curve of an edge bounding no face, over the edge's range; nothing (and a warning) for geometry
/// whose B-spline form would change its parametrization.
std::optional<nurbs::Curve> edge_curve(const TopoDS_Edge& edge, std::size_t number, std::string_view where,
                                       const io::ShapeReadOptions& options, Skipped& skipped) {
  double first = 0, last = 0;
  Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);  // with the edge's location applied
  if (curve.IsNull()) return std::nullopt;                         // no 3-D curve: nothing to read
  while (auto trimmed = Handle(Geom_TrimmedCurve)::DownCast(curve)) curve = trimmed->BasisCurve();
  Handle(Geom_BSplineCurve) spline;
  if (auto line = Handle(Geom_Line)::DownCast(curve))
    return segment(line->Value(first), line->Value(last), first, last);
  if (auto bezier = Handle(Geom_BezierCurve)::DownCast(curve))
    spline = GeomConvert::CurveToBSplineCurve(bezier);
  if (auto bspline = Handle(Geom_BSplineCurve)::DownCast(curve))
    spline = Handle(Geom_BSplineCurve)::DownCast(bspline->Copy());
  if (spline.IsNull()) {
    const std::string kind = geometry_name(curve);
    ++skipped.kinds[kind];
    io::warn(options, options.index.value_or(0),
             std::string(where) + ": free edge " + std::to_string(number) + " is " + kind +
                 ", not a B-spline: skipped (its B-spline form would change the parametrization)");
    return std::nullopt;
  }
  // A periodic curve over its period: the closed curve. Over another range (at most a period, which
  // may straddle the seam): OCCT cuts it there, exactly.
  if (spline->IsPeriodic()) {
    const double tol = Precision::PConfusion();
    if (std::abs(first - spline->FirstParameter()) > tol || std::abs(last - spline->LastParameter()) > tol)
      spline->Segment(first, last);
    return from_occt(*spline);
  }
  if (first > spline->FirstParameter() || last < spline->LastParameter())
    spline->Segment(std::max(first, spline->FirstParameter()), std::min(last, spline->LastParameter()));
  return from_occt(*spline);
}

/// Whether the face is bounded by its parameter rectangle alone: one wire whose edges run along the
/// rectangle's sides (straight iso-parametric lines in the face's parameter plane).
bool untrimmed(const TopoDS_Face& face, double u0, double u1, double v0, double v1) {
  int wires = 0;
  for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next()) ++wires;
  if (wires != 1) return false;
  const double tol =
      Precision::PConfusion() * std::max({1.0, std::abs(u0), std::abs(u1), std::abs(v0), std::abs(v1)});
  const auto on_side = [&](const gp_Pnt2d& a, const gp_Pnt2d& b) {
    const bool along_u =
        std::abs(a.Y() - b.Y()) <= tol && (std::abs(a.Y() - v0) <= tol || std::abs(a.Y() - v1) <= tol);
    const bool along_v =
        std::abs(a.X() - b.X()) <= tol && (std::abs(a.X() - u0) <= tol || std::abs(a.X() - u1) <= tol);
    return along_u || along_v;
  };
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    double first = 0, last = 0;
    Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (pcurve.IsNull()) return false;
    while (auto trimmed = Handle(Geom2d_TrimmedCurve)::DownCast(pcurve)) pcurve = trimmed->BasisCurve();
    const gp_Pnt2d a = pcurve->Value(first), b = pcurve->Value(last),
                   mid = pcurve->Value(0.5 * (first + last));
    const Handle(Geom2d_BSplineCurve) spline = Handle(Geom2d_BSplineCurve)::DownCast(pcurve);
    const bool straight = !Handle(Geom2d_Line)::DownCast(pcurve).IsNull() ||
                          (!spline.IsNull() && spline->Degree() == 1 && spline->NbPoles() == 2);
    if (!straight || !on_side(a, b) || !on_side(a, mid)) return false;
  }
  return true;
}

/// The surface of a face over its parameter rectangle; nothing (and a warning) for surfaces cifs does
/// not read exactly. A trimmed face is refused unless options.ignore_trim.
std::optional<nurbs::Surface> face_surface(const TopoDS_Face& face, std::size_t number,
                                           std::string_view where, const io::ShapeReadOptions& options,
                                           Skipped& skipped, std::size_t shape_index) {
  Handle(Geom_Surface) surface = BRep_Tool::Surface(face);  // with the face's location applied
  while (auto trimmed = Handle(Geom_RectangularTrimmedSurface)::DownCast(surface))
    surface = trimmed->BasisSurface();
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  Handle(Geom_BSplineSurface) spline;
  if (auto plane = Handle(Geom_Plane)::DownCast(surface)) {
    // Planes are affine in (u, v): the bilinear patch of the rectangle's corners is the plane itself.
    TColgp_Array2OfPnt corners(1, 2, 1, 2);
    corners(1, 1) = plane->Value(u0, v0);
    corners(1, 2) = plane->Value(u0, v1);
    corners(2, 1) = plane->Value(u1, v0);
    corners(2, 2) = plane->Value(u1, v1);
    TColStd_Array1OfReal uk(1, 2), vk(1, 2);
    TColStd_Array1OfInteger mult(1, 2);
    uk(1) = u0, uk(2) = u1, vk(1) = v0, vk(2) = v1, mult(1) = 2, mult(2) = 2;
    spline = new Geom_BSplineSurface(corners, uk, vk, mult, mult, 1, 1);
  }
  if (auto bezier = Handle(Geom_BezierSurface)::DownCast(surface))
    spline = GeomConvert::SurfaceToBSplineSurface(bezier);
  if (auto bspline = Handle(Geom_BSplineSurface)::DownCast(surface))
    spline = Handle(Geom_BSplineSurface)::DownCast(bspline->Copy());
  if (spline.IsNull()) {
    const std::string kind = geometry_name(surface);
    ++skipped.kinds[kind];
    io::warn(options, options.index.value_or(0),
             std::string(where) + ": face " + std::to_string(number) + " is " + kind +
                 ", not a B-spline: skipped (its B-spline form would change the parametrization)");
    return std::nullopt;
  }
  const std::string name = std::string(where) + ": face " + std::to_string(number) + " (shape " +
                           std::to_string(shape_index) + ")";
  if (!untrimmed(face, u0, u1, v0, v1)) {
    if (!options.ignore_trim)
      throw InvalidInput(name +
                         " is trimmed: trimmed surfaces are not supported; --ignore-trim (ignore_trim) reads "
                         "the whole untrimmed surface");
    io::warn(options, shape_index,
             name + " is trimmed: its trimming loops are ignored and the whole untrimmed surface is read");
    return from_occt(*spline);
  }
  // Bounded by a rectangle inside the surface's domain: that part, cut exactly by knot insertion.
  double su0 = 0, su1 = 0, sv0 = 0, sv1 = 0;
  spline->Bounds(su0, su1, sv0, sv1);
  const double tol = Precision::PConfusion();
  if (u0 > su0 + tol || u1 < su1 - tol || v0 > sv0 + tol || v1 < sv1 - tol)
    spline->Segment(std::max(u0, su0), std::min(u1, su1), std::max(v0, sv0), std::min(v1, sv1));
  return from_occt(*spline);
}

/// Runs OCCT code, turning its exceptions into InvalidInput naming `where`.
template <class F>
auto guarded(std::string_view where, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Standard_Failure& e) {
    throw InvalidInput(
        std::string(where) + ": OpenCASCADE refuses it: " + e.DynamicType()->Name() +
        (e.GetMessageString() && *e.GetMessageString() ? std::string(": ") + e.GetMessageString() : ""));
  }
}

/// Shape `index` as OCCT's B-spline; what OCCT refuses (an interior knot of multiplicity degree + 1) is
/// an InvalidInput naming the shape.
template <class S>
auto converted(const S& shape, std::size_t index) {
  const std::string name = "shape " + std::to_string(index);
  check_dimension(nurbs::dimension(shape), name);
  return guarded(name, [&] { return to_occt(shape); });
}

void silence_messages() {
  static const bool once = [] {
    Message::DefaultMessenger()->ChangePrinters().Clear();
    return true;
  }();
  (void)once;
}

/// The length units of a STEP model's geometric contexts, in millimetres per unit (25.4 for inches).
std::vector<double> step_length_units(const Interface_InterfaceModel& model) {
  std::vector<double> units;
  for (int i = 1; i <= model.NbEntities(); ++i) {
    const auto context =
        Handle(StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx)::DownCast(model.Value(i));
    if (context.IsNull()) continue;
    STEPConstruct_UnitContext unit;
    if (unit.ComputeFactors(context->GlobalUnitAssignedContext()) == 0 && unit.LengthDone() &&
        std::find(units.begin(), units.end(), unit.LengthFactor()) == units.end())
      units.push_back(unit.LengthFactor());
  }
  return units;
}

// OCCT converts lengths to millimetres by default. cifs keeps the numbers the file holds (in its own
// length unit: no rescaling, so no rounding), by making the file's unit OCCT's "system" unit.
TopoDS_Shape read_brep(std::string_view bytes, const std::filesystem::path& path, io::CadFormat format,
                       const io::ShapeReadOptions& options) {
  const std::string where = path.string();
  if (format == io::CadFormat::step) {
    STEPControl_Reader reader;
    std::istringstream stream{std::string(bytes)};
    if (reader.ReadStream(where.c_str(), stream) != IFSelect_RetDone)
      throw InvalidInput(where + ": not a STEP file OpenCASCADE can read");
    const std::vector<double> units = step_length_units(*reader.Model());
    if (units.size() == 1) {
      reader.SetSystemLengthUnit(units.front());
    } else if (units.size() > 1) {
      std::ostringstream list;
      for (std::size_t i = 0; i < units.size(); ++i) list << (i ? ", " : "") << units[i] << " mm";
      io::warn(options, options.index.value_or(0),
               where + ": the file's parts use different length units (" + list.str() +
                   "): every coordinate is converted to millimetres");
    }
    reader.TransferRoots();
    return reader.OneShape();
  }
  IGESControl_Controller::Init();
  // Split nothing: OCCT's default cuts C0 B-splines into C1 pieces.
  Interface_Static::SetIVal("read.iges.bspline.continuity", 0);
  IGESControl_Reader reader;
  if (reader.ReadFile(where.c_str()) != IFSelect_RetDone || reader.Model()->NbEntities() == 0)
    throw InvalidInput(where + ": not an IGES file OpenCASCADE can read");
  const Handle(IGESData_IGESModel) model = Handle(IGESData_IGESModel)::DownCast(reader.Model());
  IGESData_GlobalSection global = model->GlobalSection();
  global.SetCascadeUnit(global.UnitValue());  // UnitValue: the file's unit in millimetres
  model->SetGlobalSection(global);
  reader.TransferRoots();
  return reader.OneShape();
}

}  // namespace

std::vector<io::Shape> read_cad(std::string_view bytes, const std::filesystem::path& path,
                                io::CadFormat format, const io::ShapeReadOptions& options) {
  silence_messages();
  const std::string where = path.string();
  return guarded(where, [&] {
    const TopoDS_Shape brep = read_brep(bytes, path, format, options);
    std::vector<io::Shape> shapes;
    Skipped skipped;
    std::size_t number = 0;
    for (TopExp_Explorer f(brep, TopAbs_FACE); f.More(); f.Next(), ++number)
      if (auto s = face_surface(TopoDS::Face(f.Current()), number, where, options, skipped, shapes.size()))
        shapes.emplace_back(std::move(*s));
    number = 0;
    for (TopExp_Explorer e(brep, TopAbs_EDGE, TopAbs_FACE); e.More(); e.Next(), ++number) {
      const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
      if (BRep_Tool::Degenerated(edge)) continue;
      if (auto c = edge_curve(edge, number, where, options, skipped)) shapes.emplace_back(std::move(*c));
    }
    if (shapes.empty())
      throw InvalidInput(where + ": holds no B-spline curve or surface" +
                         (skipped.kinds.empty() ? std::string() : " (skipped: " + skipped.summary() + ")"));
    return shapes;
  });
}

std::string write_cad(std::span<const io::Shape> shapes, io::CadFormat format) {
  silence_messages();
  const std::string what = format == io::CadFormat::step ? "STEP" : "IGES";
  return guarded(what + " writer", [&] {
    std::ostringstream out;
    if (format == io::CadFormat::step) {
      // Faces and edges in one compound, written as is: surfaces as untrimmed faces, curves as a curve set.
      BRep_Builder builder;
      TopoDS_Compound compound;
      builder.MakeCompound(compound);
      for (std::size_t i = 0; i < shapes.size(); ++i) {
        if (const auto* c = std::get_if<nurbs::Curve>(&shapes[i]))
          builder.Add(compound, BRepBuilderAPI_MakeEdge(converted(*c, i)).Edge());
        else
          builder.Add(compound, BRepBuilderAPI_MakeFace(converted(std::get<nurbs::Surface>(shapes[i]), i),
                                                        Precision::Confusion())
                                    .Face());
      }
      STEPControl_Writer writer;
      if (writer.Transfer(compound, STEPControl_AsIs) != IFSelect_RetDone)
        throw InvalidInput("STEP: OpenCASCADE could not translate the shapes");
      // STEPControl_Writer::Write, into a stream and with every digit of the reals.
      StepData_StepWriter step(writer.Model());
      step.FloatWriter().SetFormat("%.16E");
      step.SendModel(Handle(StepData_Protocol)::DownCast(writer.WS()->Protocol()));
      step.Print(out);
    } else {
      IGESControl_Controller::Init();
      IGESControl_Writer writer("MM", 0);
      for (std::size_t i = 0; i < shapes.size(); ++i) {
        if (const auto* c = std::get_if<nurbs::Curve>(&shapes[i]))
          writer.AddGeom(converted(*c, i));
        else
          writer.AddGeom(converted(std::get<nurbs::Surface>(shapes[i]), i));
      }
      writer.ComputeModel();
      // IGESControl_Writer::Write, with every digit of the reals.
      IGESData_IGESWriter iges(writer.Model());
      iges.FloatWriter().SetFormat("%.16E");
      iges.SendModel(IGESSelect_WorkLibrary::DefineProtocol());
      iges.Print(out);
    }
    return out.str();
  });
}

io::CadCodec cad_codec() {
  silence_messages();
  return {.read = read_cad, .write = write_cad};
}

void enable_cad_formats() {
  io::set_cad_codec(cad_codec());
}

}  // namespace cifs::occt

/// The plugin's entry (libcifs_occt_plugin.so, apps/occt_plugin.cpp): the codec, through a C name.
extern "C" __attribute__((visibility("default"))) void cifs_occt_codec(cifs::io::CadCodec* codec) {
  *codec = cifs::occt::cad_codec();
}
