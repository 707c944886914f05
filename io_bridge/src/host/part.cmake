# io_bridge part "host": the IG's end of the CIGI link — the UDP socket and the thread that
# receives and decodes the host's datagrams and sends one Start of Frame per field (HostLink).
# What the packets mean to the service is the app's (app/src/HostSession.*).
set(_host "${CMAKE_CURRENT_LIST_DIR}")
target_sources(fieldcast_io PRIVATE ${_host}/HostLink.cpp)
target_link_libraries(fieldcast_io PRIVATE spdlog::spdlog)

if(FIELDCAST_BUILD_TESTS)
  set(_host_tests "${CMAKE_CURRENT_LIST_DIR}/../../tests/host")
  fieldcast_add_test(NAME fieldcast_io_host_tests
    SOURCES ${_host_tests}/HostLinkTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io;cigi")
endif()
