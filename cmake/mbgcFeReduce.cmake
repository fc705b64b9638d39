# mbgcFeReduce.cmake — in-tree only (tests and examples): an FE model written by
# fe/make_fe_mesh and reduced by mbgc-reduce to a modal-data file, at build time.
#
#   mbgc_fe_reduce(OUTPUT <file.mbm> MESH_DIR <dir> MESH <kind and arguments after DIR>
#                  REDUCE <mbgc-reduce options besides the matrices, nodes and -o> COMMENT <text>)
#
# make_fe_mesh writes <dir>/nodes.txt, K.mtx, M.mtx (and its node sets, which
# REDUCE may name as @<dir>/root.txt); mbgc-reduce writes <file.mbm>, whose
# directory is created. A simulation that reads the file takes it in DEPENDS.
include_guard(GLOBAL)

function(mbgc_fe_reduce)
  cmake_parse_arguments(ARG "" "OUTPUT;MESH_DIR;COMMENT" "MESH;REDUCE" ${ARGN})
  get_filename_component(out_dir ${ARG_OUTPUT} DIRECTORY)
  add_custom_command(OUTPUT ${ARG_OUTPUT}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${out_dir}
    COMMAND make_fe_mesh ${ARG_MESH}
    COMMAND mbgc-reduce --stiffness ${ARG_MESH_DIR}/K.mtx --mass ${ARG_MESH_DIR}/M.mtx --nodes ${ARG_MESH_DIR}/nodes.txt
            ${ARG_REDUCE} -o ${ARG_OUTPUT}
    DEPENDS make_fe_mesh mbgc-reduce
    COMMENT "${ARG_COMMENT}")
endfunction()
