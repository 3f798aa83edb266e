// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.subdivision on polygon meshes: Catmull–Clark, Loop, Doo–Sabin,
// modified Butterfly, √3; one-shot functions, the topology-only refinement replayed on any vertex
// data, its weights and the stencil table; local subdivision matrices and their spectra.
#include <algorithm>
#include <complex>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "cifs/errors.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"

namespace cifs::python {
namespace {

namespace sd = cifs::subdivision;

sd::MeshOptions mesh_options(double max_bytes) {
  if (!(max_bytes > 0 && max_bytes < 1.8e19)) throw InvalidInput("max_bytes must be positive");
  return {.max_bytes = static_cast<std::size_t>(max_bytes)};
}

/// The mesh with its boundary rule replaced when `boundary` is given ("edge", "corner", "none").
Mesh with_boundary(const Mesh& mesh, const std::optional<std::string>& boundary) {
  Mesh out = mesh;
  if (boundary) out.tags.boundary = cifs::named_boundary_rule(*boundary);
  return out;
}
constexpr double kDefaultBytes = 4.0 * (1ull << 30);

/// A level's faces as (face_offsets, face_vertices) integer arrays.
py::tuple faces_of(const sd::MeshRefinement& r, int level) {
  if (level < 0 || level >= static_cast<int>(r.levels.size()))
    throw InvalidInput("faces: level " + std::to_string(level) + " outside 0.." +
                       std::to_string(r.levels.size() - 1));
  const MeshTopology& t = r.levels[static_cast<std::size_t>(level)];
  return py::make_tuple(vector_array(t.face_offsets), vector_array(t.face_vertices));
}

Points apply_checked(const sd::Stencils& s, const py::handle& vertices, const char* where) {
  const Points P = points_from(vertices, where);
  int needed = 0;
  for (const int c : s.columns) needed = std::max(needed, c + 1);
  if (P.rows() < needed)
    throw InvalidInput(std::string(where) + ": " + std::to_string(P.rows()) + " rows; these weights read " +
                       std::to_string(needed));
  py::gil_scoped_release release;
  return sd::apply(s, P);
}

/// Subdividing polygon meshes, limit points and the limit surface.
void bind_mesh_subdivision_meshes(py::module_& m) {
  m.def(
      "mesh_schemes",
      []() {
        py::list out;
        for (const sd::SchemeTraits& t : sd::mesh_schemes()) out.append(std::string(t.name));
        return out;
      },
      "Names of the mesh schemes: catmull-clark, loop, doo-sabin, butterfly, sqrt3, bilinear.");
  m.def(
      "subdivide",
      [](const Mesh& mesh, const std::string& scheme, int levels, const std::optional<std::string>& boundary,
         double max_bytes, bool factored) {
        const sd::MeshScheme s = sd::named_mesh_scheme(scheme);
        const sd::MeshOptions o = mesh_options(max_bytes);
        const Mesh tagged = with_boundary(mesh, boundary);
        py::gil_scoped_release release;
        return factored ? sd::factored_subdivide(tagged, s, levels, o) : sd::subdivide(tagged, s, levels, o);
      },
      py::arg("mesh"), py::arg("scheme"), py::arg("levels") = 1, py::kw_only(),
      py::arg("boundary") = py::none(), py::arg("max_bytes") = kDefaultBytes,
      py::arg("factored").noconvert() = false,
      "The mesh refined `levels` times by a named scheme (mesh_schemes()) under its tags (creases, corners, "
      "holes, options: mesh.tags). boundary, when given, replaces the mesh's boundary rule: 'edge' smooths "
      "boundary corners along the boundary curve, 'corner' keeps them, 'none' leaves out the faces around "
      "the boundary (Catmull–Clark, Loop). "
      "factored=True: linear subdivision then averaging (catmull-clark on quads, loop), the same mesh to "
      "round-off. Refused before any work when the result would need more than max_bytes.");
  m.def(
      "limit",
      [](const Mesh& mesh, const std::string& scheme, int levels, const std::optional<std::string>& boundary,
         bool normals, double max_bytes) {
        const sd::MeshScheme s = sd::named_mesh_scheme(scheme);
        const sd::LimitOptions o{.normals = normals, .max_bytes = mesh_options(max_bytes).max_bytes};
        const Mesh tagged = with_boundary(mesh, boundary);
        py::gil_scoped_release release;
        return sd::limit_mesh(tagged, s, levels, o);
      },
      py::arg("mesh"), py::arg("scheme"), py::arg("levels") = 1, py::kw_only(),
      py::arg("boundary") = py::none(), py::arg("normals").noconvert() = false,
      py::arg("max_bytes") = kDefaultBytes,
      "The mesh after `levels` steps with every vertex on the limit surface (left eigenvectors of the local "
      "subdivision matrices; creases, corners, holes and boundaries followed exactly, any valence), and unit "
      "limit normals when normals=True: per vertex, or per face corner (mesh.normal_indices) when a vertex "
      "lies between sectors (creases, corners: each corner its sector's normal); refused, naming the vertex, "
      "where a sector's spectrum proves no tangent plane. catmull-clark, loop, butterfly (interpolating: the "
      "vertices themselves; normals at interior vertices), sqrt3.");
  m.def(
      "limit_surface",
      [](const Mesh& mesh, const std::vector<int>& faces, const std::vector<double>& u,
         const std::vector<double>& v, const std::string& scheme, bool partials) {
        const sd::MeshScheme s_scheme = sd::named_mesh_scheme(scheme);
        if (faces.size() != u.size() || faces.size() != v.size())
          throw InvalidInput("limit_surface: faces, u and v must have one entry per point (" +
                             std::to_string(faces.size()) + ", " + std::to_string(u.size()) + ", " +
                             std::to_string(v.size()) + " given)");
        std::vector<sd::FacePoint> at(faces.size());
        for (std::size_t i = 0; i < at.size(); ++i) at[i] = {.face = faces[i], .u = u[i], .v = v[i]};
        sd::SurfaceSample s;
        {
          py::gil_scoped_release release;  // the tuple below needs the GIL back
          s = sd::evaluate_limit_surface(mesh, s_scheme, at, {.partials = partials});
        }
        if (!partials) return py::make_tuple(s.positions, py::none(), py::none());
        return py::make_tuple(s.positions, s.du, s.dv);
      },
      py::arg("mesh"), py::arg("faces"), py::arg("u"), py::arg("v"), py::kw_only(),
      py::arg("scheme") = "catmull-clark", py::arg("partials").noconvert() = true,
      "The limit surface at points (faces[i], u[i], v[i]) of any mesh under its tags (boundaries, creases, "
      "corners, darts, holes; any valence), in OpenSubdiv's parametrisation: catmull-clark ((u, v) in [0, "
      "1]^2 "
      "on quads; an n-gon's sub-face i at [i mod D, + 1/2] x [i div D, + 1/2], D = 2 for triangles, 3 for "
      "5-9 corners) or loop (triangles, u + v <= 1). (positions, du, dv), each (n, d) (du, dv None when "
      "partials=False). Exact. At a vertex that is never a polynomial patch (extraordinary, dart, irregular "
      "crease sector) du, dv are the face's two edges' parts in the tangent plane (their cross product is "
      "along the limit normal; not derivatives, which are 0 or unbounded there); such a point is refused "
      "where the spectrum proves no tangent plane, unless partials=False. Points on holes or outside their "
      "face are refused.");
}

/// Limit surfaces as automata, the fractal Catmull–Clark and Loop surfaces.
void bind_mesh_subdivision_surfaces(py::module_& m) {
  py::class_<sd::SurfaceAutomaton>(
      m, "SurfaceAutomaton",
      "A subdivision surface's limit as one controlled IFS: a patch per face, four children per state; "
      "catmull-clark: 'regular' (16 points) and 'E<n>' (2n + 8); loop: 'regular' (12) and 'E<n>' (n + 6).")
      .def_readonly("automaton", &sd::SurfaceAutomaton::automaton,
                    "cifs.automata.Automaton; entry i is face i.")
      .def_readonly("nets", &sd::SurfaceAutomaton::nets, "Per face, its patch's control points.")
      .def_readonly("corners", &sd::SurfaceAutomaton::corners,
                    "Per face, the mesh vertices at the patch's (s, t) = (0, 0), (1, 0), (1, 1), (0, 1) "
                    "(triangles: (0, 0), (1, 0), (0, 1), then -1).")
      .def_property_readonly(
          "scheme", [](const sd::SurfaceAutomaton& s) { return std::string(sd::scheme_name(s.scheme)); },
          "The subdivision scheme: 'catmull-clark' (quad patches) or 'loop' (triangle patches).");
  m.def(
      "surface_automaton",
      [](const Mesh& mesh, const std::string& scheme) {
        const sd::MeshScheme s = sd::named_mesh_scheme(scheme);
        py::gil_scoped_release release;
        return sd::surface_automaton(mesh, s);
      },
      py::arg("mesh"), py::kw_only(), py::arg("scheme") = "catmull-clark",
      "The SurfaceAutomaton of a mesh: catmull-clark (quads) or loop (triangles) with its boundary, creases, "
      "corners and holes (skipped); a closed untagged mesh's faces need at most one extraordinary corner "
      "(one level of refinement gives that). cifs.ifs's attractor, tolerance and chaos functions run on "
      "(s.automaton, s.nets).");
  py::class_<sd::FractalFeatures>(
      m, "FractalFeatures",
      "The fractal feature curves of a fractal surface (fractal_surface with creases or boundaries): the "
      "perturbed BC-IFS of the uniform cubic segment every fractal edge shares, and the edges (lower vertex, "
      "higher) with their 4-point nets. surface_automaton_mesh(surface, depth, features=...) adds them.")
      .def_readonly("perturbation", &sd::FractalFeatures::perturbation,
                    "The curve segment's perturbed BC-IFS (cifs.ifs.Perturbation).")
      .def_property_readonly(
          "edges",
          [](const sd::FractalFeatures& f) {
            std::vector<std::array<int, 2>> out;
            for (const auto& item : f.nets) out.push_back(item.first);
            return out;
          },
          "The fractal edges, each (lower vertex, higher vertex).")
      .def(
          "nodes",
          [](const sd::FractalFeatures& f, const std::array<int, 2>& edge, int depth) {
            return sd::feature_curve_nodes(f, edge, depth);
          },
          py::arg("edge"), py::arg("depth"),
          "The perturbed curve's 2^depth + 1 nodes along a fractal edge (lower vertex, higher), from the "
          "lower "
          "vertex.");
  m.def(
      "surface_automaton_mesh",
      [](const sd::SurfaceAutomaton& s, int depth, double max_bytes, const sd::FractalFeatures* features) {
        ifs::MeshOptions o;
        if (!(max_bytes > 0 && max_bytes < 1.8e19)) throw InvalidInput("max_bytes must be positive");
        o.max_bytes = static_cast<std::size_t>(max_bytes);
        if (features == nullptr) {
          py::gil_scoped_release release;
          return sd::surface_automaton_mesh(s, depth, o);
        }
        sd::FractalSurface f;
        f.surface = s;
        f.features = *features;
        py::gil_scoped_release release;
        return sd::surface_automaton_mesh(f, depth, o);
      },
      py::arg("surface"), py::arg("depth"), py::kw_only(), py::arg("max_bytes") = kDefaultBytes,
      py::arg("features") = py::none(),
      "The attractor at `depth` as one closed mesh (4^depth quads or triangles per face, shared nodes welded "
      "by the mesh's topology; Mesh.states the leaves' states); with `features` (FractalFeatures, from "
      "fractal_surface) the fractal crease and boundary curves' displacements added face by face.");
  m.def(
      "fractal_surface",
      [](const sd::SurfaceAutomaton& s, double amplitude, std::uint64_t seed,
         const std::optional<std::map<std::string, double>>& values, const std::optional<Mesh>& mesh,
         bool creases, bool boundaries, double curve_amplitude, std::uint64_t curve_seed,
         const std::optional<std::map<std::string, double>>& curve_values) {
        ifs::PerturbOptions o;
        o.amplitude = amplitude;
        o.seed = seed;
        o.values = values.value_or(std::map<std::string, double>{});
        const bool curves = creases || boundaries;
        if (curves && !mesh)
          throw InvalidInput("mesh: fractal creases and boundaries need the mesh the surface was built from");
        if (!curves && (mesh || curve_amplitude != 0 || curve_values))
          throw InvalidInput(
              "creases: mesh, curve_amplitude and curve_values serve fractal creases or boundaries "
              "(creases=True, boundaries=True)");
        if (!(curve_amplitude >= 0)) throw InvalidInput("curve_amplitude: expected a number ≥ 0");
        sd::FractalFeatureOptions features;
        features.creases = creases;
        features.boundaries = boundaries;
        features.perturbation.amplitude = curve_amplitude;
        features.perturbation.seed = curve_seed;
        features.perturbation.values = curve_values.value_or(std::map<std::string, double>{});
        sd::FractalSurface f;
        {
          py::gil_scoped_release release;  // the tuple below needs the GIL back
          f = curves ? sd::fractal_surface(*mesh, s, o, features) : sd::fractal_surface(s, o);
        }
        if (!curves) return py::make_tuple(std::move(f.surface), std::move(f.perturbation));
        return py::make_tuple(std::move(f.surface), std::move(f.perturbation), std::move(f.features));
      },
      py::arg("surface"), py::kw_only(), py::arg("amplitude") = 0.0, py::arg("seed") = 1,
      py::arg("values") = py::none(), py::arg("mesh") = py::none(), py::arg("creases") = false,
      py::arg("boundaries") = false, py::arg("curve_amplitude") = 0.0, py::arg("curve_seed") = 1,
      py::arg("curve_values") = py::none(),
      "A fractal Catmull–Clark or Loop surface with the mesh's topology: the regular state replaced by the "
      "regular patch's BC-IFS (the uniform bicubic patch's, the quartic box-spline triangle's), perturbed "
      "(cifs.ifs.perturb's amplitude, seed, values). Every face keeps the smooth surface's boundary curves, "
      "the "
      "mesh's boundary and creases among them. Returns (SurfaceAutomaton, cifs.ifs.Perturbation). With "
      "creases=True (the infinitely sharp creases) or boundaries=True (the boundary curves) and `mesh` (the "
      "mesh "
      "the surface was built from), those curves become fractal on their own — the uniform cubic segment's "
      "BC-IFS perturbed by curve_amplitude, curve_seed, curve_values — the surface watertight across them: "
      "returns (SurfaceAutomaton, cifs.ifs.Perturbation, FractalFeatures), the last for "
      "surface_automaton_mesh(..., features=...).");
}

/// One function per mesh scheme.
void bind_mesh_subdivision_schemes(py::module_& m) {
  const auto one = [&m](const char* name, sd::MeshScheme scheme, const char* doc) {
    m.def(
        name,
        [scheme](const Mesh& mesh, int levels, const std::optional<std::string>& boundary, double max_bytes) {
          const sd::MeshOptions o = mesh_options(max_bytes);
          const Mesh tagged = with_boundary(mesh, boundary);
          py::gil_scoped_release release;
          return sd::subdivide(tagged, scheme, levels, o);
        },
        py::arg("mesh"), py::arg("levels") = 1, py::kw_only(), py::arg("boundary") = py::none(),
        py::arg("max_bytes") = kDefaultBytes, doc);
  };
  one("catmull_clark", sd::MeshScheme::catmull_clark, "Catmull–Clark (any polygons; quads after one level).");
  one("loop", sd::MeshScheme::loop, "Loop (triangles).");
  one("doo_sabin", sd::MeshScheme::doo_sabin, "Doo–Sabin (any polygons; dual).");
  one("butterfly", sd::MeshScheme::butterfly,
      "Modified Butterfly, Zorin–Schröder–Sweldens (triangles; interpolating).");
  one("sqrt3", sd::MeshScheme::sqrt3, "Kobbelt's √3 (triangles).");
  one("bilinear", sd::MeshScheme::bilinear,
      "Bilinear (any polygons; quads at edge midpoints and centroids).");
}

/// Stencils and refinements (topology only).
void bind_mesh_subdivision_refinement(py::module_& m) {
  py::class_<sd::Stencils>(m, "Stencils",
                           "Sparse weights, one row per new vertex: row i is Σ weights[k]·old[columns[k]] "
                           "for k in offsets[i]..offsets[i+1].")
      .def_property_readonly(
          "offsets", [](const sd::Stencils& s) { return vector_array(s.offsets); }, "Row starts (rows + 1).")
      .def_property_readonly(
          "columns", [](const sd::Stencils& s) { return vector_array(s.columns); },
          "Old vertex of each weight.")
      .def_property_readonly(
          "weights", [](const sd::Stencils& s) { return vector_array(s.weights); }, "The weights.")
      .def_property_readonly(
          "rows", [](const sd::Stencils& s) { return sd::row_count(s); }, "Number of new vertices.")
      .def(
          "apply",
          [](const sd::Stencils& s, const py::handle& v) { return apply_checked(s, v, "apply: vertices"); },
          py::arg("vertices"), "The new vertices' data from the old ones (`(#old, any)` array).")
      .def("__repr__", [](const sd::Stencils& s) {
        return "Stencils(" + std::to_string(sd::row_count(s)) + " rows, " + std::to_string(s.weights.size()) +
               " weights)";
      });

  py::class_<sd::MeshRefinement>(m, "MeshRefinement",
                                 "A refinement, topology only: every level's faces and every step's weights, "
                                 "replayed on any number of vertex data sets.")
      .def_property_readonly(
          "scheme", [](const sd::MeshRefinement& r) { return std::string(sd::scheme_name(r.scheme)); },
          "The scheme's name.")
      .def_property_readonly(
          "levels", [](const sd::MeshRefinement& r) { return static_cast<int>(r.levels.size()) - 1; },
          "Number of steps.")
      .def_property_readonly(
          "vertex_counts",
          [](const sd::MeshRefinement& r) {
            std::vector<int> counts;
            for (const MeshTopology& t : r.levels) counts.push_back(t.vertex_count);
            return counts;
          },
          "Vertices at every level, input first.")
      .def_property_readonly(
          "steps", [](const sd::MeshRefinement& r) { return r.steps; }, "Each step's Stencils.")
      .def("faces", &faces_of, py::arg("level"), "(face_offsets, face_vertices) of a level (0 = the input).")
      .def(
          "apply",
          [](const sd::MeshRefinement& r, const py::handle& vertices) {
            const Points P = points_from(vertices, "apply: vertices");
            py::gil_scoped_release release;
            return sd::apply(r, P);
          },
          py::arg("vertices"), "The last level's data from the input's (`(#V, any)` array).")
      .def(
          "stencil_table",
          [](const sd::MeshRefinement& r) {
            py::gil_scoped_release release;
            return sd::stencil_table(r);
          },
          "Stencils from the input's vertices straight to the last level's (the product of the steps).")
      .def("__repr__", [](const sd::MeshRefinement& r) {
        return "MeshRefinement(" + std::string(sd::scheme_name(r.scheme)) + ", " +
               std::to_string(r.levels.size() - 1) + " levels, " +
               std::to_string(r.levels.back().vertex_count) + " vertices)";
      });
  m.def(
      "refine_topology",
      [](const Mesh& mesh, const std::string& scheme, int levels, const std::optional<std::string>& boundary,
         double max_bytes, bool weights, bool last_level_adjacency) {
        const sd::MeshScheme s = sd::named_mesh_scheme(scheme);
        sd::MeshOptions o = mesh_options(max_bytes);
        o.weights = weights;
        o.last_level_adjacency = last_level_adjacency;
        const Mesh tagged = with_boundary(mesh, boundary);
        py::gil_scoped_release release;
        return sd::refine_topology(tagged, s, levels, o);
      },
      py::arg("mesh"), py::arg("scheme"), py::arg("levels") = 1, py::kw_only(),
      py::arg("boundary") = py::none(), py::arg("max_bytes") = kDefaultBytes, py::arg("weights") = true,
      py::arg("last_level_adjacency") = true,
      "The refinement's topology and weights only; MeshRefinement.apply replays it on vertex data. "
      "weights=False keeps no weights (topology only, as OpenSubdiv's RefineUniform: apply and "
      "stencil_table refuse it); last_level_adjacency=False builds the last level's faces only.");
}

/// Local analysis at a vertex or face.
void bind_mesh_subdivision_analysis(py::module_& m) {
  m.def(
      "local_analysis",
      [](const std::string& scheme, int valence, const std::optional<std::string>& boundary,
         const std::vector<int>& sharp, bool corner, bool concave, const std::string& rules,
         const std::vector<int>& interior_corners) {
        if (std::any_of(interior_corners.begin(), interior_corners.end(),
                        [](int c) { return c != 0 && c != 1; }))
          throw InvalidInput("local_analysis: interior_corners: 1 (interior) or 0 (boundary) per corner");
        const sd::LocalOptions o{
            .boundary = boundary.has_value() || !interior_corners.empty(),
            .rule = boundary ? cifs::named_boundary_rule(*boundary) : sd::BoundaryRule::edge_only,
            .sharp = sharp,
            .corner = corner,
            .concave = concave,
            .rules = cifs::named_rule_set(rules),
            .interior_corners = std::vector<char>(interior_corners.begin(), interior_corners.end())};
        const sd::LocalMatrix S = sd::local_matrix(sd::named_mesh_scheme(scheme), valence, o);
        const sd::LocalSpectrum sp = sd::local_spectrum(S);
        const auto complex_of = [](const std::complex<long double>& z) {
          return std::complex<double>(static_cast<double>(z.real()), static_cast<double>(z.imag()));
        };
        py::dict out;
        out["labels"] = S.labels;
        out["steps"] = S.steps;
        out["matrix"] = Points(S.values.cast<double>());
        if (S.exact) {
          const py::object fraction = py::module_::import("fractions").attr("Fraction");
          py::list rows;
          for (int i = 0; i < S.exact->rows; ++i) {
            py::list row;
            for (int j = 0; j < S.exact->cols; ++j) row.append(fraction(sd::to_string((*S.exact)(i, j))));
            rows.append(row);
          }
          out["exact"] = rows;
        } else {
          out["exact"] = py::none();
        }
        py::list eigenvalues;
        for (const auto& z : sp.eigenvalues) eigenvalues.append(complex_of(z));
        out["eigenvalues"] = eigenvalues;
        out["dominant_simple"] = sp.dominant_simple;
        out["subdominant_pair"] = sp.subdominant_pair;
        out["gap"] = sp.gap;
        out["lambda1"] = static_cast<double>(sp.subdominant);
        out["lambda2"] = static_cast<double>(sp.second);
        out["mu"] = complex_of(sp.mu);
        out["curvature_ratio"] = sp.curvature_ratio
                                     ? py::object(py::float_(static_cast<double>(*sp.curvature_ratio)))
                                     : py::none();
        out["curvature"] = sp.curvature;
        out["subdominant_basis"] = Points(sp.subdominant_basis.cast<double>());
        out["vertex"] = sd::vertex_class(valence, o);
        const auto verdict = [](const sd::C1Verdict& v) {
          py::dict c1;
          c1["verdict"] = v.c1;
          c1["reason"] = v.reason;
          c1["spectral"] = v.spectral;
          c1["method"] = v.method;
          c1["pieces"] = v.pieces;
          c1["regular"] = v.regular;
          c1["winding"] = v.winding;
          c1["margin"] = static_cast<double>(v.margin);
          c1["angle"] = static_cast<double>(v.angle);
          return c1;
        };
        const sd::C1Verdict v = sd::c1_verdict(S, sp);
        py::dict c1 = verdict(v);
        py::list sectors;
        for (const sd::C1Verdict::Sector& sector : v.sectors) {
          py::dict d;
          d["faces"] = sector.faces;
          d["lambda1"] = static_cast<double>(sector.spectrum.subdominant);
          d["lambda2"] = static_cast<double>(sector.spectrum.second);
          d["c1"] = verdict(sector.verdict);
          sectors.append(d);
        }
        c1["sectors"] = sectors;
        out["c1"] = c1;
        out["limit_stencil"] = Eigen::VectorXd(sp.limit_stencil.cast<double>());
        return out;
      },
      py::arg("scheme"), py::arg("valence"), py::kw_only(), py::arg("boundary") = py::none(),
      py::arg("sharp") = std::vector<int>{}, py::arg("corner") = false, py::arg("concave") = false,
      py::arg("rules") = "opensubdiv", py::arg("interior_corners") = std::vector<int>{},
      "The local subdivision matrix S_n at a vertex of this valence (doo-sabin: an n-gon face; "
      "boundary='edge'|'corner': a boundary vertex of valence - 1 faces; sharp: the infinitely sharp "
      "edges c r_j by j; corner: c infinitely sharp; concave: a corner meant to span more than 180 "
      "degrees; rules='opensubdiv'|'blz' (Biermann-Levin-Zorin 2000) — catmull-clark and loop; "
      "interior_corners: doo-sabin's n-gon face touching the boundary, 1 (interior) or 0 per corner) and its "
      "spectrum and C1 verdict (per sector at tagged and "
      "boundary vertices), as a dict: vertex (its class), c1, "
      "labels, steps, matrix, exact (Fractions or None), eigenvalues by modulus, dominant_simple, "
      "subdominant_pair, gap, lambda1, lambda2, mu, curvature_ratio (lambda2^2/|mu|), curvature, "
      "subdominant_basis, limit_stencil (docs/subdivision-surfaces.md).");
  m.def(
      "analyze_mesh",
      [](const Mesh& mesh, const std::string& scheme) {
        const sd::MeshScheme s = sd::named_mesh_scheme(scheme);
        sd::MeshSmoothness a;
        {
          py::gil_scoped_release release;
          a = sd::analyze_mesh(mesh, s);
        }
        py::list vertices;
        for (const sd::VertexSmoothness& v : a.vertices) {
          py::dict d;
          d["vertex"] = v.vertex;
          d["face"] = v.face;
          d["class"] = v.vertex_class;
          d["valence"] = v.valence;
          d["sector_faces"] = v.sectors;
          d["semi_sharp"] = v.semi_sharp;
          d["lambda1"] = static_cast<double>(v.lambda1);
          d["lambda2"] = static_cast<double>(v.lambda2);
          d["curvature_ratio"] = v.curvature_ratio
                                     ? py::object(py::float_(static_cast<double>(*v.curvature_ratio)))
                                     : py::none();
          d["c1"] = v.verdict.c1        ? py::object(py::bool_(true))
                    : v.verdict.decided ? py::object(py::bool_(false))
                                        : py::none();
          d["method"] = v.verdict.method;
          d["reason"] = v.verdict.reason;
          vertices.append(d);
        }
        py::dict out;
        out["vertices"] = vertices;
        out["regular"] = a.regular;
        out["in_no_face"] = a.isolated;
        out["c1"] = a.c1;
        out["not_c1"] = a.not_c1;
        out["undecided"] = a.undecided;
        out["analyses"] = a.analyses;
        out["summary"] = a.summary;
        return out;
      },
      py::arg("mesh"), py::arg("scheme"),
      "Which points of the mesh are not smooth: every irregular vertex (extraordinary, boundary, crease, "
      "dart, corner) of a catmull-clark, loop, sqrt3 or butterfly mesh — doo-sabin: every irregular face "
      "centre (face, vertex -1) and interior vertex's face — with its class, valence, sector faces, lambda1, "
      "lambda2, curvature_ratio and C1 verdict (True, False, or None when undecided) with its reason; "
      "counts and a summary line (docs/subdivision-surfaces.md).");
}

}  // namespace

void bind_mesh_subdivision(py::module_& m) {
  bind_mesh_subdivision_meshes(m);
  bind_mesh_subdivision_surfaces(m);
  bind_mesh_subdivision_schemes(m);
  bind_mesh_subdivision_refinement(m);
  bind_mesh_subdivision_analysis(m);
}

}  // namespace cifs::python
