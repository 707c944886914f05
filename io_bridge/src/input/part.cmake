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
# clang++-14 beside a gcc build when FIELDCAST_FUZZ=ON (the default when clang++ is installed). The
# `fuzz` test runs it briefly and is skipped (with the reason) when it was not built.
# FIELDCAST_FUZZ and FIELDCAST_CLANGXX are set in the top-level CMakeLists.txt.
# fieldcast_input_fuzzer(<name> <sources...>): a libFuzzer executable fuzz/<name> and a `fuzz` test
# that runs it for 15 s (seeded corpus in the build tree), or skips with the reason.
function(fieldcast_input_fuzzer name)
  set(_sources ${ARGN})
  set(_bin "${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name}")
  set(_reason "")
  set(_includes -I${PROJECT_SOURCE_DIR}/io_bridge/include -I${PROJECT_SOURCE_DIR}/types/include)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang" AND FIELDCAST_FUZZ)
    add_executable(fieldcast_${name} ${_sources})
    target_include_directories(fieldcast_${name} PRIVATE ${PROJECT_SOURCE_DIR}/io_bridge/include
                                                         ${PROJECT_SOURCE_DIR}/types/include)
    target_compile_options(fieldcast_${name} PRIVATE -fsanitize=fuzzer,address,undefined -g)
    target_link_options(fieldcast_${name} PRIVATE -fsanitize=fuzzer,address,undefined)
    set_target_properties(fieldcast_${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/fuzz
                                                       OUTPUT_NAME ${name})
  elseif(NOT FIELDCAST_CLANGXX)
    set(_reason "clang++ not found (install clang-14 libclang-rt-14-dev: scripts/install-deps.sh --interop)")
  elseif(NOT FIELDCAST_FUZZ)
    set(_reason "fuzzer not built: configure with -DFIELDCAST_FUZZ=ON (or build with clang)")
  else()
    add_custom_command(OUTPUT ${_bin}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/fuzz
      COMMAND ${FIELDCAST_CLANGXX} -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined ${_includes}
              ${_sources} -o ${_bin}
      DEPENDS ${_sources} ${PROJECT_SOURCE_DIR}/io_bridge/tests/input/RealDescriptors.h
      COMMENT "Building the ${name} with ${FIELDCAST_CLANGXX}")
    add_custom_target(fieldcast_${name} ALL DEPENDS ${_bin})
  endif()
  add_test(NAME io.input.${name}
    COMMAND ${PROJECT_SOURCE_DIR}/io_bridge/tests/input/run_fuzzer.sh ${_bin} ${CMAKE_CURRENT_BINARY_DIR}/${name}_corpus
            "${_reason}" -runs=500000 -max_total_time=15 -seed=1 -max_len=2048)
  set_tests_properties(io.input.${name} PROPERTIES LABELS "fuzz;io;input" SKIP_RETURN_CODE 77)
endfunction()

if(FIELDCAST_BUILD_TESTS)
  fieldcast_input_fuzzer(hid_descriptor_fuzzer ${_input}/InputEvent.cpp ${_input}/HidReportDescriptor.cpp
                         ${_input}/HidReportDecoder.cpp ${_input_tests}/HidDescriptorFuzz.cpp)
  fieldcast_input_fuzzer(input_recording_fuzzer ${_input}/InputEvent.cpp ${_input}/InputRecording.cpp
                         ${PROJECT_SOURCE_DIR}/types/src/Time.cpp ${_input_tests}/InputRecordingFuzz.cpp)
endif()
