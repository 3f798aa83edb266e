// SPDX-License-Identifier: MIT
// cifs::occt against OpenCASCADE itself: what cifs writes, OCCT's own readers (STEPControl_Reader,
// IGESControl_Reader) read back and OCCT's Geom evaluates (D0) at the points cifs evaluates; what OCCT
// builds and writes with its own writers, cifs reads and evaluates at the points OCCT's Geom gives.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Plane.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Precision.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
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
#include <catch2/catch.hpp>
#include <fstream>
#include <gp.hxx>
#include <gp_Circ.hxx>
#include <gp_Pln.hxx>
#include <random>
#include <tuple>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/occt/occt.hpp"
#include "support/scratch.hpp"
#ifdef CIFS_CLI_PATH
#include "apps/cli_runner.hpp"
#endif

using namespace cifs;

namespace {

const std::filesystem::path& occt_scratch() {
  static const cifs_test::ScratchDir folder("occt");
  return folder.path();
}

void occt_quiet() {
  Message::DefaultMessenger()->ChangePrinters().Clear();  // OCCT's transfer statistics on stdout
}

/// A knot vector of `spans` spans with random interior multiplicities 1 … degree, clamped or not.
nurbs::Knots occt_random_knots(std::mt19937& rng, int degree, int spans, bool clamped) {
  std::uniform_int_distribution<int> mult(1, std::max(1, degree));
  std::uniform_real_distribution<double> step(0.25, 2);
  nurbs::Knots knots;
  double t = std::uniform_real_distribution<double>(-3, 3)(rng);
  for (int i = 0; i <= degree; ++i) {
    knots.push_back(t);
    if (!clamped) t += step(rng);
  }
  for (int s = 1; s < spans; ++s) {
    t += step(rng);
    knots.insert(knots.end(), static_cast<std::size_t>(mult(rng)), t);
  }
  t += step(rng);
  for (int i = 0; i <= degree; ++i) {
    knots.push_back(t);
    if (!clamped) t += step(rng);
  }
  return knots;
}

Points occt_random_points(std::mt19937& rng, Eigen::Index rows, int dim) {
  std::uniform_real_distribution<double> coord(-10, 10);
  Points P(rows, dim);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (int j = 0; j < dim; ++j) P(i, j) = coord(rng);
  return P;
}

Eigen::VectorXd occt_random_weights(std::mt19937& rng, Eigen::Index n) {
  std::uniform_real_distribution<double> weight(0.2, 5);
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) w(i) = weight(rng);
  return w;
}

/// Random curves of degrees 1 … 5, rational or not, clamped, unclamped and closed, 2-D and 3-D.
std::vector<nurbs::Curve> occt_sample_curves(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<nurbs::Curve> out;
  for (int degree = 1; degree <= 5; ++degree) {
    const bool rational = degree % 2 == 1;
    const nurbs::Knots knots = occt_random_knots(rng, degree, 3, degree != 4);
    const auto n = static_cast<Eigen::Index>(knots.size()) - degree - 1;
    out.push_back(nurbs::make_curve(degree, knots, occt_random_points(rng, n, degree == 2 ? 2 : 3),
                                    rational ? occt_random_weights(rng, n) : Eigen::VectorXd()));
  }
  // Closed, rational, with a double breakpoint.
  const nurbs::Knots breakpoints{0, 0.5, 1.25, 1.25, 2, 3.5};
  out.push_back(
      nurbs::make_closed_curve(3, breakpoints, occt_random_points(rng, 5, 3), occt_random_weights(rng, 5)));
  return out;
}

std::vector<nurbs::Surface> occt_sample_surfaces(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<nurbs::Surface> out;
  for (const auto& [du, dv] : {std::pair{1, 2}, std::pair{3, 3}, std::pair{5, 2}}) {
    const nurbs::Knots ku = occt_random_knots(rng, du, 2, true), kv = occt_random_knots(rng, dv, 3, du != 3);
    const Eigen::Index nu = static_cast<Eigen::Index>(ku.size()) - du - 1,
                       nv = static_cast<Eigen::Index>(kv.size()) - dv - 1;
    out.push_back(nurbs::make_surface({du, dv}, {ku, kv}, {nu, nv}, occt_random_points(rng, nu * nv, 3),
                                      du == 2 ? Eigen::VectorXd() : occt_random_weights(rng, nu * nv)));
  }
  return out;
}

double occt_scale(const Points& P) {
  return std::max(1.0, P.cwiseAbs().maxCoeff());
}

/// |a − b| ≤ 1e-12 · scale, coordinate by coordinate (cifs points may be 2-D: z must then be 0).
void occt_require_same(const gp_Pnt& p, const Point& q, double scale) {
  const double xyz[3] = {p.X(), p.Y(), p.Z()};
  for (int k = 0; k < 3; ++k) {
    const double expected = k < q.size() ? q[k] : 0.0;
    INFO("coordinate " << k << ": OCCT " << xyz[k] << ", cifs " << expected);
    REQUIRE(std::abs(xyz[k] - expected) <= 1e-12 * scale);
  }
}

std::vector<double> occt_samples(nurbs::Domain d, int count) {
  return nurbs::uniform_parameters(d, count);
}

/// The faces and the edges that bound no face of an OCCT shape, in OCCT's order.
struct OcctParts {
  std::vector<TopoDS_Face> faces;
  std::vector<TopoDS_Edge> edges;
};
OcctParts occt_parts(const TopoDS_Shape& shape) {
  OcctParts out;
  for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next())
    out.faces.push_back(TopoDS::Face(f.Current()));
  for (TopExp_Explorer e(shape, TopAbs_EDGE, TopAbs_FACE); e.More(); e.Next())
    out.edges.push_back(TopoDS::Edge(e.Current()));
  return out;
}

TopoDS_Shape occt_read_file(const std::filesystem::path& path) {
  occt_quiet();
  if (cifs::io::cad_format(path) == cifs::io::CadFormat::step) {
    STEPControl_Reader reader;
    REQUIRE(reader.ReadFile(path.c_str()) == IFSelect_RetDone);
    reader.TransferRoots();
    return reader.OneShape();
  }
  IGESControl_Controller::Init();
  Interface_Static::SetIVal("read.iges.bspline.continuity", 0);  // whole curves, not C1 pieces
  IGESControl_Reader reader;
  REQUIRE(reader.ReadFile(path.c_str()) == IFSelect_RetDone);
  reader.TransferRoots();
  return reader.OneShape();
}

void occt_write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// cifs writes the samples; OCCT reads the file and evaluates every curve and surface where cifs does.
void occt_check_written(io::CadFormat format, const std::string& name) {
  const std::vector<nurbs::Curve> curves = occt_sample_curves(7);
  const std::vector<nurbs::Surface> surfaces = occt_sample_surfaces(8);
  std::vector<io::Shape> shapes(surfaces.begin(), surfaces.end());
  shapes.insert(shapes.end(), curves.begin(), curves.end());
  const std::filesystem::path path = occt_scratch() / name;
  occt_write_file(path, occt::write_cad(shapes, format));

  const OcctParts parts = occt_parts(occt_read_file(path));
  REQUIRE(parts.faces.size() == surfaces.size());
  REQUIRE(parts.edges.size() == curves.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    INFO("surface " << i);
    const nurbs::Surface& s = surfaces[i];
    const Handle(Geom_Surface) g = BRep_Tool::Surface(parts.faces[i]);
    const double scale = occt_scale(nurbs::cartesian_points(s));
    for (double u : occt_samples(nurbs::domain(s, nurbs::Direction::u), 9))
      for (double v : occt_samples(nurbs::domain(s, nurbs::Direction::v), 9))
        occt_require_same(g->Value(u, v), nurbs::evaluate(s, u, v), scale);
  }
  for (std::size_t i = 0; i < curves.size(); ++i) {
    INFO("curve " << i << " (degree " << curves[i].degree << (curves[i].closed ? ", closed" : "") << ")");
    const nurbs::Curve& c = curves[i];
    double first = 0, last = 0;
    const Handle(Geom_Curve) g = BRep_Tool::Curve(parts.edges[i], first, last);
    const nurbs::Domain dom = nurbs::domain(c);
    CHECK(first == dom.start);
    CHECK(last == dom.end);
    const double scale = occt_scale(nurbs::cartesian_points(c));
    for (double u : occt_samples(dom, 41)) occt_require_same(g->Value(u), nurbs::evaluate(c, u), scale);
  }
}

/// A dyadic number (k/16): written exactly by OCCT's writers, whose reals keep 12 (STEP) or 9 (IGES) digits.
double occt_dyadic(std::mt19937& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo * 16, hi * 16)(rng) / 16.0;
}

Handle(Geom_BSplineSurface) occt_built_surface(std::mt19937& rng) {
  const int nu = 5, nv = 4;
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  TColStd_Array2OfReal weights(1, nu, 1, nv);
  for (int i = 1; i <= nu; ++i)
    for (int j = 1; j <= nv; ++j) {
      poles(i, j) =
          gp_Pnt(i + occt_dyadic(rng, -1, 1) / 4, j + occt_dyadic(rng, -1, 1) / 4, occt_dyadic(rng, -3, 3));
      weights(i, j) = occt_dyadic(rng, 1, 3) / 2;
    }
  TColStd_Array1OfReal uk(1, 3), vk(1, 3);
  TColStd_Array1OfInteger um(1, 3), vm(1, 3);
  uk(1) = 0, uk(2) = 1.5, uk(3) = 4, um(1) = 3, um(2) = 2, um(3) = 3;   // degree 2, a double knot
  vk(1) = -1, vk(2) = 0.5, vk(3) = 2, vm(1) = 3, vm(2) = 1, vm(3) = 3;  // degree 2
  return new Geom_BSplineSurface(poles, weights, uk, vk, um, vm, 2, 2);
}

/// Rational cubic, a double interior knot; `periodic`: closed over [0, 3] with a double seam knot.
Handle(Geom_BSplineCurve) occt_built_curve(std::mt19937& rng, bool periodic) {
  const int n = periodic ? 5 : 8;
  TColgp_Array1OfPnt poles(1, n);
  TColStd_Array1OfReal weights(1, n);
  for (int i = 1; i <= n; ++i) {
    poles(i) = gp_Pnt(occt_dyadic(rng, -5, 5), occt_dyadic(rng, -5, 5), occt_dyadic(rng, -5, 5));
    weights(i) = occt_dyadic(rng, 1, 3) / 2;
  }
  TColStd_Array1OfReal knots(1, 5);
  TColStd_Array1OfInteger mults(1, 5);
  const double k[5] = {0, 0.5, 1.5, 2, 3};
  const int clamped[5] = {4, 1, 2, 1, 4}, seam[5] = {2, 1, 1, 1, 2};
  for (int i = 0; i < 5; ++i) {
    knots(i + 1) = k[i];
    mults(i + 1) = periodic ? seam[i] : clamped[i];
  }
  return new Geom_BSplineCurve(poles, weights, knots, mults, 3, periodic);
}

}  // namespace

TEST_CASE("cifs writes STEP that OpenCASCADE reads back and evaluates equal", "[occt][step]") {
  occt_check_written(io::CadFormat::step, "written.step");
}

TEST_CASE("cifs writes IGES (126, 128) that OpenCASCADE reads back and evaluates equal", "[occt][iges]") {
  occt_check_written(io::CadFormat::iges, "written.igs");
}

TEST_CASE("cifs reads what OpenCASCADE writes: rational, repeated knots, periodic", "[occt][step][iges]") {
  occt_quiet();
  std::mt19937 rng(11);
  const Handle(Geom_BSplineSurface) surface = occt_built_surface(rng);
  const Handle(Geom_BSplineCurve) open = occt_built_curve(rng, false), periodic = occt_built_curve(rng, true);
  REQUIRE(periodic->IsPeriodic());
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  builder.Add(compound, BRepBuilderAPI_MakeFace(surface, Precision::Confusion()).Face());
  builder.Add(compound, BRepBuilderAPI_MakeEdge(open).Edge());
  builder.Add(compound, BRepBuilderAPI_MakeEdge(periodic).Edge());
  builder.Add(compound, BRepBuilderAPI_MakeEdge(periodic, 0.25, 2).Edge());  // part of the period
  builder.Add(compound, BRepBuilderAPI_MakeEdge(periodic, 1, 4).Edge());     // a period across the seam

  const std::filesystem::path step = occt_scratch() / "occt.step", iges = occt_scratch() / "occt.igs";
  STEPControl_Writer step_writer;
  REQUIRE(step_writer.Transfer(compound, STEPControl_AsIs) == IFSelect_RetDone);
  REQUIRE(step_writer.Write(step.c_str()) == IFSelect_RetDone);
  IGESControl_Controller::Init();
  IGESControl_Writer iges_writer("MM", 0);
  iges_writer.AddGeom(surface);
  iges_writer.AddGeom(open);
  iges_writer.AddGeom(periodic);
  iges_writer.ComputeModel();
  REQUIRE(iges_writer.Write(iges.c_str()));

  for (const std::filesystem::path& path : {step, iges}) {
    INFO(path.filename());
    const std::vector<io::Shape> shapes = occt::read_cad(read_file(path), path, *io::cad_format(path),
                                                         {.ignore_trim = false, .index = {}, .warn = {}});
    // STEP keeps the parts as trimmed curves of the periodic one; IGES (not given them) holds three.
    REQUIRE(shapes.size() == (path == step ? 5U : 3U));
    const auto& s = std::get<nurbs::Surface>(shapes[0]);
    CHECK(s.rational);
    for (double u : occt_samples({0, 4}, 9))
      for (double v : occt_samples({-1, 2}, 9))
        occt_require_same(surface->Value(u, v), nurbs::evaluate(s, u, v), 10);
    const auto& c = std::get<nurbs::Curve>(shapes[1]);
    CHECK(c.rational);
    for (double u : occt_samples({0, 3}, 31)) occt_require_same(open->Value(u), nurbs::evaluate(c, u), 10);
    // OCCT's STEP reader gives the periodic curve back periodic: a closed cifs curve (IGES: unclamped).
    const auto& closed = std::get<nurbs::Curve>(shapes[2]);
    if (path == step) {
      CHECK(closed.closed);
      CHECK(nurbs::distinct_count(closed) == 5);
    }
    for (double u : occt_samples({0, 3}, 31))
      occt_require_same(periodic->Value(u), nurbs::evaluate(closed, u), 10);
    // Parts: [0.25, 2] of the period, and [1, 4] across the seam, same parameters.
    if (path != step) continue;
    for (const auto& [index, range] :
         {std::pair{3, nurbs::Domain{0.25, 2}}, std::pair{4, nurbs::Domain{1, 4}}}) {
      const auto& part = std::get<nurbs::Curve>(shapes[static_cast<std::size_t>(index)]);
      CHECK(nurbs::domain(part).start == Approx(range.start));
      CHECK(nurbs::domain(part).end == Approx(range.end));
      for (double u : occt_samples(range, 31))
        occt_require_same(
            periodic->Value(u),
            nurbs::evaluate(part, std::clamp(u, nurbs::domain(part).start, nurbs::domain(part).end)), 10);
    }
  }
}

TEST_CASE("STEP and IGES: coordinates are the numbers the file holds, in its own length unit",
          "[occt][step][iges]") {
  // OCCT's writers convert from millimetres to the unit asked (numbers / 25.4 for inches); OCCT's readers
  // convert back to millimetres by default. cifs keeps the file's numbers: c·25.4 mm written in inches
  // reads c (to an ulp of the writer's division), not c·25.4.
  occt_quiet();
  std::mt19937 rng(5);
  TColgp_Array1OfPnt poles(1, 4);
  std::vector<gp_Pnt> in_units;
  for (int i = 1; i <= 4; ++i) {
    in_units.emplace_back(occt_dyadic(rng, -5, 5), occt_dyadic(rng, -5, 5), occt_dyadic(rng, -5, 5));
    poles(i) = in_units.back();
  }
  TColStd_Array1OfReal knots(1, 2);
  TColStd_Array1OfInteger mults(1, 2);
  knots(1) = 0, knots(2) = 1, mults(1) = 4, mults(2) = 4;
  for (const auto& [unit, iges_unit, mm] : {std::tuple{"INCH", "IN", 25.4}, std::tuple{"M", "M", 1000.0},
                                            std::tuple{"FT", "FT", 304.8}, std::tuple{"MM", "MM", 1.0}}) {
    INFO(unit);
    TColgp_Array1OfPnt scaled(1, 4);
    for (int i = 1; i <= 4; ++i)
      scaled(i) = in_units[static_cast<std::size_t>(i - 1)].Scaled(gp::Origin(), mm);
    const Handle(Geom_BSplineCurve) curve = new Geom_BSplineCurve(scaled, knots, mults, 3);
    const std::filesystem::path step = occt_scratch() / (std::string("unit_") + unit + ".step"),
                                iges = occt_scratch() / (std::string("unit_") + unit + ".igs");
    STEPControl_Controller::Init();  // registers write.step.unit: before it, SetCVal does nothing
    REQUIRE(Interface_Static::SetCVal("write.step.unit", unit));
    STEPControl_Writer step_writer;
    REQUIRE(step_writer.Transfer(BRepBuilderAPI_MakeEdge(curve).Edge(), STEPControl_AsIs) ==
            IFSelect_RetDone);
    REQUIRE(step_writer.Write(step.c_str()) == IFSelect_RetDone);
    Interface_Static::SetCVal("write.step.unit", "MM");
    IGESControl_Controller::Init();
    IGESControl_Writer iges_writer(iges_unit, 0);
    iges_writer.AddGeom(curve);
    iges_writer.ComputeModel();
    REQUIRE(iges_writer.Write(iges.c_str()));
    if (mm == 25.4) REQUIRE(read_file(step).find("'INCH'") != std::string::npos);  // the unit is declared
    for (const std::filesystem::path& path : {step, iges}) {
      INFO(path.filename());
      const std::vector<io::Shape> shapes = occt::read_cad(read_file(path), path, *io::cad_format(path),
                                                           {.ignore_trim = false, .index = {}, .warn = {}});
      REQUIRE(shapes.size() == 1);
      const Points P = nurbs::cartesian_points(std::get<nurbs::Curve>(shapes[0]));
      REQUIRE(P.rows() == 4);
      for (int i = 0; i < 4; ++i)
        occt_require_same(in_units[static_cast<std::size_t>(i)], P.row(i).transpose(), 5);
    }
  }
}

TEST_CASE(
    "STEP: a trimmed face is refused or read whole with --ignore-trim, planes read exactly, cylinders "
    "reported",
    "[occt][step]") {
  occt_quiet();
  const gp_Pln plane(gp_Ax3(gp_Pnt(1, 2, 3), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)));
  const TopoDS_Wire circle =
      BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(gp_Circ(plane.Position().Ax2(), 2)));
  const TopoDS_Face disc = BRepBuilderAPI_MakeFace(plane, circle);
  const TopoDS_Face rectangle = BRepBuilderAPI_MakeFace(plane, -1, 3, 0.5, 2);
  const TopoDS_Face cylinder =
      BRepBuilderAPI_MakeFace(new Geom_CylindricalSurface(gp::XOY(), 2), 0, 3, 0, 1, Precision::Confusion());
  const auto write = [](const TopoDS_Shape& shape, const std::string& name) {
    STEPControl_Writer writer;
    REQUIRE(writer.Transfer(shape, STEPControl_AsIs) == IFSelect_RetDone);
    const std::filesystem::path path = occt_scratch() / name;
    REQUIRE(writer.Write(path.c_str()) == IFSelect_RetDone);
    return path;
  };
  std::vector<std::string> warnings;
  const io::ShapeReadOptions collect{
      .ignore_trim = false, .index = {}, .warn = [&](const std::string& w) { warnings.push_back(w); }};

  // The disc: trimmed by a circle.
  const std::filesystem::path disc_path = write(disc, "disc.step");
  REQUIRE_THROWS_WITH(occt::read_cad(read_file(disc_path), disc_path, io::CadFormat::step, collect),
                      Catch::Contains("face 0 (shape 0) is trimmed") && Catch::Contains("--ignore-trim"));
  io::ShapeReadOptions whole = collect;
  whole.ignore_trim = true;
  const std::vector<io::Shape> read =
      occt::read_cad(read_file(disc_path), disc_path, io::CadFormat::step, whole);
  REQUIRE(read.size() == 1);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("trimming loops are ignored"));
#ifdef CIFS_CLI_PATH
  // The CLI: one line and exit 2, naming the option; with it, the warning and exit 0.
  const cifs_test::Run refused = cifs_test::cifs_cli("info " + disc_path.string());
  CHECK(refused.status == 2);
  CHECK(std::count(refused.err.begin(), refused.err.end(), '\n') == 1);
  CHECK_THAT(refused.err, Catch::Contains("is trimmed") && Catch::Contains("--ignore-trim"));
  const cifs_test::Run ignored = cifs_test::cifs_cli("info " + disc_path.string() + " --ignore-trim");
  CHECK(ignored.status == 0);
  CHECK_THAT(ignored.err,
             Catch::Contains("cifs: warning: ") && Catch::Contains("trimming loops are ignored"));
#endif
  const auto& square = std::get<nurbs::Surface>(read[0]);  // the plane over the circle's bounding square
  CHECK(nurbs::domain(square, nurbs::Direction::u).start == Approx(-2));
  CHECK(nurbs::domain(square, nurbs::Direction::u).end == Approx(2));

  // The rectangle: the plane itself as a bilinear patch, same parameters.
  const std::filesystem::path rect_path = write(rectangle, "rectangle.step");
  const auto flat =
      std::get<nurbs::Surface>(occt::read_cad(read_file(rect_path), rect_path, io::CadFormat::step)[0]);
  const Handle(Geom_Plane) g = new Geom_Plane(plane);
  for (double u : occt_samples({-1, 3}, 5))
    for (double v : occt_samples({0.5, 2}, 5))
      occt_require_same(g->Value(u, v), nurbs::evaluate(flat, u, v), 4);

  // A cylinder beside the rectangle: reported and skipped; alone: nothing to read, said so.
  warnings.clear();
  BRep_Builder builder;
  TopoDS_Compound both;
  builder.MakeCompound(both);
  builder.Add(both, cylinder);
  builder.Add(both, rectangle);
  const std::filesystem::path both_path = write(both, "both.step");
  CHECK(occt::read_cad(read_file(both_path), both_path, io::CadFormat::step, collect).size() == 1);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("face 0 is a cylindrical surface, not a B-spline: skipped"));
  const std::filesystem::path cyl_path = write(cylinder, "cylinder.step");
  REQUIRE_THROWS_WITH(
      occt::read_cad(read_file(cyl_path), cyl_path, io::CadFormat::step, collect),
      Catch::Contains("holds no B-spline curve or surface (skipped: 1 × cylindrical surface)"));
}

TEST_CASE("STEP and IGES: broken files and unwritable shapes are refused", "[occt][step][iges]") {
  const std::vector<io::Shape> shapes{occt_sample_surfaces(3)[1]};
  const std::string step = occt::write_cad(shapes, io::CadFormat::step);
  const std::string iges = occt::write_cad(shapes, io::CadFormat::iges);
  for (const auto& [name, text] : {std::pair{"noise.step", std::string("ISO-10303-21;\nnot step at all\n")},
                                   std::pair{"cut.step", step.substr(0, step.size() / 2)},
                                   std::pair{"noise.igs", std::string("hello\n")},
                                   std::pair{"cut.igs", iges.substr(0, iges.size() / 2)}}) {
    INFO(name);
    const std::filesystem::path path = occt_scratch() / name;
    occt_write_file(path, text);
    REQUIRE_THROWS_AS(occt::read_cad(text, path, *io::cad_format(path)), InvalidInput);
  }
  Points P4(2, 4);
  P4 << 0, 0, 0, 0, 1, 1, 1, 1;
  const std::vector<io::Shape> four{nurbs::make_curve(1, {0, 0, 1, 1}, P4)};
  REQUIRE_THROWS_WITH(occt::write_cad(four, io::CadFormat::step), Catch::Contains("4-D"));
}

TEST_CASE("io reads and writes .step and .igs (any case) once the component is plugged in", "[occt][io]") {
  occt::enable_cad_formats();
  const nurbs::Curve c = occt_sample_curves(5)[2];  // degree 3, rational
  for (const char* name : {"io.step", "io.stp", "io.iges", "io.igs", "upper.STEP", "upper.Igs"}) {
    INFO(name);
    const std::filesystem::path path = occt_scratch() / name;
    io::write(path, io::Shape(c));
    const auto back = std::get<nurbs::Curve>(io::read_shape(path));
    const double scale = occt_scale(nurbs::cartesian_points(c));
    for (double u : occt_samples(nurbs::domain(c), 17)) {
      const Point p = nurbs::evaluate(back, u), q = nurbs::evaluate(c, u);
      REQUIRE((p - q).cwiseAbs().maxCoeff() <= 1e-12 * scale);
    }
  }
}
