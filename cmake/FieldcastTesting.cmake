# fieldcast_add_test(NAME name SOURCES ... LIBRARIES ... LABELS ...)
# One GoogleTest executable, its cases discovered into CTest with the given labels
# (unit, golden, integration, interop, soak, hw, plus the module's name).
include(GoogleTest)

function(fieldcast_add_test)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBRARIES;LABELS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBRARIES} GTest::gtest GTest::gmock GTest::gtest_main
                        fieldcast::warnings fieldcast::sanitizers)
  target_compile_definitions(${ARG_NAME} PRIVATE FIELDCAST_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  gtest_discover_tests(${ARG_NAME}
    TEST_LIST ${ARG_NAME}_TESTS
    PROPERTIES SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]"
    DISCOVERY_TIMEOUT 60)
  # CMake 3.25 flattens list-valued PROPERTIES of gtest_discover_tests, so several labels cannot
  # be passed there. Set them in a script CTest includes after the discovered tests.
  set(_script "${CMAKE_CURRENT_BINARY_DIR}/${ARG_NAME}_labels.cmake")
  file(WRITE "${_script}"
    "foreach(_t IN LISTS ${ARG_NAME}_TESTS)\n"
    "  set_tests_properties(\"\${_t}\" PROPERTIES LABELS \"${ARG_LABELS}\")\n"
    "endforeach()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${_script}")
endfunction()

# fieldcast_add_command_test(NAME name COMMAND cmd args... LABELS label... [PASS_REGULAR_EXPRESSION re]
#                            [FAIL_REGULAR_EXPRESSION re] [TIMEOUT s])
# One CTest test that runs a command (an executable of the project, or a script that drives one)
# and passes on exit status 0 (and the regular expressions, when given); a script that cannot run
# here exits 77 and is reported skipped. The labels are those of fieldcast_add_test.
function(fieldcast_add_command_test)
  cmake_parse_arguments(ARG "" "NAME;PASS_REGULAR_EXPRESSION;FAIL_REGULAR_EXPRESSION;TIMEOUT" "COMMAND;LABELS" ${ARGN})
  if(NOT ARG_NAME OR NOT ARG_COMMAND OR NOT ARG_LABELS)
    message(FATAL_ERROR "fieldcast_add_command_test: NAME, COMMAND and LABELS are required")
  endif()
  add_test(NAME ${ARG_NAME} COMMAND ${ARG_COMMAND})
  set_tests_properties(${ARG_NAME} PROPERTIES LABELS "${ARG_LABELS}" SKIP_RETURN_CODE 77)
  foreach(_property PASS_REGULAR_EXPRESSION FAIL_REGULAR_EXPRESSION TIMEOUT)
    if(DEFINED ARG_${_property})
      set_tests_properties(${ARG_NAME} PROPERTIES ${_property} "${ARG_${_property}}")
    endif()
  endforeach()
endfunction()

# fieldcast_add_fuzzer(): libFuzzer targets and their `fuzz` tests.
include(FieldcastFuzzing)
