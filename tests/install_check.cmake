# ctest install.check_scenes: installs the build into a scratch prefix and checks what a
# user of the installed tree gets: the executables, every installed scene accepted by
# `granhydro --check` (the silo scenes find their mesh in share/granhydro/meshes through
# their relative Mesh file), the documentation that README.md links to, and the tools with
# their Python package.
#   cmake -DBUILD=<build dir> -DPREFIX=<scratch prefix> -P tests/install_check.cmake
if(NOT BUILD OR NOT PREFIX)
  message(FATAL_ERROR "install_check: give -DBUILD=<build dir> -DPREFIX=<scratch prefix>")
endif()
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${PREFIX}"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}):\n${err}")
endif()
include(GNUInstallDirs)
set(share "${PREFIX}/${CMAKE_INSTALL_DATADIR}/granhydro")
set(docdir "${PREFIX}/${CMAKE_INSTALL_DATADIR}/doc/granhydro")
foreach(f "${PREFIX}/${CMAKE_INSTALL_BINDIR}/granhydro" "${PREFIX}/${CMAKE_INSTALL_BINDIR}/granhydro_bed_budget"
          "${share}/meshes/silo_3d.msh" "${share}/tools/plot_profiles.py"
          "${share}/tools/granhydro_py/granhydro/readers.py" "${docdir}/README.md"
          "${docdir}/doc/user-guide.md" "${docdir}/doc/physics.md" "${docdir}/doc/parameters.md")
  if(NOT EXISTS "${f}")
    message(FATAL_ERROR "install_check: not installed: ${f}")
  endif()
endforeach()
# the installed executable finds its library through its install run path ($ORIGIN/../lib)
file(GLOB_RECURSE scenes "${share}/parameters/*.prm")
list(LENGTH scenes n)
if(n LESS 20)
  message(FATAL_ERROR "install_check: only ${n} scenes installed below ${share}/parameters")
endif()
set(failed 0)
foreach(scene ${scenes})
  execute_process(COMMAND "${PREFIX}/${CMAKE_INSTALL_BINDIR}/granhydro" --check "${scene}"
                  WORKING_DIRECTORY "${PREFIX}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 120)
  if(NOT rc EQUAL 0)
    message(SEND_ERROR "granhydro --check ${scene} exited with ${rc}:\n${out}${err}")
    math(EXPR failed "${failed} + 1")
  endif()
endforeach()
if(failed GREATER 0)
  message(FATAL_ERROR "install_check: ${failed} of ${n} installed scenes refused")
endif()
message(STATUS "install_check: ${n} installed scenes accepted by --check; executables, meshes, tools and documentation installed")
