# io_bridge part "gpio": cockpit discretes (freeze, reset, trigger) and the external sync input,
# read as kernel-timestamped edges through libgpiod v1, behind a line seam (fake line in tests).
# (The GPIO field-sync *output* pulse belongs to the sinks part.)
set(_gpio "${CMAKE_CURRENT_LIST_DIR}")
target_sources(fieldcast_io PRIVATE
  ${_gpio}/ExternalSync.cpp
  ${_gpio}/GpioInputs.cpp
  ${_gpio}/GpiodEdgeLine.cpp
  ${_gpio}/GpioLineSpec.cpp)
target_link_libraries(fieldcast_io PRIVATE PkgConfig::libgpiod spdlog::spdlog)

if(FIELDCAST_BUILD_TESTS)
  set(_gpio_tests "${CMAKE_CURRENT_LIST_DIR}/../../tests/gpio")
  fieldcast_add_test(NAME fieldcast_io_gpio_tests
    SOURCES ${_gpio_tests}/GpioInputTest.cpp
    LIBRARIES fieldcast::io
    LABELS "unit;io;gpio")
  fieldcast_add_test(NAME fieldcast_io_gpio_hw_tests
    SOURCES ${_gpio_tests}/GpioHardwareTest.cpp
    LIBRARIES fieldcast::io PkgConfig::libgpiod  # it reads lines back through libgpiod itself
    LABELS "hw;io;gpio")
endif()
