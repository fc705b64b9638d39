# lean_simulator.cmake — a simulator loads only the shared libraries its
# model uses (mbgrt/features.hpp): for a bond graph (the DC motor) ldd lists
# SUNDIALS, fmt and the C/C++ runtime, nothing else (no MPI, no tinygltf, no
# SuiteSparse).
#
#   cmake -DSIM=<simulator> [-DSANITIZED=ON] -P lean_simulator.cmake
#
# SANITIZED: the build adds the sanitizers' runtimes (MBGC_SANITIZE), which
# are allowed too.
cmake_minimum_required(VERSION 3.20)
find_program(LDD ldd REQUIRED)
execute_process(COMMAND ${LDD} ${SIM} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "ldd ${SIM} failed (${status}): ${err}")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(allowed "^(linux-vdso|linux-gate|libsundials_|libfmt|libstdc\\+\\+|libm\\.|libgcc_s|libc\\.|ld-linux|/lib.*/ld-linux)")
if(SANITIZED)
  set(allowed "${allowed}|^(libasan|libubsan)")
endif()
set(unexpected)
set(count 0)
foreach(line IN LISTS lines)
  string(STRIP "${line}" line)
  if(line STREQUAL "")
    continue()
  endif()
  math(EXPR count "${count} + 1")
  string(REGEX REPLACE " .*" "" name "${line}")
  if(NOT name MATCHES "${allowed}")
    list(APPEND unexpected "${name}")
  endif()
endforeach()
if(unexpected)
  list(JOIN unexpected ", " names)
  message(FATAL_ERROR "${SIM} loads ${count} shared libraries, among them ${names}, which its model does not use:\n${out}")
endif()
message(STATUS "${SIM}: ${count} shared libraries, SUNDIALS, fmt and the C/C++ runtime only")
