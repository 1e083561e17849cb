# ctest install.check_scenes: installs the build into a scratch prefix and checks what a
# user of the installed tree gets: the executables, every installed scene accepted by
# `granhydro --check` (the silo scenes find their mesh in share/granhydro/meshes through
# their relative Mesh file), the documentation that README.md links to, the tools with
# their Python package, and headers that are the public API only: no internal header
# (source/<layer>/*.h) is installed, and every granhydro header an installed header
# includes is installed.
#   cmake -DBUILD=<build dir> -DPREFIX=<scratch prefix> [-DSOURCE=<checkout>] -P tests/install/install_check.cmake
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
# the headers: the public API only, and closed under #include
set(incdir "${PREFIX}/${CMAKE_INSTALL_INCLUDEDIR}")
if(NOT EXISTS "${incdir}/granhydro/mesh/cartesian_patch.h")
  message(FATAL_ERROR "install_check: not installed: ${incdir}/granhydro/mesh/cartesian_patch.h")
endif()
if(SOURCE)
  file(GLOB_RECURSE internal RELATIVE "${SOURCE}/source" "${SOURCE}/source/*.h")
  foreach(h ${internal})
    if(EXISTS "${incdir}/granhydro/${h}")
      message(FATAL_ERROR "install_check: internal header installed: ${incdir}/granhydro/${h}")
    endif()
  endforeach()
endif()
file(GLOB_RECURSE headers "${incdir}/granhydro/*.h")
foreach(h ${headers})
  file(STRINGS "${h}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
  foreach(l ${lines})
    if(l MATCHES "include[ \t]*\"")
      message(FATAL_ERROR "install_check: ${h} includes a quoted (internal) header: ${l}")
    elseif(l MATCHES "<(granhydro/[^>]+)>" AND NOT EXISTS "${incdir}/${CMAKE_MATCH_1}")
      message(FATAL_ERROR "install_check: ${h} includes ${CMAKE_MATCH_1}, which is not installed")
    endif()
  endforeach()
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
