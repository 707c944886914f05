# io_bridge part "sinks": the field outputs (Y4M, RFC 4175 RTP, image files, live window,
# shared-memory ring, GPIO field pulse) behind one FieldSink interface, fed by the SinkHub.
target_sources(fieldcast_io PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/StreamFormat.cpp
  ${CMAKE_CURRENT_LIST_DIR}/SinkHub.cpp
  ${CMAKE_CURRENT_LIST_DIR}/PixelConvert.cpp
  ${CMAKE_CURRENT_LIST_DIR}/FileOutput.cpp
  ${CMAKE_CURRENT_LIST_DIR}/Y4mSink.cpp
  ${CMAKE_CURRENT_LIST_DIR}/Rfc4175Packetizer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/RtpVideoSink.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ShmRing.cpp
  ${CMAKE_CURRENT_LIST_DIR}/GpioPulseSink.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ImageWrite.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ImageFileSink.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ContactSheetSink.cpp
  ${CMAKE_CURRENT_LIST_DIR}/SinksConfig.cpp
  ${CMAKE_CURRENT_LIST_DIR}/WindowSink.cpp)
target_link_libraries(fieldcast_io PRIVATE spdlog::spdlog PkgConfig::libgpiod OpenImageIO::OpenImageIO
                      opencv_core opencv_imgproc opencv_highgui)

if(FIELDCAST_BUILD_TESTS)
  set(_sink_tests "${PROJECT_SOURCE_DIR}/io_bridge/tests/sinks")
  fieldcast_add_test(NAME fieldcast_io_sinks_tests
    SOURCES ${_sink_tests}/SinkHubTest.cpp ${_sink_tests}/Y4mSinkTest.cpp ${_sink_tests}/PixelConvertTest.cpp
            ${_sink_tests}/Rfc4175PacketizerTest.cpp ${_sink_tests}/RtpVideoSinkTest.cpp ${_sink_tests}/ShmRingTest.cpp
            ${_sink_tests}/GpioPulseSinkTest.cpp ${_sink_tests}/ImageFileSinkTest.cpp
            ${_sink_tests}/ContactSheetSinkTest.cpp ${_sink_tests}/SinksConfigTest.cpp ${_sink_tests}/FileOutputTest.cpp
    LIBRARIES fieldcast::io OpenImageIO::OpenImageIO
    LABELS "unit;io")
  target_include_directories(fieldcast_io_sinks_tests PRIVATE ${CMAKE_CURRENT_LIST_DIR})
endif()

if(FIELDCAST_BUILD_TESTS)
  # Third-party judges: ffprobe/ffmpeg read our Y4M, GStreamer receives our RTP.
  fieldcast_add_test(NAME fieldcast_io_sinks_interop_tests
    SOURCES ${_sink_tests}/SinksInteropTest.cpp
    LIBRARIES fieldcast::io
    LABELS "interop;io")
  # The live window: the no-display behaviour everywhere, the window itself under a display.
  fieldcast_add_test(NAME fieldcast_io_window_tests
    SOURCES ${_sink_tests}/WindowSinkTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io")
  find_program(FIELDCAST_XVFB_RUN xvfb-run DOC "xvfb-run, to test the live window on a virtual display")
  if(FIELDCAST_XVFB_RUN)
    # One process per case: the GUI belongs to one thread per process (see WindowSink.h).
    foreach(_case ShowsInterlacedFieldsWithOverlay RunsOnAHubWorker)
      fieldcast_add_command_test(NAME io_sinks_window_xvfb_${_case}
        COMMAND ${FIELDCAST_XVFB_RUN} -a $<TARGET_FILE:fieldcast_io_window_tests> --gtest_filter=WindowSinkDisplay.${_case}
        LABELS integration io TIMEOUT 60 FAIL_REGULAR_EXPRESSION "\\[  SKIPPED \\]")
    endforeach()
  endif()
  # Real GPIO hardware; skipped with the reason where there is none.
  fieldcast_add_test(NAME fieldcast_io_sinks_hw_tests
    SOURCES ${_sink_tests}/GpioPulseHwTest.cpp
    LIBRARIES fieldcast::io PkgConfig::libgpiod  # it reads the pulsed line back through libgpiod itself
    LABELS "hw;io")
endif()

# libFuzzer target for the shm ring header a reader validates (fieldcast_add_fuzzer,
# cmake/FieldcastFuzzing.cmake): `ctest -L fuzz` runs it for 20 s from the seed (a valid ring), or
# reports it skipped with the reason when it was not built.
if(FIELDCAST_BUILD_TESTS)
  fieldcast_add_fuzzer(NAME shm_ring_header_fuzzer MODULE io
    SOURCES ${PROJECT_SOURCE_DIR}/io_bridge/tests/sinks/fuzz/ShmRingHeaderFuzz.cpp ${CMAKE_CURRENT_LIST_DIR}/ShmRing.cpp
            ${CMAKE_CURRENT_LIST_DIR}/StreamFormat.cpp ${PROJECT_SOURCE_DIR}/types/src/Time.cpp
    INCLUDES ${PROJECT_SOURCE_DIR}/io_bridge/include ${PROJECT_SOURCE_DIR}/types/include
    SEEDS ${PROJECT_SOURCE_DIR}/io_bridge/tests/sinks/fuzz/seeds
    ARGS -max_total_time=20 -rss_limit_mb=1024)
endif()
