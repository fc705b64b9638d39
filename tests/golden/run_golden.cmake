# run_golden.cmake — one golden test, run with `cmake -P`.
#
#   -DMBGC=<mbgc> -DDIR=<golden dir> -DNAME=<model name without .mbg> -DKIND=good|bad
#
# good: the generated C++ and every stage dump must equal the blessed files
#       <NAME>.cpp, <NAME>.<stage>.txt, <NAME>.dot, <NAME>.stats.csv (mbgc --stats
#       --stats-format csv: each generated method's lines, bytes and operations
#       per call) and <NAME>.scene.txt (from --explain-scene, when the
#       arguments choose a scene); mbgc must exit 0 and be
#       deterministic (two runs, same bytes); what it prints to stderr (notes,
#       warnings) must equal <NAME>.stderr if either is non-empty.
# bad:  stderr must equal <NAME>.stderr and the exit status <NAME>.status;
#       no output file may be written.
# Both: extra mbgc arguments (e.g. --set N=2.5, --scene tip) may be given in
#       <NAME>.args, one per line.
#       <NAME>.sparse ("file-name bytes") makes a sparse file of that size in a
#       folder of the build tree, passed with -I; the folder is shown as
#       <sparse> in stderr (a file too large to commit, for the size limit).
# With the environment variable MBGC_BLESS=1 the expected files are rewritten
# from the actual output instead (review the diff before committing).
cmake_minimum_required(VERSION 3.20)

include(${CMAKE_CURRENT_LIST_DIR}/golden_check.cmake)

set(extra_args "")
if(EXISTS ${DIR}/${NAME}.args)
  file(STRINGS ${DIR}/${NAME}.args extra_args)
endif()
set(sparse_dir "")
if(EXISTS ${DIR}/${NAME}.sparse)
  file(STRINGS ${DIR}/${NAME}.sparse sparse)
  separate_arguments(sparse)
  list(GET sparse 0 sparse_name)
  list(GET sparse 1 sparse_bytes)
  set(sparse_dir ${CMAKE_CURRENT_BINARY_DIR}/golden-sparse-${NAME})
  file(REMOVE_RECURSE ${sparse_dir})
  file(MAKE_DIRECTORY ${sparse_dir})
  execute_process(COMMAND truncate -s ${sparse_bytes} ${sparse_dir}/${sparse_name} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cannot make the sparse file ${sparse_dir}/${sparse_name}")
  endif()
  list(APPEND extra_args -I ${sparse_dir})
endif()

if(KIND STREQUAL "good")
  execute_process(COMMAND ${MBGC} ${NAME}.mbg ${extra_args} WORKING_DIRECTORY ${DIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE cpp ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mbgc failed on good model ${NAME}.mbg (status ${rc}):\n${err}")
  endif()
  execute_process(COMMAND ${MBGC} ${NAME}.mbg ${extra_args} WORKING_DIRECTORY ${DIR} OUTPUT_VARIABLE cpp2)
  if(NOT cpp STREQUAL cpp2)
    message(FATAL_ERROR "mbgc is not deterministic on ${NAME}.mbg: two runs gave different C++")
  endif()
  check(${NAME}.cpp "${cpp}")
  # notes and warnings on a good model (e.g. what a floating frame removed) are part of its golden
  if(NOT err STREQUAL "" OR EXISTS ${DIR}/${NAME}.stderr)
    check(${NAME}.stderr "${err}")
  endif()
  foreach(stage ast graph causality equations reduced)
    execute_process(COMMAND ${MBGC} ${NAME}.mbg ${extra_args} --dump=${stage} WORKING_DIRECTORY ${DIR}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "mbgc --dump=${stage} failed on ${NAME}.mbg:\n${err}")
    endif()
    check(${NAME}.${stage}.txt "${out}")
  endforeach()
  execute_process(COMMAND ${MBGC} ${NAME}.mbg ${extra_args} --dump=graph --format=dot WORKING_DIRECTORY ${DIR} OUTPUT_VARIABLE dot)
  check(${NAME}.dot "${dot}")
  # What the generated methods cost (mbgc --stats): lines, bytes and operations per call.
  execute_process(COMMAND ${MBGC} ${NAME}.mbg ${extra_args} --stats --stats-format csv WORKING_DIRECTORY ${DIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stats ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mbgc --stats failed on ${NAME}.mbg:\n${err}")
  endif()
  check(${NAME}.stats.csv "${stats}")
  # A scene's golden also holds what --explain-scene says it removed.
  list(FIND extra_args --scene at)
  if(at GREATER_EQUAL 0)
    math(EXPR at "${at} + 1")
    list(GET extra_args ${at} scene)
    execute_process(COMMAND ${MBGC} ${NAME}.mbg --explain-scene ${scene} WORKING_DIRECTORY ${DIR}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE explained ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "mbgc --explain-scene ${scene} failed on ${NAME}.mbg:\n${err}")
    endif()
    check(${NAME}.scene.txt "${explained}")
  endif()
elseif(KIND STREQUAL "bad")
  set(out_file ${CMAKE_CURRENT_BINARY_DIR}/golden-bad-${NAME}.cpp)
  file(REMOVE ${out_file})
  execute_process(COMMAND ${MBGC} ${NAME}.mbg -o ${out_file} ${extra_args} WORKING_DIRECTORY ${DIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "mbgc accepted bad model ${NAME}.mbg")
  endif()
  if(NOT rc MATCHES "^[0-9]+$")
    message(FATAL_ERROR "mbgc crashed on ${NAME}.mbg: ${rc}\n${err}")
  endif()
  if(EXISTS ${out_file})
    message(FATAL_ERROR "mbgc wrote an output file for bad model ${NAME}.mbg")
  endif()
  if(sparse_dir)
    string(REPLACE "${sparse_dir}" "<sparse>" err "${err}")
    file(REMOVE_RECURSE ${sparse_dir})
  endif()
  check(${NAME}.stderr "${err}")
  check(${NAME}.status "${rc}\n")
else()
  message(FATAL_ERROR "KIND must be good or bad")
endif()

if(failures)
  message(FATAL_ERROR "golden test ${KIND}/${NAME} failed:${failures}")
endif()
