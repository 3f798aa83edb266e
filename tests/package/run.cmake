# ctest driver: install the build tree into a scratch prefix and move the prefix (what is installed
# must find its own files relative to itself), then:
# - the installed cifs: its gallery's default examples are the prefix's (shown in --help), and with
#   the prefix's experiments cut down to one it writes that one's outputs, none of the source tree's;
# - shared libraries (SHARED): the installed cifs and the consumer resolve libcifs_* inside the prefix;
# - tests/package in each MODE of its CMakeLists.txt, configured, built and run against the prefix.
# Variables: BUILD (cifs build dir), SRC (this folder), WORK (scratch), SHARED (BUILD_SHARED_LIBS), CLI
# (whether the build has the cifs CLI), OCCT (whether it has the optional cifs::occt),
# FLAGS (the cifs build's CMAKE_CXX_FLAGS: a sanitized cifs needs a sanitized consumer to link).
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "step failed: ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/staging)
file(RENAME ${WORK}/staging ${WORK}/prefix)
set(prefix ${WORK}/prefix)
file(REAL_PATH ${prefix} prefix_real)

# The installed CLI's gallery reads the prefix's examples (the source tree's have all experiments).
set(cli ${prefix}/bin/cifs)
if(CLI)
  run(${cli} gallery --help)
  string(FIND "${out}" "default: ${prefix_real}/share/cifs/examples:" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the installed cifs gallery does not default to ${prefix_real}/share/cifs/examples:\n${out}")
  endif()
  file(GLOB experiments ${prefix}/share/cifs/examples/experiments/*.json)
  list(LENGTH experiments count)
  if(count LESS 10 OR NOT EXISTS ${prefix}/share/cifs/examples/experiments/circle.json)
    message(FATAL_ERROR "examples not installed: ${count} experiments in ${prefix}/share/cifs/examples/experiments")
  endif()
  list(REMOVE_ITEM experiments ${prefix}/share/cifs/examples/experiments/circle.json)
  file(REMOVE ${experiments})
  run(${cli} gallery ${WORK}/gallery --quiet)
  if(NOT EXISTS ${WORK}/gallery/circle.png OR EXISTS ${WORK}/gallery/sierpinski.png)
    message(FATAL_ERROR "the installed cifs gallery did not run the prefix's one experiment (circle):\n${out}")
  endif()
  message(STATUS "installed gallery from ${prefix_real}/share/cifs/examples:\n${out}")
endif()

# With OpenCASCADE, the installed CLI opens the prefix's plugin (lib/cifs/) for a STEP file.
if(CLI AND OCCT)
  run(${cli} convert ${prefix}/share/cifs/examples/shapes/hills.json ${WORK}/hills.step)
  run(${cli} info ${WORK}/hills.step)
  if(NOT out MATCHES "\"type\": \"surface\"")
    message(FATAL_ERROR "the installed cifs did not read back its STEP file:\n${out}")
  endif()
  file(GLOB plugin ${prefix}/lib*/cifs/libcifs_occt_plugin.so ${prefix}/lib*/*/cifs/libcifs_occt_plugin.so)
  if(NOT plugin)
    message(FATAL_ERROR "the OpenCASCADE plugin is not installed under ${prefix}/lib…/cifs/")
  endif()
  message(STATUS "installed cifs read STEP through ${plugin}")
endif()

# Every libcifs_* an installed program loads comes from the prefix (RUNPATH relative to it).
function(check_libraries executable)
  file(GET_RUNTIME_DEPENDENCIES EXECUTABLES ${executable} RESOLVED_DEPENDENCIES_VAR resolved
    UNRESOLVED_DEPENDENCIES_VAR unresolved)
  set(ours ${resolved})
  list(FILTER ours INCLUDE REGEX "libcifs_")
  list(FILTER unresolved INCLUDE REGEX "libcifs_")
  if(unresolved OR NOT ours)
    message(FATAL_ERROR "${executable}: libcifs_* unresolved (${unresolved}) or none (${resolved})")
  endif()
  foreach(library IN LISTS ours)
    file(REAL_PATH ${library} library)
    string(FIND "${library}" "${prefix_real}/" at)
    if(NOT at EQUAL 0)
      message(FATAL_ERROR "${executable} loads ${library}, outside ${prefix_real}")
    endif()
  endforeach()
  message(STATUS "${executable}: ${ours}")
endfunction()
if(SHARED AND CLI)
  check_libraries(${cli})
endif()

# OCCT: whether cifs was built with the optional OpenCASCADE component.
if(OCCT)
  set(occt_mode occt)
else()
  set(occt_mode no_occt)
endif()
foreach(mode all nurbs io ${occt_mode} unknown)
  set(build ${WORK}/build_${mode})
  run(${CMAKE_COMMAND} -S ${SRC} -B ${build} -DMODE=${mode} -DCMAKE_PREFIX_PATH=${prefix}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=${FLAGS})
  if(mode STREQUAL "unknown" OR mode STREQUAL "no_occt")
    continue()
  endif()
  run(${CMAKE_COMMAND} --build ${build})
  run(${build}/consumer)
  message(STATUS "${out}")
  if(SHARED)
    check_libraries(${build}/consumer)
  endif()
endforeach()
