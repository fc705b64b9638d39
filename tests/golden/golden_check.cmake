# golden_check.cmake — what every golden runner shares (included by
# run_golden.cmake and tests/fe/run_reduce_golden.cmake): check(<file> <actual>)
# compares DIR/<file> with the actual text, or rewrites it when MBGC_BLESS=1;
# differences collect in `failures`.
set(bless "$ENV{MBGC_BLESS}")
set(failures "")

function(check expected_file actual)
  if(bless STREQUAL "1")
    file(WRITE ${DIR}/${expected_file} "${actual}")
    return()
  endif()
  if(NOT EXISTS ${DIR}/${expected_file})
    set(failures "${failures}\n  missing ${expected_file} (run with MBGC_BLESS=1 to create it)" PARENT_SCOPE)
    return()
  endif()
  file(READ ${DIR}/${expected_file} expected)
  if(NOT expected STREQUAL actual)
    set(tmp ${CMAKE_CURRENT_BINARY_DIR}/golden-actual-${expected_file})
    file(WRITE ${tmp} "${actual}")
    execute_process(COMMAND diff -u ${DIR}/${expected_file} ${tmp} OUTPUT_VARIABLE d)
    set(failures "${failures}\n  ${expected_file} differs:\n${d}" PARENT_SCOPE)
  endif()
endfunction()

