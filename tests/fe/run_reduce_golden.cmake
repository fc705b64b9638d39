# run_reduce_golden.cmake — one golden test of an mbgc-reduce error, run with `cmake -P`.
#
#   -DREDUCE=<mbgc-reduce> -DDIR=<tests/fe/bad> -DNAME=<case>
#
# The case's arguments are in <NAME>.args (one per line, paths relative to
# DIR); stderr must equal <NAME>.stderr and the exit status <NAME>.status, and
# no output file may be written. MBGC_BLESS=1 rewrites the expected files.
cmake_minimum_required(VERSION 3.20)
file(STRINGS ${DIR}/${NAME}.args args)
set(out_file ${CMAKE_CURRENT_BINARY_DIR}/reduce-bad-${NAME}.mbm)
file(REMOVE ${out_file})
execute_process(COMMAND ${REDUCE} ${args} -o ${out_file} WORKING_DIRECTORY ${DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "mbgc-reduce accepted bad case ${NAME}")
endif()
if(NOT rc MATCHES "^[0-9]+$")
  message(FATAL_ERROR "mbgc-reduce crashed on ${NAME}: ${rc}\n${err}")
endif()
if(EXISTS ${out_file})
  message(FATAL_ERROR "mbgc-reduce wrote an output file for bad case ${NAME}")
endif()
include(${CMAKE_CURRENT_LIST_DIR}/../golden/golden_check.cmake)
check(${NAME}.stderr "${err}")
check(${NAME}.status "${rc}\n")
if(failures)
  message(FATAL_ERROR "golden test fe/bad/${NAME} failed:${failures}")
endif()
