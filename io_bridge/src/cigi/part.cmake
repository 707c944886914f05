# io_bridge part "cigi": the CIGI 3.3 wire codec (SISO-STD-013) — packet structs, encode/decode
# in either byte order, whole-datagram decoding with counted rejections, message builders.
# No sockets and no service wiring here (see src/cigi/README.md).
set(_cigi "${CMAKE_CURRENT_LIST_DIR}")
target_sources(fieldcast_io PRIVATE
  ${_cigi}/Codec.cpp
  ${_cigi}/DatagramDecoder.cpp)

if(FIELDCAST_BUILD_TESTS)
  set(_cigi_tests "${CMAKE_CURRENT_LIST_DIR}/../../tests/cigi")
  fieldcast_add_test(NAME fieldcast_io_cigi_tests
    SOURCES ${_cigi_tests}/CodecTest.cpp ${_cigi_tests}/DatagramDecoderTest.cpp ${_cigi_tests}/MessageBuilderTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io;cigi")
  target_include_directories(fieldcast_io_cigi_tests PRIVATE ${_cigi_tests})

  # Third-party judge: tshark's CIGI dissector reads a capture of both directions in both byte
  # orders (the capture writer is ours; the script compares tshark's field values with the sent ones).
  add_executable(fieldcast_cigi_capture ${_cigi_tests}/CigiCaptureWriter.cpp)
  target_include_directories(fieldcast_cigi_capture PRIVATE ${_cigi_tests})
  target_link_libraries(fieldcast_cigi_capture PRIVATE fieldcast::io fieldcast::warnings)
  fieldcast_add_command_test(NAME io_cigi_tshark_interop
    COMMAND ${_cigi_tests}/cigi_tshark_check.sh $<TARGET_FILE:fieldcast_cigi_capture>
            ${CMAKE_CURRENT_BINARY_DIR}/cigi_interop
    LABELS interop io cigi TIMEOUT 120)
endif()

# libFuzzer target for the datagram decoders (fieldcast_add_fuzzer, cmake/FieldcastFuzzing.cmake):
# `ctest -L fuzz` runs it for 20 s from seeds it writes itself, or reports it skipped with the reason.
if(FIELDCAST_BUILD_TESTS)
  fieldcast_add_fuzzer(NAME cigi_datagram_fuzzer MODULE io LABELS cigi
    SOURCES ${_cigi}/Codec.cpp ${_cigi}/DatagramDecoder.cpp ${_cigi_tests}/CigiDatagramFuzz.cpp
    INCLUDES ${PROJECT_SOURCE_DIR}/io_bridge/include ${PROJECT_SOURCE_DIR}/io_bridge/tests/input
    ARGS -max_total_time=20 -seed=1 -max_len=4096 -rss_limit_mb=1024)
endif()
