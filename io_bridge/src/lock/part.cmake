# io_bridge part "lock": the software frame lock between channels — the announcement of a
# channel's field epoch, its wire format, and the UDP thread that sends and hears them
# (FieldLockLink). What the service does with the earliest epoch heard is the app's.
set(_lock "${CMAKE_CURRENT_LIST_DIR}")
target_sources(fieldcast_io PRIVATE ${_lock}/FieldLockLink.cpp)
target_link_libraries(fieldcast_io PRIVATE spdlog::spdlog)

if(FIELDCAST_BUILD_TESTS)
  set(_lock_tests "${CMAKE_CURRENT_LIST_DIR}/../../tests/lock")
  fieldcast_add_test(NAME fieldcast_io_lock_tests
    SOURCES ${_lock_tests}/FieldLockLinkTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io")
endif()
