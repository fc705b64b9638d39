# ops_ratio.cmake — how the generated code's work grows with the model, from
# mbgc --stats's operation counts (not from timings). Run with `cmake -P`:
#
#   -DMBGC=<mbgc> -DMODEL=<file.mbg> -DSMALL=<N> -DLARGE=<N> -DMAX_RATIO=<r>
#   [-DSMALLEST=<N>] [-DEXTRA=<more mbgc arguments, ;-separated>]
#
# Compiles MODEL with --set N=SMALL and --set N=LARGE and reads the ops of the
# method that computes the dynamics (derivative_and_power, derivative, or residual for a DAE: its
# expressions plus mbgrt::solve_linear's arithmetic). Fails unless
# ops(LARGE) / ops(SMALL) <= MAX_RATIO (a decimal such as 2.1). With
# SMALLEST, also unless the operations per added body are the same, to 1 %,
# from SMALLEST to SMALL as from SMALL to LARGE (exactly linear growth, a
# constant allowed: the test for a tree whose root costs less than a body).
cmake_minimum_required(VERSION 3.20)

function(dynamics_ops n out_ops out_lines)
  execute_process(COMMAND ${MBGC} ${MODEL} --set N=${n} ${EXTRA} --stats --stats-format csv
                  RESULT_VARIABLE rc OUTPUT_VARIABLE csv ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mbgc --stats failed on ${MODEL} with N = ${n}:\n${err}")
  endif()
  # (derivative_and_power where the model has an energy balance: derivative() calls it)
  string(REGEX MATCH "\n(derivative_and_power),([0-9]+),[0-9]+,([0-9]+)," row "${csv}")
  if(NOT row)
    string(REGEX MATCH "\n(derivative|residual),([0-9]+),[0-9]+,([0-9]+)," row "${csv}")
  endif()
  if(NOT row)
    message(FATAL_ERROR "no derivative or residual row in mbgc --stats for N = ${n}:\n${csv}")
  endif()
  set(${out_ops} ${CMAKE_MATCH_3} PARENT_SCOPE)
  set(${out_lines} ${CMAKE_MATCH_2} PARENT_SCOPE)
  set(method ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

dynamics_ops(${SMALL} small_ops small_lines)
dynamics_ops(${LARGE} large_ops large_lines)
if(small_ops EQUAL 0)
  message(FATAL_ERROR "${method} has no operations at N = ${SMALL}")
endif()

# ratio in thousandths, integer arithmetic: large * 1000 / small (rounded down)
math(EXPR milli "${large_ops} * 1000 / ${small_ops}")
string(REGEX MATCH "^([0-9]+)(\\.([0-9]*))?$" ok "${MAX_RATIO}")
if(NOT ok)
  message(FATAL_ERROR "MAX_RATIO must be a decimal number, got ${MAX_RATIO}")
endif()
set(frac "${CMAKE_MATCH_3}000")
string(SUBSTRING "${frac}" 0 3 frac)
math(EXPR max_milli "${CMAKE_MATCH_1} * 1000 + 1${frac} - 1000")
math(EXPR whole "${milli} / 1000")
math(EXPR part "${milli} % 1000")
string(LENGTH "${part}" len)
if(len EQUAL 1)
  set(part "00${part}")
elseif(len EQUAL 2)
  set(part "0${part}")
endif()
set(args "")
if(EXTRA)
  string(REPLACE ";" " " args " (${EXTRA})")
endif()
set(report "${method} of ${MODEL}${args}: ${small_ops} operations (${small_lines} lines) at N = ${SMALL}, ${large_ops} (${large_lines} lines) at N = ${LARGE}: ratio ${whole}.${part}, at most ${MAX_RATIO} allowed")
# exact comparison: large / small <= max  <=>  large * 1000 <= max_milli * small
math(EXPR lhs "${large_ops} * 1000")
math(EXPR rhs "${max_milli} * ${small_ops}")
if(lhs GREATER rhs)
  message(FATAL_ERROR "the work grows faster than allowed: ${report}")
endif()
message(STATUS "${report}")

if(DEFINED SMALLEST)
  dynamics_ops(${SMALLEST} smallest_ops smallest_lines)
  # per added body, in thousandths of an operation
  math(EXPR early "(${small_ops} - ${smallest_ops}) * 1000 / (${SMALL} - ${SMALLEST})")
  math(EXPR late "(${large_ops} - ${small_ops}) * 1000 / (${LARGE} - ${SMALL})")
  math(EXPR gap "${late} - ${early}")
  if(gap LESS 0)
    math(EXPR gap "0 - ${gap}")
  endif()
  set(report "${method}: ${early}/1000 operations per added body from N = ${SMALLEST} to ${SMALL}, ${late}/1000 from ${SMALL} to ${LARGE}")
  math(EXPR limit "${early} / 100")
  if(gap GREATER limit)
    message(FATAL_ERROR "the work per body is not constant: ${report}")
  endif()
  message(STATUS "${report}")
endif()
