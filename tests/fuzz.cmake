# Scene-file fuzz corpus (tests/fuzz/README.md): >= 300 broken scenes, regenerated
# deterministically by tools/fuzz_scenes.py, that `granhydro --check` must refuse
# cleanly (exit 2, message naming the parameter or line, no crash, empty working dir).
# Included from tests/CMakeLists.txt.  Python 3 as for the DEM tools (no numpy needed);
# without it the test is still registered and fails with a message.
if(NOT GRANHYDRO_DEM_PYTHON)
  find_program(GRANHYDRO_DEM_PYTHON NAMES python3 HINTS /usr/bin)
endif()
if(GRANHYDRO_DEM_PYTHON)
  add_test(NAME input.fuzz_corpus
    COMMAND ${GRANHYDRO_DEM_PYTHON} ${CMAKE_CURRENT_LIST_DIR}/fuzz/fuzz_corpus.py
            --exe $<TARGET_FILE:granhydro> --jobs 2
            --workdir ${CMAKE_CURRENT_BINARY_DIR}/fuzz_corpus)
  set_tests_properties(input.fuzz_corpus PROPERTIES LABELS input TIMEOUT 900 PROCESSORS 2)
else()
  message(WARNING "python3 not found: test input.fuzz_corpus will fail until it is installed")
  add_test(NAME input.fuzz_corpus COMMAND ${CMAKE_COMMAND} -E echo "input.fuzz_corpus: python3 not found (apt-get install python3)")
  set_tests_properties(input.fuzz_corpus PROPERTIES LABELS input PASS_REGULAR_EXPRESSION "^$")
endif()
