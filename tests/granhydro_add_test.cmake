# granhydro_add_test: the one way a test is registered (tests/*/CMakeLists.txt).
#
#   granhydro_add_test(NAME <ctest name> LABELS <label...> TIMEOUT <seconds>
#                      EXE <target> [SOURCES <file...>] [PLAIN] [SCENES] | COMMAND <command...>
#                      [ARGS <argument...>] [RANKS <n>] [MPI] [PROCESSORS <n>]
#                      [ENVIRONMENT <VAR=value...>] [PROPERTIES <property value...>])
#
# EXE <target>: the test runs the executable target; if it does not exist yet it is built
#   from SOURCES (default <target>.cc of the calling folder), linked to granhydro_core, or
#   from the standard library only with PLAIN. Test executables are written to
#   build/tests/ whatever their folder (the documented study commands use that path).
#   SCENES: the source reads its scenes (.prm files beside it) from GRANHYDRO_TEST_DIR,
#   defined as the calling folder, and the shared ones of tests/data from
#   GRANHYDRO_TEST_DATA_DIR.
# COMMAND <command...>: a driver (bash script, cmake -P, python3) run as given.
# ARGS: the arguments after the executable or the command.
# RANKS <n>: the executable runs under ${DEAL_II_MPIEXEC} -n <n> (--oversubscribe above 2).
# MPI: the command starts mpiexec itself (a driver given DEAL_II_MPIEXEC).
# Without RANKS or MPI a test gets GRANHYDRO_SINGLETON_ENV (below); with them MPIEXEC_ENV
# (mpirun as root, oversubscription) and PROCESSORS min(<n>, 2) (2 cores reserved for a
# 2-rank run; more ranks oversubscribe); PROCESSORS <n> overrides that. ENVIRONMENT adds
# to the environment, PROPERTIES sets any
# further test property (PASS_REGULAR_EXPRESSION, SKIP_RETURN_CODE, ...).

set(MPIEXEC_ENV OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1)
# tests without mpiexec: granhydro started alone (an Open MPI singleton) does not start
# Open MPI's supporting daemon, which it would use only to spawn processes (granhydro never
# does); its start-up was about a quarter of the wall time of each of the suite's many
# short runs (--check, refused scenes; 0.25 of 1 s measured). Such singletons share one
# session directory, so each test gets its own (as tools/fuzz_scenes.py gives each case).
# Other MPI implementations ignore the variables.
set(GRANHYDRO_SINGLETON_ENV OMPI_MCA_ess_singleton_isolated=1)

function(granhydro_add_test)
  # PARSE_ARGV keeps a ';' inside one argument (a -D list for a cmake -P driver)
  cmake_parse_arguments(PARSE_ARGV 0 T "PLAIN;MPI;SCENES" "NAME;TIMEOUT;EXE;RANKS;PROCESSORS"
                        "LABELS;SOURCES;COMMAND;ARGS;ENVIRONMENT;PROPERTIES")
  if(T_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "granhydro_add_test(${T_NAME}): unknown arguments ${T_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT T_NAME OR NOT T_LABELS OR NOT T_TIMEOUT)
    message(FATAL_ERROR "granhydro_add_test(${T_NAME}): NAME, LABELS and TIMEOUT are required")
  endif()
  if((T_EXE AND T_COMMAND) OR (NOT T_EXE AND NOT T_COMMAND))
    message(FATAL_ERROR "granhydro_add_test(${T_NAME}): give either EXE or COMMAND")
  endif()
  if(T_EXE)
    if(NOT TARGET ${T_EXE})
      if(NOT T_SOURCES)
        set(T_SOURCES ${T_EXE}.cc)
      endif()
      add_executable(${T_EXE} ${T_SOURCES})
      set_target_properties(${T_EXE} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
      if(T_PLAIN)
        target_include_directories(${T_EXE} PRIVATE ${PROJECT_SOURCE_DIR}/include ${GRANHYDRO_TESTS_DIR})
      else()
        target_link_libraries(${T_EXE} granhydro_core)
        target_include_directories(${T_EXE} PRIVATE ${GRANHYDRO_TESTS_DIR})
        deal_ii_setup_target(${T_EXE})
      endif()
      if(T_SCENES)
        target_compile_definitions(${T_EXE} PRIVATE GRANHYDRO_TEST_DIR="${CMAKE_CURRENT_SOURCE_DIR}"
                                                      GRANHYDRO_TEST_DATA_DIR="${GRANHYDRO_TEST_DATA}")
      endif()
    endif()
    set(command "$<TARGET_FILE:${T_EXE}>")
  else()
    set(command "${T_COMMAND}") # quoted: an escaped ';' stays inside its argument
  endif()
  set(environment ${T_ENVIRONMENT})
  if(NOT T_RANKS AND NOT T_MPI)
    list(PREPEND environment ${GRANHYDRO_SINGLETON_ENV}
         OMPI_MCA_orte_tmpdir_base=${CMAKE_CURRENT_BINARY_DIR}/ompi_session/${T_NAME})
  endif()
  set(processors 1)
  if(T_RANKS)
    set(launcher ${DEAL_II_MPIEXEC} -n ${T_RANKS})
    if(T_RANKS GREATER 2)
      list(APPEND launcher --oversubscribe)
    endif()
    list(PREPEND command ${launcher})
    set(processors ${T_RANKS})
  endif()
  if(T_RANKS OR T_MPI)
    set(environment ${MPIEXEC_ENV} ${environment})
    if(processors GREATER 2)
      set(processors 2)
    endif()
    if(T_MPI)
      set(processors 2)
    endif()
  endif()
  if(T_PROCESSORS)
    set(processors ${T_PROCESSORS})
  endif()
  add_test(NAME ${T_NAME} COMMAND ${command} ${T_ARGS})
  set_tests_properties(${T_NAME} PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT})
  if(processors GREATER 1)
    set_tests_properties(${T_NAME} PROPERTIES PROCESSORS ${processors})
  endif()
  if(environment)
    set_tests_properties(${T_NAME} PROPERTIES ENVIRONMENT "${environment}")
  endif()
  if(T_PROPERTIES)
    set_tests_properties(${T_NAME} PROPERTIES ${T_PROPERTIES})
  endif()
endfunction()

# granhydro_missing_test(NAME WHAT [LABELS...]): a test whose dependency is missing stays
# registered and fails with a message naming what to install (labels default to dem)
function(granhydro_missing_test name what)
  set(labels dem)
  if(ARGN)
    set(labels ${ARGN})
  endif()
  message(WARNING "${what} not found: test ${name} will fail until it is installed")
  add_test(NAME ${name} COMMAND ${CMAKE_COMMAND} -E echo "${name}: ${what} not found (apt-get install it, see README)")
  set_tests_properties(${name} PROPERTIES LABELS "${labels}" WILL_FAIL FALSE PASS_REGULAR_EXPRESSION "^$")
endfunction()
