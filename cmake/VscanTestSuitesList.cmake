# Run by VscanTestSuites.cmake after a test executable links (cmake -P): writes OUTPUT, one add_test
# per suite that `EXECUTABLE --gtest_list_tests` lists, run with --gtest_filter=Suite.* in
# WORKING_DIRECTORY under TIMEOUT seconds.
foreach(var EXECUTABLE OUTPUT WORKING_DIRECTORY TIMEOUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "VscanTestSuitesList.cmake: -D ${var}=... is required")
  endif()
endforeach()

execute_process(COMMAND ${EXECUTABLE} --gtest_list_tests
                WORKING_DIRECTORY ${WORKING_DIRECTORY}
                OUTPUT_VARIABLE listing ERROR_VARIABLE errors RESULT_VARIABLE status TIMEOUT 60)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE} --gtest_list_tests failed (${status}):\n${listing}${errors}")
endif()

# Suites start in the first column and end in '.', with "  # TypeParam = ..." after a typed one;
# their cases are indented. Other lines (gtest_main's greeting) are neither.
string(REPLACE "\n" ";" lines "${listing}")
set(script "")
set(count 0)
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ #][^ ]*)\\.( +#.*)?$")
    set(suite ${CMAKE_MATCH_1})
    if(suite MATCHES "^DISABLED_")
      continue()
    endif()
    string(APPEND script
      "add_test([==[${suite}]==] [==[${EXECUTABLE}]==] [==[--gtest_filter=${suite}.*]==])\n"
      "set_tests_properties([==[${suite}]==] PROPERTIES WORKING_DIRECTORY [==[${WORKING_DIRECTORY}]==]"
      " TIMEOUT ${TIMEOUT})\n")
    math(EXPR count "${count} + 1")
  endif()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE} --gtest_list_tests listed no test suite:\n${listing}")
endif()
file(WRITE ${OUTPUT} "${script}")
