# mbgcFunctions.cmake — compile .mbg models at build time.
#
#   mbgc_add_simulation(<target> MODEL <file.mbg> [NATIVE] [OPTIONS <mbgc options>...]
#                       [DEPENDS <files or targets>...])
#       a simulator executable (generated C++ with main()). DEPENDS names files
#       the model reads that the build itself makes (a modal-data file written
#       by a custom command, found with OPTIONS -I <its directory>). The
#       model itself may be written by the build too: the OUTPUT of an
#       add_custom_command in the same directory (tests/random). NATIVE
#       compiles the generated source for the build machine's processor
#       (-march=native: its vector and FMA instructions), which may make it
#       faster there and keeps it from running on an older processor: for a
#       simulator that stays on the machine that built it, not for one to
#       copy elsewhere. The runtime library is compiled as before.
#   mbgc_add_fmu(<target> MODEL <file.mbg> [OPTIONS <mbgc options>...] [DEPENDS ...])
#       a Functional Mock-up Unit, <target>.fmu in the current binary
#       directory, built by `mbgc --fmu` (OPTIONS: --fmi 2, --fmu-kind me,
#       --constraints coordinates, ...; docs/fmi.md); the target <target>
#       builds it with `all`.
#   mbgc_add_model(<target> MODEL <file.mbg> [NATIVE] [OPTIONS ...] [DEPENDS ...])
#       an INTERFACE library whose header <target>.hpp holds the model class
#       (mbgc --library), for embedding a model in your own program (NATIVE:
#       the programs that include it are compiled with -march=native).
#
# The generated source is rebuilt when the model, any file it imports or reads
# (modal-data files), or the compiler changes (add_custom_command with DEPENDS and a depfile).
# MBGC_COMPILER_TARGET names the mbgc executable target: `mbgc` inside this
# project, `mbgc::mbgc` after find_package(mbgc). MBGC_GENERATED_COMPILE_OPTIONS,
# if set, are added to the compile of each generated simulator source only, and
# to the programs that include a model made by mbgc_add_model (this project's
# sanitizer build sets -fno-sanitize=undefined there).
include_guard(GLOBAL)

if(NOT DEFINED MBGC_COMPILER_TARGET)
  set(MBGC_COMPILER_TARGET mbgc)
endif()
if(NOT DEFINED MBGC_RUNTIME_TARGET)
  set(MBGC_RUNTIME_TARGET mbgc::mbgrt)
endif()
if(NOT DEFINED MBGC_FMU_RUNTIME_TARGET)
  set(MBGC_FMU_RUNTIME_TARGET mbgc::mbgrt_fmu)
endif()

# -march=native, where the compiler takes it (GCC and Clang do; MSVC does not)
include(CheckCXXCompilerFlag)
check_cxx_compiler_flag(-march=native MBGC_HAVE_MARCH_NATIVE)
# A simulator's generated source reads no errno and tests no floating-point
# exception flag: -fno-math-errno and -fno-trapping-math change none of its
# values (the two-track car's rows are the same to the last bit) and let the
# compiler inline sqrt and if-convert (the car 3 % faster). Only there: a
# program that includes a model of mbgc_add_model keeps its own flags.
check_cxx_compiler_flag(-fno-math-errno MBGC_HAVE_NO_MATH_ERRNO)
check_cxx_compiler_flag(-fno-trapping-math MBGC_HAVE_NO_TRAPPING_MATH)

# The compile options of a generated source: MBGC_GENERATED_COMPILE_OPTIONS,
# and -march=native if `native` is true (a warning where the compiler has
# none); `simulator`: a simulator's own source (the math flags above).
function(_mbgc_generated_options target native out_var)
  set(options ${MBGC_GENERATED_COMPILE_OPTIONS})
  if(ARGN STREQUAL "simulator")
    if(MBGC_HAVE_NO_MATH_ERRNO)
      list(APPEND options -fno-math-errno)
    endif()
    if(MBGC_HAVE_NO_TRAPPING_MATH)
      list(APPEND options -fno-trapping-math)
    endif()
  endif()
  if(native)
    if(MBGC_HAVE_MARCH_NATIVE)
      list(APPEND options -march=native)
    else()
      message(WARNING "mbgc: ${target}: NATIVE asked for, but ${CMAKE_CXX_COMPILER_ID} does not take -march=native; "
                      "compiled for the default target")
    endif()
  endif()
  set(${out_var} ${options} PARENT_SCOPE)
endfunction()

function(_mbgc_generate target model_in out_file)
  cmake_parse_arguments(ARG "" "OUTPUT_OPTION" "OPTIONS;DEPENDS" ${ARGN})
  if(NOT ARG_OUTPUT_OPTION)
    set(ARG_OUTPUT_OPTION -o)
  endif()
  get_filename_component(model ${model_in} ABSOLUTE)
  # a model the build writes (the OUTPUT of an add_custom_command in the same
  # directory, as tests/random does) need not exist yet
  get_source_file_property(generated ${model} GENERATED)
  if(NOT EXISTS ${model} AND NOT generated)
    message(FATAL_ERROR "mbgc: model file ${model_in} not found (for target ${target})")
  endif()
  set(depfile ${CMAKE_CURRENT_BINARY_DIR}/${target}.mbgc.d)
  set(depfile_args)
  if(CMAKE_GENERATOR MATCHES "Ninja|Makefiles")
    set(depfile_args DEPFILE ${depfile})
    list(APPEND ARG_OPTIONS --depfile ${depfile})
  endif()
  # Ninja re-checks a custom command's outputs (restat): when a new mbgc
  # generates the same C++, the simulator is not recompiled. (Make would
  # rerun mbgc on every build instead, so only under Ninja.)
  if(CMAKE_GENERATOR MATCHES "Ninja" AND ARG_OUTPUT_OPTION STREQUAL "-o")
    list(APPEND ARG_OPTIONS --keep-unchanged)
  endif()
  add_custom_command(
    OUTPUT ${out_file}
    COMMAND ${MBGC_COMPILER_TARGET} ${model} ${ARG_OUTPUT_OPTION} ${out_file} ${ARG_OPTIONS}
    DEPENDS ${model} ${MBGC_COMPILER_TARGET} ${ARG_DEPENDS}
    ${depfile_args}
    COMMENT "mbgc: compiling model ${model_in}"
    VERBATIM)
endfunction()

function(mbgc_add_simulation target)
  cmake_parse_arguments(ARG "NATIVE" "MODEL" "OPTIONS;DEPENDS" ${ARGN})
  if(NOT ARG_MODEL)
    message(FATAL_ERROR "mbgc_add_simulation(${target}): MODEL <file.mbg> is required")
  endif()
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target}.cpp)
  _mbgc_generate(${target} ${ARG_MODEL} ${out} OPTIONS ${ARG_OPTIONS} DEPENDS ${ARG_DEPENDS})
  add_executable(${target} ${out})
  _mbgc_generated_options(${target} "${ARG_NATIVE}" options simulator)
  if(options)
    set_source_files_properties(${out} PROPERTIES COMPILE_OPTIONS "${options}")
  endif()
  target_link_libraries(${target} PRIVATE ${MBGC_RUNTIME_TARGET})
endfunction()

function(mbgc_add_model target)
  cmake_parse_arguments(ARG "NATIVE" "MODEL" "OPTIONS;DEPENDS" ${ARGN})
  if(NOT ARG_MODEL)
    message(FATAL_ERROR "mbgc_add_model(${target}): MODEL <file.mbg> is required")
  endif()
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/${target}_include)
  set(out ${dir}/${target}.hpp)
  file(MAKE_DIRECTORY ${dir})
  _mbgc_generate(${target} ${ARG_MODEL} ${out} OPTIONS --library ${ARG_OPTIONS} DEPENDS ${ARG_DEPENDS})
  add_custom_target(${target}_generate DEPENDS ${out})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_generate)
  target_include_directories(${target} INTERFACE ${dir})
  target_link_libraries(${target} INTERFACE ${MBGC_RUNTIME_TARGET})
  # a program that includes the model compiles its code in its own source
  _mbgc_generated_options(${target} "${ARG_NATIVE}" options)
  if(options)
    target_compile_options(${target} INTERFACE ${options})
  endif()
endfunction()

function(mbgc_add_fmu target)
  cmake_parse_arguments(ARG "" "MODEL" "OPTIONS;DEPENDS" ${ARGN})
  if(NOT ARG_MODEL)
    message(FATAL_ERROR "mbgc_add_fmu(${target}): MODEL <file.mbg> is required")
  endif()
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target}.fmu)
  # (the FMU links the runtime's FMU library: rebuilt when it changes)
  _mbgc_generate(${target} ${ARG_MODEL} ${out} OUTPUT_OPTION --fmu OPTIONS ${ARG_OPTIONS}
                 DEPENDS ${ARG_DEPENDS} ${MBGC_FMU_RUNTIME_TARGET})
  add_custom_target(${target} ALL DEPENDS ${out})
endfunction()
