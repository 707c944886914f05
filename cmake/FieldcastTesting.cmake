# fieldcast_add_test(NAME name SOURCES ... LIBRARIES ... LABELS ...)
# One GoogleTest executable, its cases discovered into CTest with the given labels
# (unit, golden, integration, interop, soak, hw) and the module's name.
include(GoogleTest)

function(fieldcast_add_test)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBRARIES;LABELS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBRARIES} GTest::gtest GTest::gmock GTest::gtest_main
                        fieldcast::warnings fieldcast::sanitizers)
  target_compile_definitions(${ARG_NAME} PRIVATE FIELDCAST_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  gtest_discover_tests(${ARG_NAME}
    PROPERTIES LABELS "${ARG_LABELS}" SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]"
    DISCOVERY_TIMEOUT 60)
endfunction()
