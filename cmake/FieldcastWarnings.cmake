# fieldcast::warnings — the warning set every Fieldcast target compiles with (PRIVATE link).
# fieldcast::arch — the instruction-set choice: generic x86-64 unless FIELDCAST_NATIVE is on.
add_library(fieldcast_warnings INTERFACE)
add_library(fieldcast::warnings ALIAS fieldcast_warnings)
target_compile_options(fieldcast_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Wnull-dereference
  -Wimplicit-fallthrough -Wformat=2)
if(FIELDCAST_WERROR)
  target_compile_options(fieldcast_warnings INTERFACE -Werror)
endif()

add_library(fieldcast_arch INTERFACE)
add_library(fieldcast::arch ALIAS fieldcast_arch)
if(FIELDCAST_NATIVE)
  target_compile_options(fieldcast_arch INTERFACE -march=native)
endif()
