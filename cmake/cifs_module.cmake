# cifs_module(NAME SOURCES ... [DEPENDS target ...] [PRIVATE_DEPENDS target ...] [HEADER_ONLY_DEPENDS target ...])
# One library per module folder: target cifs_NAME, alias cifs::NAME, headers under
# NAME/include/cifs/NAME, installed and exported with the package as its component NAME.
# HEADER_ONLY_DEPENDS are private and used only while building: a header-only library has nothing to
# link, so the installed static library does not name it and its consumers never look for it.
function(cifs_warnings target)
  # -Wno-restrict: GCC 12 reports string concatenations falsely (GCC bug 105329).
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
  if(CIFS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# cifs_find_package(NAME ARGS...): find_package(NAME ARGS... REQUIRED) for a dependency of the module
# libraries, remembering ARGS: the package config finds NAME the same way, and only for the
# components whose link interface names a NAME:: target.
macro(cifs_find_package name)
  find_package(${name} ${ARGN} REQUIRED)
  set_property(GLOBAL PROPERTY CIFS_FIND_${name} ${name} ${ARGN})
endmacro()

function(cifs_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS;HEADER_ONLY_DEPENDS" ${ARGN})
  add_library(cifs_${name} ${ARG_SOURCES})
  add_library(cifs::${name} ALIAS cifs_${name})
  # Shared (BUILD_SHARED_LIBS): versioned like the package (SameMinorVersion), and an installed
  # library finds the others beside it.
  set_target_properties(cifs_${name} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR} INSTALL_RPATH "$ORIGIN")
  target_include_directories(cifs_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  set(header_only)
  foreach(dep IN LISTS ARG_HEADER_ONLY_DEPENDS)
    list(APPEND header_only $<BUILD_INTERFACE:${dep}>)
  endforeach()
  target_link_libraries(cifs_${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS} ${header_only})
  target_compile_features(cifs_${name} PUBLIC cxx_std_20)
  cifs_warnings(cifs_${name})
  # Under libFuzzer the numeric modules' comparisons are not traced: Eigen's inlined loops sent every
  # iteration through __sanitizer_cov_trace_cmp8 (53 % of fuzz_compute's time, perf, 1 Dec); edge coverage
  # stays. The parsers (core, io) keep the comparison feedback that finds their keywords and magic numbers.
  if(CIFS_FUZZ AND NOT name MATCHES "^(core|io)$")
    target_compile_options(cifs_${name} PRIVATE -fno-sanitize-coverage=trace-cmp)
  endif()
  install(TARGETS cifs_${name} EXPORT cifs_${name}Targets)
  install(EXPORT cifs_${name}Targets NAMESPACE cifs:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cifs)
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

  # What a consumer of the installed component needs: the modules and packages of its link interface.
  # A static library's private dependencies are in it too ($<LINK_ONLY:…>); a shared one's are not.
  set(interface ${ARG_DEPENDS})
  get_target_property(type cifs_${name} TYPE)
  if(type STREQUAL "STATIC_LIBRARY")
    list(APPEND interface ${ARG_PRIVATE_DEPENDS})
  endif()
  set(modules)
  set(packages)
  foreach(dep IN LISTS interface)
    string(REGEX MATCH "^([^:]+)::(.*)$" match "${dep}")
    if(NOT match)
      message(FATAL_ERROR "cifs_module(${name}): '${dep}' is not a NAMESPACE::target dependency")
    elseif(CMAKE_MATCH_1 STREQUAL "cifs")
      list(APPEND modules ${CMAKE_MATCH_2})
    else()
      get_property(found GLOBAL PROPERTY CIFS_FIND_${CMAKE_MATCH_1} SET)
      if(NOT found)
        message(FATAL_ERROR "cifs_module(${name}): find ${CMAKE_MATCH_1} with cifs_find_package, not find_package")
      endif()
      list(APPEND packages ${CMAKE_MATCH_1})
    endif()
  endforeach()
  set_property(GLOBAL APPEND PROPERTY CIFS_MODULES ${name})
  set_property(GLOBAL PROPERTY CIFS_MODULE_${name}_MODULES ${modules})
  set_property(GLOBAL PROPERTY CIFS_MODULE_${name}_PACKAGES ${packages})
endfunction()

# The table of the package config (cmake/cifsConfig.cmake.in) in CIFS_COMPONENT_TABLE: the
# components (modules in layer order), per component the modules it needs (itself and everything
# below it in its link interface, in layer order) and the packages they name, and per package the
# arguments of its find_package.
function(cifs_component_table)
  get_property(all GLOBAL PROPERTY CIFS_MODULES)
  list(JOIN all " " names)
  set(table "set(_cifs_components ${names})\n")
  set(used_packages)
  foreach(name IN LISTS all)
    get_property(direct GLOBAL PROPERTY CIFS_MODULE_${name}_MODULES)
    get_property(packages GLOBAL PROPERTY CIFS_MODULE_${name}_PACKAGES)
    set(needed ${name})
    foreach(dep IN LISTS direct)
      list(APPEND needed ${closure_${dep}})  # modules come in layer order: dep's closure is known
      list(APPEND packages ${packages_${dep}})
    endforeach()
    set(closure_${name})
    foreach(module IN LISTS all)  # in layer order, each once
      if(module IN_LIST needed)
        list(APPEND closure_${name} ${module})
      endif()
    endforeach()
    list(REMOVE_DUPLICATES packages)
    set(packages_${name} ${packages})
    list(APPEND used_packages ${packages})
    list(JOIN closure_${name} " " modules)
    list(JOIN packages " " names)
    string(APPEND table "set(_cifs_${name}_modules ${modules})\nset(_cifs_${name}_packages ${names})\n")
  endforeach()
  list(REMOVE_DUPLICATES used_packages)
  foreach(package IN LISTS used_packages)
    get_property(args GLOBAL PROPERTY CIFS_FIND_${package})
    list(JOIN args " " args)
    string(APPEND table "set(_cifs_find_${package} ${args})\n")
  endforeach()
  set(CIFS_COMPONENT_TABLE "${table}" PARENT_SCOPE)
endfunction()
