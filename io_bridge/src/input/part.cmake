# io_bridge part "input": control sticks and cockpit USB devices — evdev (libevdev), hidraw and raw
# USB HID (libusb) through our own HID report-descriptor parser, stick profiles, the lock-free
# ControlState hand-off, device-loss handling, and record/replay of any source.
set(_input "${CMAKE_CURRENT_LIST_DIR}")
target_sources(fieldcast_io PRIVATE
  ${_input}/InputEvent.cpp
  ${_input}/HidReportDescriptor.cpp
  ${_input}/HidReportDecoder.cpp
  ${_input}/EvdevDecoder.cpp
  ${_input}/EvdevSource.cpp
  ${_input}/StickProfile.cpp
  ${_input}/StickMapper.cpp
  ${_input}/InputRecording.cpp
  ${_input}/StickInput.cpp
  ${_input}/HidrawSource.cpp
  ${_input}/UsbHidSource.cpp
  ${_input}/LibusbTransport.cpp
  ${_input}/UsbHotplug.cpp
  ${_input}/InputSources.cpp
  ${_input}/InputConfig.cpp)
target_link_libraries(fieldcast_io PRIVATE PkgConfig::libevdev PkgConfig::libusb spdlog::spdlog)

if(FIELDCAST_BUILD_TESTS)
  set(_input_tests "${CMAKE_CURRENT_LIST_DIR}/../../tests/input")
  fieldcast_add_test(NAME fieldcast_io_input_tests
    SOURCES ${_input_tests}/HidDescriptorTest.cpp ${_input_tests}/EvdevDecoderTest.cpp
            ${_input_tests}/StickMappingTest.cpp ${_input_tests}/StickInputTest.cpp ${_input_tests}/DeviceSourceTest.cpp
    LIBRARIES fieldcast::io fieldcast::motion
    LABELS "unit;io;input")
  fieldcast_add_test(NAME fieldcast_io_input_hw_tests
    SOURCES ${_input_tests}/HardwareTest.cpp
    LIBRARIES fieldcast::io
    LABELS "hw;io;input")
endif()

# libFuzzer targets for the HID parser and the recording reader (fieldcast_add_fuzzer,
# cmake/FieldcastFuzzing.cmake): `ctest -L fuzz` runs each for 15 s, or reports it skipped with the
# reason when it was not built.
if(FIELDCAST_BUILD_TESTS)
  set(_input_fuzz_includes ${PROJECT_SOURCE_DIR}/io_bridge/include ${PROJECT_SOURCE_DIR}/types/include)
  set(_input_fuzz_args -runs=500000 -max_total_time=15 -seed=1 -max_len=2048)
  fieldcast_add_fuzzer(NAME hid_descriptor_fuzzer MODULE io LABELS input
    SOURCES ${_input}/InputEvent.cpp ${_input}/HidReportDescriptor.cpp ${_input}/HidReportDecoder.cpp
            ${_input_tests}/HidDescriptorFuzz.cpp
    INCLUDES ${_input_fuzz_includes}
    ARGS ${_input_fuzz_args})
  fieldcast_add_fuzzer(NAME input_recording_fuzzer MODULE io LABELS input
    SOURCES ${_input}/InputEvent.cpp ${_input}/InputRecording.cpp ${PROJECT_SOURCE_DIR}/types/src/Time.cpp
            ${_input_tests}/InputRecordingFuzz.cpp
    INCLUDES ${_input_fuzz_includes}
    ARGS ${_input_fuzz_args})
endif()
