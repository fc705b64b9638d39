# run_install_test.cmake — the install/outside-project test (cmake -P script).
#
#   1. cmake --install MBGC_BUILD_DIR --prefix WORK_DIR/prefix, check the files;
#   2. copy tests/install/outside to WORK_DIR/src, configure it with
#      CMAKE_PREFIX_PATH=WORK_DIR/prefix and build it;
#   3. run both simulators (rc from mbgc_add_simulation, rc_embedded from
#      mbgc_add_model + main.cpp) with --t-end 1 --out FILE.csv and check the
#      CSV against the RC closed form to 1e-6 relative;
#   3a. run its FMU (mbgc_add_fmu) under fmusim (FMUSIM, when given) and
#      check its CSV the same way;
#   4. touch rc.mbg, rebuild: mbgc must run for both targets (under Ninja,
#      leaving the same C++ untouched and nothing recompiled); edit it so that
#      the C++ changes: both generated files must be rewritten; a further
#      build must do nothing.
#
# Variables (-D): MBGC_BUILD_DIR WORK_DIR OUTSIDE_SOURCE_DIR GENERATOR
# CXX_COMPILER INSTALL_BINDIR INSTALL_LIBDIR INSTALL_INCLUDEDIR
# COMPILER_FILE_NAME RUNTIME_FILE_NAME; optional CONFIG MAKE_PROGRAM.
cmake_minimum_required(VERSION 3.20)

foreach(var MBGC_BUILD_DIR WORK_DIR OUTSIDE_SOURCE_DIR GENERATOR CXX_COMPILER
            INSTALL_BINDIR INSTALL_LIBDIR INSTALL_INCLUDEDIR
            COMPILER_FILE_NAME RUNTIME_FILE_NAME)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_install_test.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix ${WORK_DIR}/prefix)
set(src ${WORK_DIR}/src)
set(bld ${WORK_DIR}/build)
set(config_args)
if(CONFIG)
  set(config_args --config ${CONFIG})
endif()

# ---- helpers -----------------------------------------------------------------

# run(<what> [OUTPUT_VARIABLE <var>] COMMAND <cmd>...): run, fail the test on a
# nonzero exit status, showing the command's output.
function(run what)
  cmake_parse_arguments(R "" "OUTPUT_VARIABLE" "COMMAND" ${ARGN})
  message(STATUS "install test: ${what}")
  execute_process(COMMAND ${R_COMMAND}
    RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT status EQUAL 0)
    list(JOIN R_COMMAND " " cmd)
    message(FATAL_ERROR "install test: ${what} failed (exit status ${status})\n"
                        "command: ${cmd}\n${out}")
  endif()
  if(R_OUTPUT_VARIABLE)
    set(${R_OUTPUT_VARIABLE} "${out}" PARENT_SCOPE)
  endif()
endfunction()

# to_fixed(<out> <number>): the decimal or scientific number as an integer in
# units of 1e-12 (truncated). CMake's math() is 64-bit integer only.
set(FIXED_DIGITS 12)
function(to_fixed out str)
  string(STRIP "${str}" s)
  if(NOT s MATCHES "^([-+]?)([0-9]*)(\\.([0-9]*))?([eE]([-+]?[0-9]+))?$"
     OR (CMAKE_MATCH_2 STREQUAL "" AND CMAKE_MATCH_4 STREQUAL ""))
    message(FATAL_ERROR "install test: `${str}` is not a number")
  endif()
  set(sign "${CMAKE_MATCH_1}")
  set(digits "${CMAKE_MATCH_2}${CMAKE_MATCH_4}")
  string(LENGTH "${CMAKE_MATCH_4}" frac_len)
  set(exp10 0)
  if(NOT "${CMAKE_MATCH_6}" STREQUAL "")
    set(exp10 ${CMAKE_MATCH_6})
  endif()
  string(REGEX REPLACE "^\\+" "" exp10 "${exp10}")
  math(EXPR shift "${exp10} - ${frac_len} + ${FIXED_DIGITS}")
  if(shift GREATER_EQUAL 0)
    string(REPEAT "0" ${shift} zeros)
    string(APPEND digits "${zeros}")
  else()
    string(LENGTH "${digits}" n)
    math(EXPR keep "${n} + ${shift}")
    if(keep LESS_EQUAL 0)
      set(digits 0)
    else()
      string(SUBSTRING "${digits}" 0 ${keep} digits)
    endif()
  endif()
  string(REGEX REPLACE "^0+" "" digits "${digits}")
  if(digits STREQUAL "")
    set(digits 0)
  endif()
  string(LENGTH "${digits}" n)
  if(n GREATER 18)
    message(FATAL_ERROR "install test: ${str} is too large to compare")
  endif()
  if(sign STREQUAL "-")
    set(digits "-${digits}")
  endif()
  set(${out} ${digits} PARENT_SCOPE)
endfunction()

# expect_close(<what> <actual> <expected> <divisor>):
# |actual - expected| <= |expected| / divisor (divisor 1000000: 1e-6 relative).
function(expect_close what actual expected divisor)
  to_fixed(a "${actual}")
  to_fixed(e "${expected}")
  math(EXPR diff "${a} - ${e}")
  if(diff LESS 0)
    math(EXPR diff "-(${diff})")
  endif()
  set(abs_e ${e})
  if(abs_e LESS 0)
    math(EXPR abs_e "-(${abs_e})")
  endif()
  math(EXPR limit "${abs_e} / ${divisor}")
  if(diff GREATER limit)
    message(FATAL_ERROR "install test: ${what} is ${actual}, expected ${expected} "
                        "(difference ${diff}e-${FIXED_DIGITS}, allowed ${limit}e-${FIXED_DIGITS})")
  endif()
  message(STATUS "install test: ${what} = ${actual} (closed form ${expected})")
endfunction()

# check_csv(<file>): header `t,...`; rows at t = 0.5 and the final row t = 1
# match the RC closed form (R C = 1 s, V = 1 V, R = 1000 ohm).
function(check_csv file)
  if(NOT EXISTS ${file})
    message(FATAL_ERROR "install test: ${file} was not written")
  endif()
  file(STRINGS ${file} lines)
  list(LENGTH lines n)
  if(n LESS 3)
    message(FATAL_ERROR "install test: ${file} has only ${n} lines")
  endif()
  list(GET lines 0 header)
  if(NOT header MATCHES "^t,")
    message(FATAL_ERROR "install test: ${file}: header `${header}` does not begin with `t,`")
  endif()
  string(REPLACE "," ";" columns "${header}")
  list(FIND columns v_c col_v)
  list(FIND columns i col_i)
  if(col_v LESS 0 OR col_i LESS 0)
    message(FATAL_ERROR "install test: ${file}: header `${header}` lacks v_c or i")
  endif()

  # Closed form: v_c = 1 - exp(-t), i = 1e-3 exp(-t).
  set(found_half FALSE)
  math(EXPR last "${n} - 1")
  foreach(k RANGE 1 ${last})
    list(GET lines ${k} row)
    string(REPLACE "," ";" row "${row}")
    list(GET row 0 t)
    list(GET row ${col_v} v)
    list(GET row ${col_i} i)
    to_fixed(t_fx "${t}")
    if(t_fx GREATER 499999999000 AND t_fx LESS 500000001000)       # t = 0.5
      set(found_half TRUE)
      expect_close("${file}: v_c(0.5)" "${v}" 0.39346934028736658 1000000)
      expect_close("${file}: i(0.5)" "${i}" 6.0653065971263342e-4 1000000)
    endif()
  endforeach()
  if(NOT found_half)
    message(FATAL_ERROR "install test: ${file} has no row at t = 0.5")
  endif()
  # The final row is the stop time, t = 1.
  expect_close("${file}: final t" "${t}" 1 1000000000)
  expect_close("${file}: final v_c (t = 1)" "${v}" 0.63212055882855768 1000000)
  expect_close("${file}: final i (t = 1)" "${i}" 3.6787944117144233e-4 1000000)
endfunction()

# ---- 1. install ----------------------------------------------------------------
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
run("cmake --install ${MBGC_BUILD_DIR} --prefix ${prefix}"
  OUTPUT_VARIABLE out
  COMMAND ${CMAKE_COMMAND} --install ${MBGC_BUILD_DIR} --prefix ${prefix} ${config_args})
if(out MATCHES "CMake (Warning|Error|Deprecation)")
  message(FATAL_ERROR "install test: cmake --install complained:\n${out}")
endif()

set(cmakedir ${prefix}/${INSTALL_LIBDIR}/cmake/mbgc)
foreach(f
    ${INSTALL_BINDIR}/${COMPILER_FILE_NAME}
    ${INSTALL_LIBDIR}/${RUNTIME_FILE_NAME}
    ${INSTALL_INCLUDEDIR}/mbgrt/model.hpp
    ${INSTALL_INCLUDEDIR}/mbgrt/fmu.hpp
    ${INSTALL_LIBDIR}/libmbgrt_fmu.a
    ${INSTALL_LIBDIR}/cmake/mbgc/mbgcConfig.cmake
    ${INSTALL_LIBDIR}/cmake/mbgc/mbgcConfigVersion.cmake
    ${INSTALL_LIBDIR}/cmake/mbgc/mbgcTargets.cmake
    ${INSTALL_LIBDIR}/cmake/mbgc/mbgcFunctions.cmake
    ${INSTALL_LIBDIR}/pkgconfig/mbgrt.pc)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "install test: ${prefix}/${f} was not installed")
  endif()
endforeach()
run("installed mbgc --version"
  COMMAND ${prefix}/${INSTALL_BINDIR}/${COMPILER_FILE_NAME} --version)

# ---- 2. configure and build the outside project ----------------------------------
file(COPY ${OUTSIDE_SOURCE_DIR}/ DESTINATION ${src})
set(configure_args -S ${src} -B ${bld} -G ${GENERATOR}
  -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
  -DCMAKE_PREFIX_PATH=${prefix}
  -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON)
if(MAKE_PROGRAM)
  list(APPEND configure_args -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
endif()
if(CONFIG)
  list(APPEND configure_args -DCMAKE_BUILD_TYPE=${CONFIG})
endif()
run("configure the outside project" OUTPUT_VARIABLE out
  COMMAND ${CMAKE_COMMAND} ${configure_args})

# It must have used the package just installed, not the build tree or another copy.
file(STRINGS ${bld}/CMakeCache.txt mbgc_dir_line REGEX "^mbgc_DIR:")
string(REGEX REPLACE "^mbgc_DIR:[A-Z]+=" "" mbgc_dir "${mbgc_dir_line}")
file(REAL_PATH "${mbgc_dir}" mbgc_dir)
file(REAL_PATH "${cmakedir}" cmakedir_real)
if(NOT mbgc_dir STREQUAL cmakedir_real)
  message(FATAL_ERROR "install test: find_package(mbgc) found `${mbgc_dir}`, not ${cmakedir_real}\n${out}")
endif()
string(FIND "${out}" "compiler ${prefix}/" at)
if(at LESS 0)
  message(FATAL_ERROR "install test: mbgc::mbgc is not the installed compiler:\n${out}")
endif()

run("build the outside project" OUTPUT_VARIABLE out
  COMMAND ${CMAKE_COMMAND} --build ${bld} ${config_args})

# ---- 3. run the simulators and check the CSV ------------------------------------------
function(find_exe out name)
  foreach(candidate ${bld}/${CONFIG}/${name} ${bld}/${name})
    if(EXISTS ${candidate} AND NOT IS_DIRECTORY ${candidate})
      set(${out} ${candidate} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "install test: no executable ${name} in ${bld}")
endfunction()

foreach(sim rc rc_embedded)
  find_exe(exe ${sim})
  run("${sim} --t-end 1 --out ${sim}.csv"
    COMMAND ${exe} --t-end 1 --out ${WORK_DIR}/${sim}.csv)
  check_csv(${WORK_DIR}/${sim}.csv)
endforeach()

# ---- 3a. the FMU of mbgc_add_fmu, under fmusim (when the build has it: tests/fmi) ----------
if(NOT EXISTS ${bld}/rc_fmu.fmu)
  message(FATAL_ERROR "install test: mbgc_add_fmu made no ${bld}/rc_fmu.fmu")
endif()
if(FMUSIM)
  run("fmusim --interface-type cs rc_fmu.fmu"
    COMMAND ${FMUSIM} --interface-type cs --stop-time 1 --output-file ${WORK_DIR}/rc_fmu_fmusim.csv ${bld}/rc_fmu.fmu)
  # fmusim quotes its header and calls the time `time`: as the simulators write it
  file(READ ${WORK_DIR}/rc_fmu_fmusim.csv fmu_csv)
  string(REPLACE "\"" "" fmu_csv "${fmu_csv}")
  string(REGEX REPLACE "^time," "t," fmu_csv "${fmu_csv}")
  file(WRITE ${WORK_DIR}/rc_fmu.csv "${fmu_csv}")
  check_csv(${WORK_DIR}/rc_fmu.csv)
else()
  message(STATUS "install test: no fmusim, the outside project's FMU was built but not run")
endif()

# ---- 3b. without CMake: the installed mbgc, then c++ with pkg-config's flags ----------
find_program(PKG_CONFIG pkg-config REQUIRED)
run("installed mbgc rc.mbg -o rc_by_hand.cpp"
  COMMAND ${prefix}/${INSTALL_BINDIR}/${COMPILER_FILE_NAME} ${src}/rc.mbg -o ${WORK_DIR}/rc_by_hand.cpp)
set(ENV{PKG_CONFIG_PATH} ${prefix}/${INSTALL_LIBDIR}/pkgconfig)
run("pkg-config --cflags --libs mbgrt" OUTPUT_VARIABLE flags
  COMMAND ${PKG_CONFIG} --cflags --libs mbgrt)
if(NOT flags MATCHES "-I${prefix}/")
  message(FATAL_ERROR "install test: pkg-config's flags do not name the prefix ${prefix}:\n${flags}")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run("c++ rc_by_hand.cpp $(pkg-config --cflags --libs mbgrt)"
  COMMAND ${CXX_COMPILER} -std=c++17 -O1 ${WORK_DIR}/rc_by_hand.cpp ${flags} -o ${WORK_DIR}/rc_by_hand)
run("rc_by_hand --t-end 1 --out rc_by_hand.csv"
  COMMAND ${WORK_DIR}/rc_by_hand --t-end 1 --out ${WORK_DIR}/rc_by_hand.csv)
check_csv(${WORK_DIR}/rc_by_hand.csv)

# ---- 4. touching the model regenerates the C++ -------------------------------------
set(generated ${bld}/rc.cpp ${bld}/rc_lib_include/rc_lib.hpp)
set(comment_regex "mbgc: compiling model")

run("rebuild with nothing changed" OUTPUT_VARIABLE out
  COMMAND ${CMAKE_COMMAND} --build ${bld} ${config_args})
if(out MATCHES "${comment_regex}")
  message(FATAL_ERROR "install test: an unchanged model was recompiled:\n${out}")
endif()

set(before)
foreach(g ${generated})
  if(NOT EXISTS ${g})
    message(FATAL_ERROR "install test: generated file ${g} is missing")
  endif()
  file(TIMESTAMP ${g} stamp "%s")
  list(APPEND before ${stamp})
endforeach()
# Timestamps below have one-second resolution: make sure a second passes.
execute_process(COMMAND ${CMAKE_COMMAND} -E sleep 1.1)
file(TOUCH ${src}/rc.mbg)

run("rebuild after touching rc.mbg" OUTPUT_VARIABLE out
  COMMAND ${CMAKE_COMMAND} --build ${bld} ${config_args})
string(REGEX MATCHALL "${comment_regex}" hits "${out}")
list(LENGTH hits n_hits)
if(NOT n_hits EQUAL 3)
  message(FATAL_ERROR "install test: after touching rc.mbg, expected the model compiled "
                      "three times (rc, rc_lib and rc_fmu), saw ${n_hits}:\n${out}")
endif()
# Under Ninja mbgc runs with --keep-unchanged: the same C++ is left alone
# (restat: nothing is recompiled); an edit that changes the C++ (here a new
# parameter, which the simulator lists) rewrites it.
if(GENERATOR MATCHES "Ninja")
  foreach(g stamp IN ZIP_LISTS generated before)
    file(TIMESTAMP ${g} after "%s")
    if(NOT after EQUAL stamp)
      message(FATAL_ERROR "install test: ${g} was rewritten with the same text (mtime ${stamp} -> ${after})")
    endif()
  endforeach()
  if(out MATCHES "Building CXX")
    message(FATAL_ERROR "install test: the same generated C++ was recompiled:\n${out}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E sleep 1.1)
  file(APPEND ${src}/rc.mbg "param spare = 1   // a parameter nothing reads: new C++, the same results\n")
  run("rebuild after editing rc.mbg" OUTPUT_VARIABLE out
    COMMAND ${CMAKE_COMMAND} --build ${bld} ${config_args})
endif()
foreach(g stamp IN ZIP_LISTS generated before)
  file(TIMESTAMP ${g} after "%s")
  if(NOT after GREATER stamp)
    message(FATAL_ERROR "install test: ${g} was not rewritten (mtime ${stamp} -> ${after})")
  endif()
endforeach()
string(REGEX MATCHALL "[^\n]*${comment_regex}[^\n]*" hits "${out}")
list(JOIN hits "\n  " hits)
message(STATUS "install test: editing rc.mbg regenerated rc.cpp and rc_lib.hpp:\n  ${hits}")

run("rebuild once more" OUTPUT_VARIABLE out
  COMMAND ${CMAKE_COMMAND} --build ${bld} ${config_args})
if(out MATCHES "${comment_regex}")
  message(FATAL_ERROR "install test: the model is recompiled on every build:\n${out}")
endif()

# The rebuilt simulator still runs.
find_exe(exe rc)
run("rc after the rebuild" COMMAND ${exe} --t-end 1 --out ${WORK_DIR}/rc_rebuilt.csv)
check_csv(${WORK_DIR}/rc_rebuilt.csv)

message(STATUS "install test: passed")
