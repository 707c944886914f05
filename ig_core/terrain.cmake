# Terrain database part of fieldcast::core (issue 3): import, built-in terrain, database format,
# builder, paging. Included by ig_core/CMakeLists.txt.
target_sources(fieldcast_core PRIVATE
  src/BuiltinTerrain.cpp
  src/OpenTerrain.cpp
  src/ProceduralColour.cpp
  src/Progress.cpp
  src/TerrainBuilder.cpp
  src/TerrainDatabase.cpp
  src/TileCache.cpp)
target_link_libraries(fieldcast_core PRIVATE zstd::libzstd_shared PkgConfig::libxxhash spdlog::spdlog)

list(APPEND FIELDCAST_CORE_TEST_SOURCES
  tests/TerrainDatabaseTest.cpp
  tests/BuiltinTerrainTest.cpp
  tests/TileCacheTest.cpp)
