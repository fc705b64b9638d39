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
