# ctest driver: install the `python` component of the build into a scratch prefix and import the
# package from there (not from the build tree). Variables: BUILD, WORK, PYTHON, SITE (the package
# folder relative to the prefix, CIFS_PYTHON_INSTALL_DIR).
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK} --component python
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "install failed:\n${out}\n${err}")
endif()
set(check [=[
import sys, cifs
from pathlib import Path
assert Path(cifs.__file__).resolve().is_relative_to(Path(sys.argv[1]).resolve()), cifs.__file__
for stub in ("py.typed", "__init__.pyi", "nurbs.pyi", "render.pyi"):  # the type stubs ship with the package
    assert (Path(cifs.__file__).parent / stub).is_file(), stub
c = cifs.nurbs.uniform_bspline([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]], 2, False)
print("installed cifs", cifs.__version__, "at", Path(cifs.__file__).parent, "C(0.5) =", list(cifs.nurbs.evaluate(c, 0.5)))
]=])
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH PYTHONPATH=${WORK}/${SITE} ${PYTHON} -c "${check}" ${WORK}
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "import of the installed package failed:\n${out}\n${err}")
endif()
message(STATUS "${out}")
# PREFIX/bin/cifs-python imports the installed package from anywhere, without PYTHONPATH.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH ${WORK}/bin/cifs-python -c "${check}" ${WORK}
  WORKING_DIRECTORY ${WORK}/bin RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the installed launcher bin/cifs-python failed:\n${out}\n${err}")
endif()
message(STATUS "bin/cifs-python: ${out}")

