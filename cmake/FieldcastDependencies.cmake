# Every third-party library, found once, each through its own CMake config or pkg-config module.
# scripts/install-deps.sh installs all of them from Debian 12.
find_package(Threads REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(Eigen3 3.4 CONFIG REQUIRED)
find_package(OpenCV 4 CONFIG REQUIRED COMPONENTS core imgproc highgui imgcodecs)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(tomlplusplus CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(spdlog CONFIG REQUIRED)
find_package(zstd CONFIG REQUIRED)
# libtiff (libtiff-dev): GeoTIFF georeferencing tags, which OpenImageIO 2.4 does not expose (ig_core terrain import).
find_package(TIFF REQUIRED)
find_package(nlohmann_json 3 CONFIG REQUIRED)
# Google Highway: the vector kernels, compiled per instruction-set level and dispatched at run time.
find_package(hwy CONFIG REQUIRED)

find_package(PkgConfig REQUIRED)
pkg_check_modules(libgpiod REQUIRED IMPORTED_TARGET libgpiod)
pkg_check_modules(libusb REQUIRED IMPORTED_TARGET libusb-1.0)
pkg_check_modules(libevdev REQUIRED IMPORTED_TARGET libevdev)
pkg_check_modules(libxxhash REQUIRED IMPORTED_TARGET libxxhash)

if(FIELDCAST_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
endif()
if(FIELDCAST_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)
endif()
