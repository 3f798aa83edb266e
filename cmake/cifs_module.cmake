# cifs_module(NAME SOURCES ... [DEPENDS target ...] [PRIVATE_DEPENDS target ...])
# One library per module folder: target cifs_NAME, alias cifs::NAME, headers under
# NAME/include/cifs/NAME, installed and exported with the package.
function(cifs_warnings target)
  # -Wno-restrict: GCC 12 reports string concatenations falsely (GCC bug 105329).
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
  if(CIFS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

function(cifs_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(cifs_${name} ${ARG_SOURCES})
  add_library(cifs::${name} ALIAS cifs_${name})
  set_target_properties(cifs_${name} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(cifs_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(cifs_${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS})
  target_compile_features(cifs_${name} PUBLIC cxx_std_20)
  cifs_warnings(cifs_${name})
  install(TARGETS cifs_${name} EXPORT cifsTargets)
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
