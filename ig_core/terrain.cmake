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
  tests/ElevationImportTest.cpp)
