# fieldcast_add_fuzzer(NAME name MODULE module SOURCES src... [INCLUDES dir...] [LIBRARIES lib...]
#                      [SEEDS dir...] [LABELS label...] [ARGS libFuzzer-flag...])
#
# A libFuzzer executable <current binary dir>/fuzz/<name> (target fieldcast_<name>) and a CTest test
# <module>.fuzz.<name>, labelled "fuzz;<module>" plus LABELS, that runs it briefly (ARGS, e.g.
# -max_total_time=20) over a scratch corpus in the build tree and the read-only SEEDS directories.
#
# - SOURCES are compiled into the fuzzer, the code under test included, so libFuzzer sees their
#   coverage. INCLUDES are include directories (GLM's are added). LIBRARIES are plain system
#   libraries (zstd → -lzstd): the clang++ beside a gcc build cannot take CMake targets.
#   Relative paths are relative to the current source directory.
# - Built with the project compiler when that is clang, or with FIELDCAST_CLANGXX through a custom
#   command beside a gcc build; in both cases only when FIELDCAST_FUZZ is ON (FIELDCAST_FUZZ and
#   FIELDCAST_CLANGXX are set in the top-level CMakeLists.txt).
# - When it cannot be built the test is still registered and reports itself skipped with the
#   reason (cmake/run_fuzzer.sh exits 77).
# - The custom command rebuilds the fuzzer when a source, or a header in an INCLUDES directory or
#   beside a source, changes (headers found at configure time).
include_guard(GLOBAL)

function(fieldcast_add_fuzzer)
  cmake_parse_arguments(ARG "" "NAME;MODULE" "SOURCES;INCLUDES;LIBRARIES;SEEDS;LABELS;ARGS" ${ARGN})
  if(NOT ARG_NAME OR NOT ARG_MODULE OR NOT ARG_SOURCES)
    message(FATAL_ERROR "fieldcast_add_fuzzer: NAME, MODULE and SOURCES are required")
  endif()
  set(_sources "")
  foreach(_s IN LISTS ARG_SOURCES)
    cmake_path(ABSOLUTE_PATH _s BASE_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" NORMALIZE)
    list(APPEND _sources "${_s}")
  endforeach()
  set(_includes "")
  foreach(_i IN LISTS ARG_INCLUDES)
    cmake_path(ABSOLUTE_PATH _i BASE_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" NORMALIZE)
    list(APPEND _includes "${_i}")
  endforeach()
  set(_seeds "")
  foreach(_d IN LISTS ARG_SEEDS)
    cmake_path(ABSOLUTE_PATH _d BASE_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" NORMALIZE)
    list(APPEND _seeds "${_d}")
  endforeach()
  set(_system_includes "")
  if(TARGET glm::glm)  # every fuzzer sees the types' vocabulary, GLM vectors
    get_target_property(_system_includes glm::glm INTERFACE_INCLUDE_DIRECTORIES)
  endif()

  set(_target fieldcast_${ARG_NAME})
  set(_bin "${CMAKE_CURRENT_BINARY_DIR}/fuzz/${ARG_NAME}")
  set(_reason "")
  set(_flags -fsanitize=fuzzer,address,undefined)
  if(NOT FIELDCAST_FUZZ)
    set(_reason "fuzzer not built: configure with -DFIELDCAST_FUZZ=ON (or build with clang)")
  elseif(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    add_executable(${_target} ${_sources})
    target_include_directories(${_target} PRIVATE ${_includes})
    target_include_directories(${_target} SYSTEM PRIVATE ${_system_includes})
    target_compile_options(${_target} PRIVATE ${_flags} -g)
    target_link_options(${_target} PRIVATE ${_flags})
    target_link_libraries(${_target} PRIVATE ${ARG_LIBRARIES})
    set_target_properties(${_target} PROPERTIES RUNTIME_OUTPUT_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}/fuzz"
                                                OUTPUT_NAME ${ARG_NAME})
    set(_bin "$<TARGET_FILE:${_target}>")
  elseif(NOT FIELDCAST_CLANGXX)
    set(_reason "clang++ not found (install clang-14 libclang-rt-14-dev: scripts/install-deps.sh --interop)")
  else()
    set(_headers "")
    set(_header_dirs ${_includes})
    foreach(_s IN LISTS _sources)
      cmake_path(GET _s PARENT_PATH _dir)
      list(APPEND _header_dirs "${_dir}")
    endforeach()
    list(REMOVE_DUPLICATES _header_dirs)
    foreach(_dir IN LISTS _header_dirs)
      file(GLOB_RECURSE _found "${_dir}/*.h")
      list(APPEND _headers ${_found})
    endforeach()
    list(TRANSFORM _includes PREPEND "-I" OUTPUT_VARIABLE _include_flags)
    # The compiler's own directories (/usr/include) stay out: -isystem on them breaks #include_next.
    list(REMOVE_ITEM _system_includes ${CMAKE_CXX_IMPLICIT_INCLUDE_DIRECTORIES})
    list(TRANSFORM _system_includes PREPEND "-isystem" OUTPUT_VARIABLE _system_flags)
    list(TRANSFORM ARG_LIBRARIES PREPEND "-l" OUTPUT_VARIABLE _libs)
    add_custom_command(OUTPUT "${_bin}"
      COMMAND ${CMAKE_COMMAND} -E make_directory "${CMAKE_CURRENT_BINARY_DIR}/fuzz"
      COMMAND ${FIELDCAST_CLANGXX} -std=c++20 -O1 -g ${_flags} ${_include_flags} ${_system_flags} ${_sources}
              ${_libs} -o "${_bin}"
      DEPENDS ${_sources} ${_headers}
      COMMENT "Building the ${ARG_NAME} with ${FIELDCAST_CLANGXX}"
      VERBATIM)
    add_custom_target(${_target} ALL DEPENDS "${_bin}")
  endif()

  set(_test ${ARG_MODULE}.fuzz.${ARG_NAME})
  add_test(NAME ${_test}
    COMMAND "${PROJECT_SOURCE_DIR}/cmake/run_fuzzer.sh" "${_bin}" "${CMAKE_CURRENT_BINARY_DIR}/fuzz/${ARG_NAME}_corpus"
            "${_reason}" ${_seeds} ${ARG_ARGS})
  set(_labels fuzz ${ARG_MODULE} ${ARG_LABELS})
  set_tests_properties(${_test} PROPERTIES LABELS "${_labels}" SKIP_RETURN_CODE 77)
endfunction()
