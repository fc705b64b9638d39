# witness_size.cmake — what the energy witness (stored_energy() and power())
# adds to the generated file, in bytes (mbgc --stats's `file` row): exact
# counts, not timings. Run with `cmake -P`:
#
#   -DMBGC=<mbgc> -DMODEL=<file.mbg> -DMAX_RATIO=<r> [-DEXTRA=<more mbgc arguments, ;-separated>]
#
# Compiles MODEL with and without --no-energy-witness. Fails unless
# bytes(with) / bytes(without) <= MAX_RATIO (a decimal such as 1.25).
cmake_minimum_required(VERSION 3.20)

function(file_bytes out)
  execute_process(COMMAND ${MBGC} ${MODEL} ${EXTRA} ${ARGN} --stats --stats-format csv
                  RESULT_VARIABLE rc OUTPUT_VARIABLE csv ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mbgc --stats failed on ${MODEL} ${ARGN}:\n${err}")
  endif()
  string(REGEX MATCH "\nfile,[0-9]+,([0-9]+)," row "${csv}")
  if(NOT row)
    message(FATAL_ERROR "no file row in mbgc --stats:\n${csv}")
  endif()
  set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

file_bytes(with)
file_bytes(without --no-energy-witness)
string(REGEX MATCH "^([0-9]+)\\.([0-9][0-9])$" ok "${MAX_RATIO}")
if(NOT ok)
  message(FATAL_ERROR "MAX_RATIO must be a decimal with two places, got ${MAX_RATIO}")
endif()
math(EXPR max_percent "${CMAKE_MATCH_1} * 100 + ${CMAKE_MATCH_2}")
math(EXPR percent "(${with} * 100 + ${without} - 1) / ${without}")  # rounded up
set(args "")
if(EXTRA)
  string(REPLACE ";" " " args " (${EXTRA})")
endif()
set(report "${MODEL}${args}: ${with} bytes with the energy witness, ${without} without: ${percent} % of it (rounded up), at most ${max_percent} % allowed")
# exact comparison: with / without <= max  <=>  with * 100 <= max_percent * without
math(EXPR lhs "${with} * 100")
math(EXPR rhs "${max_percent} * ${without}")
if(lhs GREATER rhs)
  message(FATAL_ERROR "the energy witness costs more code than allowed: ${report}")
endif()
message(STATUS "${report}")
