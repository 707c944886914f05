# The ray caster (issue 4): column caster, reference renderer, render pool, frame-time controller.
target_sources(fieldcast_core PRIVATE
  src/render/ColumnCaster.cpp
  src/render/FrameTimeController.cpp
  src/render/PlaneMarch.cpp
  src/render/RayMarch.cpp
  src/render/ReferenceRenderer.cpp
  src/render/RenderPool.cpp
  src/render/Renderer.cpp
  src/render/SyntheticTerrain.cpp
  src/render/ViewGeometry.cpp)
list(APPEND FIELDCAST_CORE_TEST_SOURCES
  tests/render/RenderAccuracyTest.cpp
  tests/render/RenderPoolTest.cpp
  tests/render/RendererTest.cpp
  tests/render/LodSeamTest.cpp
  tests/render/FrameLayoutTest.cpp
  tests/render/PlaneMarchSweepTest.cpp
  tests/render/SpanFillTest.cpp)
