# vscan_add_test_suites(target [TIMEOUT seconds]): registers a GoogleTest executable with CTest as one
# test per test suite (`ctest -R Suite` runs it, `--gtest_filter=Suite.Case` one case of it).
# A process per suite rather than per case: each case in its own process paid the executable's
# start-up (the dynamic loader binding some hundred shared libraries) and its fixtures' setup again:
# 28 s more of the unit tests' CPU (docs/BENCHMARKS.md, "Build"). A suite counts as passed when its
# process exits 0; cases it skips show in its output.
# The suites are listed after each link, as gtest_discover_tests lists the cases.
set(VSCAN_TEST_SUITES_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/VscanTestSuitesList.cmake)

function(vscan_add_test_suites target)
  cmake_parse_arguments(ARG "" "TIMEOUT" "" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  set(listed ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake)
  set(include_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites_include.cmake)
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -D EXECUTABLE=$<TARGET_FILE:${target}> -D OUTPUT=${listed}
            -D WORKING_DIRECTORY=${CMAKE_CURRENT_BINARY_DIR} -D TIMEOUT=${ARG_TIMEOUT}
            -P ${VSCAN_TEST_SUITES_SCRIPT}
    BYPRODUCTS ${listed}
    VERBATIM)
  # An executable not built yet shows as one failing test rather than as no tests.
  file(WRITE ${include_file}
       "if(EXISTS [==[${listed}]==])\n"
       "  include([==[${listed}]==])\n"
       "else()\n"
       "  add_test([==[${target}_NOT_BUILT]==] [==[${target}_NOT_BUILT]==])\n"
       "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${include_file})
endfunction()
