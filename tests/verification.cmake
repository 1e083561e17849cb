# verification, stability and MPI tests (C++ executables linked to the core)
granhydro_test_executable(test_riemann test_riemann.cc)
add_test(NAME verify.riemann COMMAND test_riemann)
set_tests_properties(verify.riemann PROPERTIES LABELS verify TIMEOUT 600)
