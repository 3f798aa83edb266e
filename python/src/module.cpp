// SPDX-License-Identifier: MIT
// cifs Python bindings — the extension module `cifs._cifs`: error types and submodules.
#include <exception>
#include <filesystem>
#include <new>

#include "bindings.hpp"
#include "cifs/errors.hpp"
#ifdef CIFS_HAVE_OCCT
#include "cifs/occt/occt.hpp"
#endif

namespace py = pybind11;
using namespace cifs::python;

PYBIND11_MODULE(_cifs, m) {
  m.doc() =
      "cifs — NURBS curves and surfaces and subdivision schemes as controlled iterated function systems.";
  m.attr("__version__") = CIFS_VERSION;
#ifdef CIFS_HAVE_OCCT
  cifs::occt::enable_cad_formats();  // cifs.io.read_shape("part.step") …, through OpenCASCADE
#endif
  py::register_exception<cifs::InvalidInput>(m, "InvalidInput", PyExc_ValueError);
  static const py::exception<cifs::IoError> io_error =
      py::register_exception<cifs::IoError>(m, "IoError", PyExc_OSError);
  // A refused allocation (the machine's memory, a ulimit) said "MemoryError: std::bad_alloc"; a
  // file-system error that escaped the readers' own checks, a bare RuntimeError.
  // NOLINTNEXTLINE(performance-unnecessary-value-param): pybind11 takes a void (*)(std::exception_ptr)
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::filesystem::filesystem_error& e) {
      const std::string path = e.path1().string();
      PyErr_SetString(io_error.ptr(),
                      ((path.empty() ? std::string() : path + ": ") + e.code().message()).c_str());
    } catch (const std::bad_alloc&) {
      PyErr_SetString(PyExc_MemoryError,
                      "out of memory: the system refused an allocation; ask for less (a lower depth, fewer "
                      "points or samples, a smaller image)");
    }
  });

  // Order: a submodule's types are registered before the submodules whose signatures use them (else the
  // signatures, docstrings and stubs show C++ names: `limit(mesh: cifs::Mesh)`). The meshes and segment
  // sets of io come first: nurbs, ifs, subdivision and render take and return them.
  auto io = m.def_submodule(
      "io",
      "Every file format: shapes, polygons, meshes, segment sets, automata, BC-IFS and experiment\n"
      "files; the format table and read/write by extension.");
  bind_io_types(io);
  auto nurbs = m.def_submodule("nurbs",
                               "B-spline and NURBS curves and surfaces: evaluation, knot insertion, "
                               "blossoms, knot-doubling matrices.");
  bind_nurbs(nurbs);
  auto automata = m.def_submodule("automata",
                                  "Automata whose transitions carry subdivision matrices: knot "
                                  "doubling, tensor products, hand-made automata.");
  bind_automata(automata);
  auto ifs = m.def_submodule("ifs",
                             "The CIFS engine: attractors, contraction, chaos game, meshes, BC-IFS "
                             "constraints and free coefficients, classic affine IFS, fractal dimension.");
  bind_ifs(ifs);
  bind_bcifs(ifs);
  auto subdivision = m.def_submodule("subdivision",
                                     "Uniform binary curve subdivision schemes: masks, "
                                     "refinement, IFS matrices, smoothness analysis; subdivision "
                                     "surfaces on polygon meshes.");
  bind_subdivision(subdivision);
  bind_mesh_subdivision(subdivision);
  auto render = m.def_submodule("render", "Cameras, rasterisers, the chaos-game density, OpenEXR and PNG.");
  bind_render(render);
  bind_io(io);
  bind_bcifs_io(io);
  bind_io_dispatch(io);
  auto verify =
      m.def_submodule("verify", "Attractor vs knot insertion vs Cox–de Boor, per segment or patch.");
  bind_verify(verify);
  auto experiment = m.def_submodule("experiment",
                                    "Running experiment files: build, perturb, evaluate, "
                                    "render, export.");
  bind_experiment(experiment);
  check_arguments(m);  // after every function exists
}
