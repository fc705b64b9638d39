# mbgc_warnings(TARGET...): the warnings this project's own code is held to,
# -Wall -Wextra with GCC and Clang. They are errors only with
# -DMBGC_WERROR=ON (tools/test.sh and .ci/run turn it on): a user's build, an
# IDE's or a distribution's, with whatever compiler and build type, never
# stops on a warning a newer compiler invents. The installed package's CMake
# functions (mbgcFunctions.cmake) add no warning flags to a consumer's
# targets.
option(MBGC_WERROR "Treat warnings as errors in the project's own targets (CI)" OFF)

function(mbgc_warnings)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    return()
  endif()
  set(flags -Wall -Wextra)
  # GCC 12's flow-based -Warray-bounds, -Wrestrict, -Wstringop-overflow and
  # -Wstringop-overread misfire on libstdc++'s own inlined std::string
  # copies at -O3 (CMake's Release): "__builtin_memcpy forming offset [40,
  # 44] is out of the bounds [0, 40]" for moving a struct that holds a string
  # into a vector, a bug many projects met with this compiler. Off for GCC 12 only; the sanitizer
  # pass of CI (AddressSanitizer) checks the real bounds at run time.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
     AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    list(APPEND flags -Wno-array-bounds -Wno-restrict -Wno-stringop-overflow -Wno-stringop-overread)
  endif()
  if(MBGC_WERROR)
    list(APPEND flags -Werror)
  endif()
  foreach(target IN LISTS ARGN)
    target_compile_options(${target} PRIVATE ${flags})
  endforeach()
endfunction()
