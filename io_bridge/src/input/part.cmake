# io_bridge part "input": control sticks and cockpit USB devices — evdev (libevdev), hidraw and raw
# USB HID (libusb) through our own HID report-descriptor parser, stick profiles, the lock-free
# ControlState hand-off, device-loss handling, and record/replay of any source.
set(_input "${CMAKE_CURRENT_LIST_DIR}")
target_sources(fieldcast_io PRIVATE
  ${_input}/InputEvent.cpp
  ${_input}/HidReportDescriptor.cpp
  ${_input}/HidReportDecoder.cpp)
target_link_libraries(fieldcast_io PRIVATE PkgConfig::libevdev PkgConfig::libusb tomlplusplus::tomlplusplus
                      spdlog::spdlog)

if(FIELDCAST_BUILD_TESTS)
  set(_input_tests "${CMAKE_CURRENT_LIST_DIR}/../../tests/input")
  fieldcast_add_test(NAME fieldcast_io_input_tests
    SOURCES ${_input_tests}/HidDescriptorTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io;input")
endif()
