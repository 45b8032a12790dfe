# Test discovery for inkwell_tests (run at build time, after it links), in place of doctest's
# doctestAddTests.cmake: one CTest test per doctest test case, labelled with its doctest test suite, one of
# unit, gpu, cli, viewer, golden (docs/contributing.md). A test case without a label fails the build. Unlike
# doctest's script it keeps test names whole that hold a ';' (that script split them into tests that matched
# nothing and passed). Called with -D TEST_EXECUTABLE, TEST_WORKING_DIR, TEST_PROPERTIES, CTEST_FILE.
cmake_minimum_required(VERSION 3.25)  # IN_LIST

# The test cases of the executable (of one suite with `suite`), their ';' as <semicolon>.
function(list_cases out suite)
  set(args --list-test-cases)
  if(suite)
    list(APPEND args --test-suite=${suite})
  endif()
  execute_process(
    COMMAND "${TEST_EXECUTABLE}" ${args}
    OUTPUT_VARIABLE output
    RESULT_VARIABLE result
    WORKING_DIRECTORY "${TEST_WORKING_DIR}")
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "listing the test cases of ${TEST_EXECUTABLE} failed (${result}):\n${output}")
  endif()
  string(REPLACE ";" "<semicolon>" output "${output}")
  string(REPLACE "\n" ";" output "${output}")
  set(cases)
  foreach(line ${output})
    if(line STREQUAL "" OR line MATCHES "^=+$" OR line MATCHES [==[^\[doctest\] ]==])
      continue()
    endif()
    list(APPEND cases "${line}")
  endforeach()
  set(${out} "${cases}" PARENT_SCOPE)
endfunction()

list_cases(all "")
set(labels unit gpu cli viewer golden)
foreach(label ${labels})
  list_cases(cases_${label} ${label})
endforeach()

set(script "")
set(unlabelled)
foreach(test ${all})
  set(label "")
  foreach(l ${labels})
    if(test IN_LIST cases_${l})
      set(label ${l})
    endif()
  endforeach()
  if(NOT label)
    list(APPEND unlabelled "${test}")
    continue()
  endif()
  string(REPLACE "<semicolon>" ";" name "${test}")
  # doctest's filter: ',' separates patterns (escaped), '?' matches the ';'.
  string(REPLACE "," "\\," filter "${test}")
  string(REPLACE "<semicolon>" "?" filter "${filter}")
  string(APPEND script "add_test([==[${name}]==] \"${TEST_EXECUTABLE}\" [==[--test-case=${filter}]==])\n")
  string(APPEND script "set_tests_properties([==[${name}]==] PROPERTIES WORKING_DIRECTORY \"${TEST_WORKING_DIR}\" "
                       "LABELS ${label} ${TEST_PROPERTIES})\n")
endforeach()
if(unlabelled)
  file(REMOVE "${CTEST_FILE}")
  string(REPLACE ";" "\n  " names "${unlabelled}")
  message(FATAL_ERROR "test cases without a label: add * doctest::test_suite(\"unit\") (or gpu, cli, viewer, "
                      "golden) to each of\n  ${names}")
endif()
file(WRITE "${CTEST_FILE}" "${script}")
