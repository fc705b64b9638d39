# The progress line on a terminal (issue 18, point 4): a simulator run under a
# pseudo-terminal (util-linux `script`) draws "t = ... s of ... s (NN %)" with
# carriage returns; with --quiet it draws nothing. The run is paced by
# --realtime 2 over 1 s of simulated time, so it lasts 0.5 s of wall time,
# longer than the 0.25 s before a progress line first appears.
#   cmake -DSIM=<simulator> -P progress_tty.cmake
find_program(SCRIPT script REQUIRED)
foreach(quiet "" "--quiet")
  execute_process(COMMAND ${SCRIPT} -qec "${SIM} --realtime 2 --t-end 1 --out /dev/null ${quiet}" /dev/null
                  OUTPUT_VARIABLE tty RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "the run under script failed (${status}):\n${tty}")
  endif()
  string(REGEX MATCH "\rt = [0-9.]+ s of 1 s \\([0-9]+ %\\)" line "${tty}")
  if(quiet STREQUAL "" AND NOT line)
    message(FATAL_ERROR "no progress line on the terminal:\n${tty}")
  elseif(NOT quiet STREQUAL "" AND (line OR tty MATCHES "\r[^\n]"))
    message(FATAL_ERROR "--quiet, but something was drawn on the terminal:\n${tty}")
  endif()
endforeach()
