# mbgc_precompile_common_headers(TARGET): the standard library headers and fmt
# that most of TARGET's files include, parsed once into a precompiled header. Used on the compiler's and the
# runtime's libraries, where parsing std and fmt took about 1.5 s of each
# file's 1 to 11 s (g++ 12, -O2): mbgc_core compiled in 180 s of CPU instead
# of 232, mbgrt in 91 s of build time instead of 116. Not on the FE library
# (Eigen in the header: 59 s against 51) nor on the gtest programs (gtest in
# it: no change). Each target builds its own (a precompiled header needs its
# target's exact flags). Off with -DMBGC_PCH=OFF.
option(MBGC_PCH "Precompile the common headers of the compiler's and the runtime's libraries" ON)

function(mbgc_precompile_common_headers target)
  if(NOT MBGC_PCH)
    return()
  endif()
  target_precompile_headers(${target} PRIVATE
    <algorithm> <array> <cmath> <cstddef> <functional> <limits> <map> <memory> <optional>
    <set> <string> <string_view> <tuple> <unordered_map> <utility> <vector>
    <fmt/format.h>)
endfunction()

# mbgc_build_in_batches(TARGET): TARGET's files compiled as unity batches of
# 8 (CMake's UNITY_BUILD: one translation unit includes 8 of the sources),
# so the headers they share are parsed and their templates instantiated once
# a batch. On the compiler's library (71 files) and the runtime's (31 files):
# on 2 cores mbgc built in 50 s instead of 72 at the quick start's -O1.
# Off with -DMBGC_UNITY_BUILD=OFF (one file recompiled at a time when you edit
# it; .ci/run's sanitizer tree builds that way, so that every file still
# compiles on its own).
option(MBGC_UNITY_BUILD "Compile the compiler's and the runtime's libraries in unity batches of 8 files" ON)

function(mbgc_build_in_batches target)
  if(MBGC_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
    # In a batch a source file is included, so GCC takes a class it defines
    # for one of a header's and warns when it holds a type of the file's
    # anonymous namespace (-Wsubobject-linkage): true of a header, not of a
    # source compiled in a batch.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
    endif()
  endif()
endfunction()
