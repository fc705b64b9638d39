#include "codegen/entry_point.hpp"

#include <fmt/format.h>

namespace mbgc::codegen {

std::string simulator_main(const EntryPoint& e) {
  std::string uses;
  if (e.draws_bodies) uses += "  mbgrt::use_gltf_animation();  // --animate FILE.glb: the bodies drawn in glTF\n";
  if (e.sparse_pattern) uses += "  mbgrt::use_sparse_lu();  // IDA's KLU on the sparsity pattern above\n";
  return fmt::format("int main(int argc, char** argv) {{\n  {} model;\n{}  return mbgrt::run_main(model, argc, argv);\n}}\n",
                     e.class_name, uses);
}

}  // namespace mbgc::codegen
