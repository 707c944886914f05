# io_bridge part "capture": a classic pcap writer for UDP datagrams (PcapWriter), so a person can
# open in Wireshark what a link sent and received (fieldcast-host --pcap; the CIGI tshark test).
target_sources(fieldcast_io PRIVATE ${CMAKE_CURRENT_LIST_DIR}/PcapWriter.cpp)

if(FIELDCAST_BUILD_TESTS)
  fieldcast_add_test(NAME fieldcast_io_capture_tests
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/../../tests/capture/PcapWriterTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io")
endif()
