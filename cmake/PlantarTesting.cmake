# plantar_add_test(NAME name SOURCES a.cc ... LIBS lib ... LABELS unit|validation|slow ... [ARGS ...] [TIMEOUT s])
# One GoogleTest executable registered as one ctest test with labels.
include_guard(GLOBAL)
find_package(GTest REQUIRED)

# In a sanitizer tree (PLANTAR_SANITIZE) a test program's own sources are compiled with
# AddressSanitizer but without UBSan's checks, which double their compile time (a contact test:
# 49.6 s with both, 31.1 s with ASan alone, 23.6 s with neither); the libraries they test keep
# both (docs/reliability.md).
function(plantar_test_sanitizer_options target)
  if(PLANTAR_SANITIZE)
    target_compile_options(${target} PRIVATE -fno-sanitize=undefined)
  endif()
endfunction()

# With LONG_CASES filter (a GoogleTest filter), the cases it matches are registered apart as
# `name.long` and `name` runs the others, so that the sanitizer tree can leave out the long
# ones (tools/sanitizers/skipped_tests.txt) and still run the rest.
function(plantar_add_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT;LONG_CASES" "SOURCES;LIBS;LABELS;ARGS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main plantar_warnings)
  target_compile_definitions(${T_NAME} PRIVATE PLANTAR_SOURCE_DIR="${PLANTAR_SOURCE_DIR}")
  plantar_test_sanitizer_options(${T_NAME})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 600)
  endif()
  if(T_LONG_CASES)
    if(T_ARGS)
      message(FATAL_ERROR "plantar_add_test(${T_NAME}): LONG_CASES and ARGS together")
    endif()
    plantar_add_test_case(NAME ${T_NAME} EXE ${T_NAME} FILTER "-${T_LONG_CASES}"
                          LABELS ${T_LABELS} TIMEOUT ${T_TIMEOUT})
    plantar_add_test_case(NAME ${T_NAME}.long EXE ${T_NAME} FILTER "${T_LONG_CASES}"
                          LABELS ${T_LABELS} TIMEOUT ${T_TIMEOUT})
    return()
  endif()
  add_test(NAME ${T_NAME} COMMAND ${T_NAME} ${T_ARGS} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  set_tests_properties(${T_NAME} PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT})
endfunction()

# plantar_add_test_case(NAME name EXE executable FILTER gtest_filter LABELS ... [TIMEOUT s])
# Registers one more ctest test running a subset of an existing GoogleTest executable.
function(plantar_add_test_case)
  cmake_parse_arguments(T "" "NAME;EXE;FILTER;TIMEOUT" "LABELS" ${ARGN})
  add_test(NAME ${T_NAME} COMMAND ${T_EXE} --gtest_filter=${T_FILTER}
           WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 600)
  endif()
  set_tests_properties(${T_NAME} PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT})
endfunction()

# plantar_add_test_executable(NAME exe SOURCES ... LIBS ...): a GoogleTest
# executable whose suites are registered with plantar_add_test_case.
function(plantar_add_test_executable)
  cmake_parse_arguments(T "" "NAME" "SOURCES;LIBS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main plantar_warnings)
  target_compile_definitions(${T_NAME} PRIVATE PLANTAR_SOURCE_DIR="${PLANTAR_SOURCE_DIR}")
  plantar_test_sanitizer_options(${T_NAME})
endfunction()

# plantar_sanitize_mpi_test(test): in a sanitizer tree (PLANTAR_SANITIZE), a test whose processes
# initialise MPI unwinds allocation stacks through DWARF information: Open MPI and PETSc are
# built without frame pointers, so the fast unwinder loses their frames and LeakSanitizer could
# not match their start-up allocations to tools/sanitizers/lsan.supp.
function(plantar_sanitize_mpi_test name)
  if(PLANTAR_SANITIZE)
    set_tests_properties(${name} PROPERTIES ENVIRONMENT_MODIFICATION
                         "ASAN_OPTIONS=string_append::fast_unwind_on_malloc=0")
  endif()
endfunction()
