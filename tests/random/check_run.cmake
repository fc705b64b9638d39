# check_run.cmake — one random-model test (tests/random/CMakeLists.txt), run
# with `cmake -P`.
#
#   -DSIM=<simulator> -DCSV=<file.csv>   runs `SIM --t-end 1 -o CSV`, then checks CSV
#   -DCSV=<file.csv>                     checks an existing CSV (the meta tests)
#
# Fails unless the simulator exits with status 0 and the CSV has a header and
# at least two rows, each as wide as the header, of finite numbers only (no
# nan, inf or empty field).
cmake_minimum_required(VERSION 3.20)

if(NOT CSV)
  message(FATAL_ERROR "usage: cmake -DCSV=<file.csv> [-DSIM=<simulator>] -P check_run.cmake")
endif()

if(SIM)
  file(REMOVE ${CSV})
  execute_process(COMMAND ${SIM} --t-end 1 -o ${CSV}
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${SIM} --t-end 1 failed (status ${rc}):\n${err}")
  endif()
endif()

if(NOT EXISTS ${CSV})
  message(FATAL_ERROR "no CSV written: ${CSV}")
endif()
file(STRINGS ${CSV} lines)
list(LENGTH lines count)
if(count LESS 3)
  message(FATAL_ERROR "${CSV}: a header and at least 2 rows expected, found ${count} lines")
endif()
list(POP_FRONT lines header)
string(REPLACE "," ";" columns "${header}")
list(LENGTH columns width)

# a decimal number as the simulator writes it (shortest round trip, e.g.
# -0.25, 1e-05, 3.5e+20); nan, inf and text do not match
set(number "^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$")
set(row 1)
foreach(line IN LISTS lines)
  math(EXPR row "${row} + 1")
  string(REPLACE "," ";" values "${line}")
  list(LENGTH values n)
  if(NOT n EQUAL width)
    message(FATAL_ERROR "${CSV}:${row}: ${n} values for ${width} columns")
  endif()
  set(column 0)
  foreach(value IN LISTS values)
    if(NOT value MATCHES "${number}")
      list(GET columns ${column} name)
      message(FATAL_ERROR "${CSV}:${row}: column ${name} is `${value}`, not a finite number")
    endif()
    math(EXPR column "${column} + 1")
  endforeach()
endforeach()
