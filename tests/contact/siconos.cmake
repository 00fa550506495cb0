# Siconos numerics (Debian's libsiconos-numerics-dev), the test-only oracle of the contact
# solvers: tests/contact and bench/contact only, never plantar_contact. tools/bootstrap installs
# it; configure fails when it is missing rather than skipping the tests that need it.
include_guard(GLOBAL)
find_path(SICONOS_NUMERICS_INCLUDE_DIR NAMES numerics/FrictionContactProblem.h
          PATH_SUFFIXES siconos)
find_library(SICONOS_NUMERICS_LIBRARY NAMES siconos_numerics)
if(NOT SICONOS_NUMERICS_INCLUDE_DIR OR NOT SICONOS_NUMERICS_LIBRARY)
  message(FATAL_ERROR
    "Siconos numerics not found (header numerics/FrictionContactProblem.h: "
    "'${SICONOS_NUMERICS_INCLUDE_DIR}', library siconos_numerics: '${SICONOS_NUMERICS_LIBRARY}'). "
    "The contact tests and bench/contact use it as their oracle: install Debian's "
    "libsiconos-numerics-dev (tools/bootstrap does), or configure with "
    "-DPLANTAR_BUILD_TESTS=OFF -DPLANTAR_BUILD_BENCH=OFF.")
endif()
add_library(plantar_siconos_numerics INTERFACE IMPORTED GLOBAL)
target_include_directories(plantar_siconos_numerics INTERFACE
  ${SICONOS_NUMERICS_INCLUDE_DIR} ${SICONOS_NUMERICS_INCLUDE_DIR}/numerics)
target_link_libraries(plantar_siconos_numerics INTERFACE ${SICONOS_NUMERICS_LIBRARY})
