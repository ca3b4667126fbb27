# Run with cmake -P after each build of a test executable (tests/CMakeLists.txt): writes CTEST_FILE,
# which adds every test of TEST_EXECUTABLE to CTest under its full GoogleTest name, as
# --gtest_list_tests prints it, without the trailing "# TypeParam = ..." / "# GetParam() = ..."
# comments. Those comments are for reading only: they spell out whole types and byte dumps.
#
# Inputs: TEST_EXECUTABLE, CTEST_FILE, WORKING_DIR, DISCOVERY_TIMEOUT (seconds), LABELS, TIMEOUT.
cmake_minimum_required(VERSION 3.25)

execute_process(
  COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
  WORKING_DIRECTORY "${WORKING_DIR}"
  TIMEOUT ${DISCOVERY_TIMEOUT}
  OUTPUT_VARIABLE listing
  ERROR_VARIABLE listing_err
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed (${result}):\n${listing}${listing_err}")
endif()

# Comments go first: they are the only part of the listing that may hold ';', '[' or ']', which
# would otherwise split or garble the CMake list of lines below.
string(REGEX REPLACE " *#[^\n]*" "" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")

set(script "")
set(suite "")
set(count 0)
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ ].*)\\.$")
    # "Suite." or "Prefix/Suite." or "Suite/type." starts the tests of one suite.
    set(suite "${CMAKE_MATCH_1}")
  elseif(line MATCHES "^  +([^ ].*)$" AND NOT suite STREQUAL "")
    set(name "${suite}.${CMAKE_MATCH_1}")
    string(APPEND script
      "add_test([==[${name}]==] [==[${TEST_EXECUTABLE}]==] [==[--gtest_filter=${name}]==]"
      " --gtest_also_run_disabled_tests)\n"
      "set_tests_properties([==[${name}]==] PROPERTIES WORKING_DIRECTORY [==[${WORKING_DIR}]==]"
      " SKIP_REGULAR_EXPRESSION [==[\\[  SKIPPED \\]]==] LABELS [==[${LABELS}]==] TIMEOUT ${TIMEOUT})\n")
    # A GoogleTest DISABLED_ test or suite stays listed, and CTest reports it as disabled.
    if(name MATCHES "(^|[/.])DISABLED_")
      string(APPEND script "set_tests_properties([==[${name}]==] PROPERTIES DISABLED TRUE)\n")
    endif()
    math(EXPR count "${count} + 1")
  endif()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests listed no tests:\n${listing}")
endif()

file(WRITE "${CTEST_FILE}" "${script}")
