# doc/parameters.md is `granhydro --print-parameters` rendered as Markdown (a header, then
# the printed default scene in a text block). The ctest doc.parameters_md fails when the
# committed file differs from what the current granhydro prints.
#
#   cmake -DREGENERATE=1 -P tests/doc/parameters_md.cmake        regenerate doc/parameters.md
#   cmake -P tests/doc/parameters_md.cmake                       check it
#
# Options: -DEXE=<granhydro> (default: build/granhydro of this tree), -DDOC=<file> (default:
# doc/parameters.md), -DOUT=<file>: where a check writes the expected text (default:
# parameters.md.expected in the working directory).

get_filename_component(tree "${CMAKE_CURRENT_LIST_DIR}/../.." ABSOLUTE)
if(NOT EXE)
  set(EXE "${tree}/build/granhydro")
endif()
if(NOT DOC)
  set(DOC "${tree}/doc/parameters.md")
endif()
if(NOT OUT)
  set(OUT "${CMAKE_CURRENT_BINARY_DIR}/parameters.md.expected")
endif()
if(NOT EXISTS "${EXE}")
  message(FATAL_ERROR "parameters_md: no granhydro at '${EXE}' (build it, or give -DEXE=...)")
endif()

execute_process(COMMAND "${EXE}" --print-parameters RESULT_VARIABLE rc
                OUTPUT_VARIABLE printed ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR printed STREQUAL "")
  message(FATAL_ERROR "'${EXE} --print-parameters' exited with '${rc}':\n${err}")
endif()
# deal.II ends an empty value with a blank ("set Mesh file = "): no trailing blanks in the page
string(REGEX REPLACE "[ \t]+\n" "\n" printed "${printed}")
string(REGEX REPLACE "\n+$" "\n" printed "${printed}")

set(text [=[# Scene parameters

Every parameter of a granhydro scene with its documentation, in the order the code
declares them, as `granhydro --print-parameters` prints them: the embedded default
scene (a 2D cylindrical blast; [user guide](user-guide.md#running-scenes)). Where
the default scene sets a value other than the parameter's own default, the line ends
with `# default: <value>`. A scene file sets only what it changes
([Scene files](user-guide.md#scene-files)); `granhydro --print-parameters scene.prm`
prints a scene the same way, expanded (includes and `-p` overrides applied), and every
run records its scene so in `<Base name>_parameters.prm` ([Output](user-guide.md#output)).

This page is generated: do not edit it. After changing a parameter or its documentation,
build `granhydro` and run `cmake -DREGENERATE=1 -P tests/doc/parameters_md.cmake` (ctest
`doc.parameters_md` fails while the page is out of date).

Subsections, in this order: @SUBSECTIONS@.

```text
]=])
# the top-level subsections (two-space indented ones are nested)
string(REGEX MATCHALL "\nsubsection [^\n]+" subsections "${printed}")
string(REGEX REPLACE "\nsubsection ([^;]+)" "`\\1`" subsections "${subsections}")
string(REPLACE ";" ", " subsections "${subsections}")
string(REPLACE "@SUBSECTIONS@" "${subsections}" text "${text}")
string(APPEND text "${printed}```\n")

if(REGENERATE)
  file(WRITE "${DOC}" "${text}")
  message(STATUS "wrote ${DOC}")
  return()
endif()
set(committed "")
if(EXISTS "${DOC}")
  file(READ "${DOC}" committed)
endif()
if(NOT committed STREQUAL text)
  file(WRITE "${OUT}" "${text}")
  message(FATAL_ERROR "${DOC} is out of date: it is not what '${EXE} --print-parameters' prints "
                      "(expected text in ${OUT}; diff -u ${DOC} ${OUT}). Regenerate it with\n"
                      "  cmake -DEXE=${EXE} -DREGENERATE=1 -P ${CMAKE_CURRENT_LIST_FILE}")
endif()
message(STATUS "${DOC} is up to date")
