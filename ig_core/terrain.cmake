# Terrain database part of fieldcast::core (issue 3): import, built-in terrain, database format,
# builder, paging. Included by ig_core/CMakeLists.txt.
target_sources(fieldcast_core PRIVATE
  src/AsciiGridReader.cpp
  src/BuiltinTerrain.cpp
  src/ElevationImport.cpp
  src/GeoTiffTags.cpp
  src/Orthophoto.cpp
  src/RawGridReader.cpp
  src/OpenTerrain.cpp
  src/ProceduralColour.cpp
  src/Progress.cpp
  src/TerrainBuilder.cpp
  src/TerrainDatabase.cpp
  src/TileCache.cpp)
target_link_libraries(fieldcast_core PRIVATE zstd::libzstd_shared PkgConfig::libxxhash spdlog::spdlog
  OpenImageIO::OpenImageIO TIFF::TIFF tomlplusplus::tomlplusplus)

list(APPEND FIELDCAST_CORE_TEST_SOURCES
  tests/TerrainDatabaseTest.cpp
  tests/BuiltinTerrainTest.cpp
  tests/TileCacheTest.cpp
  tests/ElevationImportTest.cpp
  tests/ProceduralColourTest.cpp)

# libFuzzer target for the database header/index reader and tile decoder: built with the project
# compiler when that is clang, or with clang++-14 beside a gcc build when FIELDCAST_FUZZ=ON. The
# `fuzz` test runs it briefly and is skipped (with the reason) when it was not built.
# FIELDCAST_FUZZ and FIELDCAST_CLANGXX are set in the top-level CMakeLists.txt.
if(FIELDCAST_BUILD_TESTS)
  set(_db_fuzz_sources ${CMAKE_CURRENT_SOURCE_DIR}/src/TerrainDatabase.cpp ${CMAKE_CURRENT_SOURCE_DIR}/src/TerrainView.cpp
                       ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/DatabaseFuzzer.cpp)
  set(_db_fuzz_bin "${CMAKE_CURRENT_BINARY_DIR}/fuzz/terrain_database_fuzzer")
  set(_db_fuzz_reason "")
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    add_executable(fieldcast_fuzz_terrain_database ${_db_fuzz_sources})
    target_include_directories(fieldcast_fuzz_terrain_database PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(fieldcast_fuzz_terrain_database PRIVATE glm::glm zstd::libzstd_shared PkgConfig::libxxhash)
    target_compile_options(fieldcast_fuzz_terrain_database PRIVATE -fsanitize=fuzzer,address,undefined -g)
    target_link_options(fieldcast_fuzz_terrain_database PRIVATE -fsanitize=fuzzer,address,undefined)
    set_target_properties(fieldcast_fuzz_terrain_database PROPERTIES
      RUNTIME_OUTPUT_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/fuzz OUTPUT_NAME terrain_database_fuzzer)
  else()
    if(NOT FIELDCAST_CLANGXX)
      set(_db_fuzz_reason "clang++ not found (install clang-14 libclang-rt-14-dev: scripts/install-deps.sh --interop)")
    elseif(NOT FIELDCAST_FUZZ)
      set(_db_fuzz_reason "fuzzer not built: configure with -DFIELDCAST_FUZZ=ON (or build with clang)")
    else()
      add_custom_command(OUTPUT ${_db_fuzz_bin}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/fuzz
        COMMAND ${FIELDCAST_CLANGXX} -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined
                -I${CMAKE_CURRENT_SOURCE_DIR}/include ${_db_fuzz_sources} -lzstd -lxxhash -o ${_db_fuzz_bin}
        DEPENDS ${_db_fuzz_sources}
        COMMENT "Building the terrain database fuzzer with ${FIELDCAST_CLANGXX}")
      add_custom_target(fieldcast_fuzz_terrain_database ALL DEPENDS ${_db_fuzz_bin})
    endif()
  endif()
  add_test(NAME core.terrain.fuzz_database
    COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/run_fuzzer.sh ${_db_fuzz_bin} ${CMAKE_CURRENT_BINARY_DIR}/fuzz_database_corpus
            "${_db_fuzz_reason}" -runs=200000 -max_total_time=20 -seed=1 -max_len=65536 -rss_limit_mb=2048)
  set_tests_properties(core.terrain.fuzz_database PROPERTIES LABELS "fuzz;core" SKIP_RETURN_CODE 77)
endif()

# The full-size built-in terrain: build, verify, fly (minutes on 2 cores, so label soak).
if(FIELDCAST_BUILD_TESTS)
  fieldcast_add_test(NAME fieldcast_core_terrain_soak
    SOURCES tests/TerrainSoakTest.cpp
    LIBRARIES fieldcast::core
    LABELS "soak;core")
endif()

# Interop: GeoTIFFs written by GDAL's gdal_translate (skipped without gdal-bin).
if(FIELDCAST_BUILD_TESTS)
  fieldcast_add_test(NAME fieldcast_core_terrain_interop
    SOURCES tests/GdalInteropTest.cpp
    LIBRARIES fieldcast::core
    LABELS "interop;core")
endif()
