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
  ${_input}/InputSources.cpp)
target_link_libraries(fieldcast_io PRIVATE PkgConfig::libevdev PkgConfig::libusb tomlplusplus::tomlplusplus
                      spdlog::spdlog)

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

# libFuzzer target for the HID parser: built with the project compiler when that is clang, or with
# clang++-14 beside a gcc build when FIELDCAST_FUZZ=ON. The `fuzz` test runs it briefly and is
# skipped (with the reason) when it was not built.
option(FIELDCAST_FUZZ "Build the libFuzzer targets (needs clang++; with gcc, clang++-14 builds them)" OFF)
if(FIELDCAST_BUILD_TESTS)
  set(_fuzz_sources ${_input}/InputEvent.cpp ${_input}/HidReportDescriptor.cpp ${_input}/HidReportDecoder.cpp
                    ${_input_tests}/HidDescriptorFuzz.cpp)
  set(_fuzz_bin "${CMAKE_CURRENT_BINARY_DIR}/fuzz/hid_descriptor_fuzzer")
  set(_fuzz_reason "")
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    add_executable(fieldcast_fuzz_hid_descriptor ${_fuzz_sources})
    target_include_directories(fieldcast_fuzz_hid_descriptor PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_compile_options(fieldcast_fuzz_hid_descriptor PRIVATE -fsanitize=fuzzer,address,undefined -g)
    target_link_options(fieldcast_fuzz_hid_descriptor PRIVATE -fsanitize=fuzzer,address,undefined)
    set_target_properties(fieldcast_fuzz_hid_descriptor PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/fuzz
                                                             OUTPUT_NAME hid_descriptor_fuzzer)
  else()
    find_program(FIELDCAST_CLANGXX NAMES clang++-14 clang++ DOC "clang++ for the libFuzzer targets")
    if(NOT FIELDCAST_CLANGXX)
      set(_fuzz_reason "clang++ not found (install clang-14 libclang-rt-14-dev: scripts/install-deps.sh --interop)")
    elseif(NOT FIELDCAST_FUZZ)
      set(_fuzz_reason "fuzzer not built: configure with -DFIELDCAST_FUZZ=ON (or build with clang)")
    else()
      add_custom_command(OUTPUT ${_fuzz_bin}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/fuzz
        COMMAND ${FIELDCAST_CLANGXX} -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined
                -I${CMAKE_CURRENT_SOURCE_DIR}/include ${_fuzz_sources} -o ${_fuzz_bin}
        DEPENDS ${_fuzz_sources} ${_input_tests}/RealDescriptors.h
        COMMENT "Building the HID descriptor fuzzer with ${FIELDCAST_CLANGXX}")
      add_custom_target(fieldcast_fuzz_hid_descriptor ALL DEPENDS ${_fuzz_bin})
    endif()
  endif()
  add_test(NAME io.input.fuzz_hid_descriptor
    COMMAND ${_input_tests}/run_fuzzer.sh ${_fuzz_bin} ${CMAKE_CURRENT_BINARY_DIR}/fuzz_hid_corpus "${_fuzz_reason}"
            -runs=500000 -max_total_time=20 -seed=1 -max_len=2048)
  set_tests_properties(io.input.fuzz_hid_descriptor PROPERTIES LABELS "fuzz;io;input" SKIP_RETURN_CODE 77)
endif()
