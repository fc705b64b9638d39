// entry_point.hpp — the simulator's main(): the model, the optional parts of
// the runtime its model needs (mbgrt/features.hpp), and run_main. Only what
// a model uses is linked: a bond graph's simulator loads neither tinygltf
// nor SuiteSparse.
#pragma once

#include <string>

namespace mbgc::codegen {

struct EntryPoint {
  std::string class_name;
  bool draws_bodies = false;   ///< the model has body_poses: --animate's glTF writer
  bool sparse_pattern = false; ///< the model gives residual_sparsity: IDA's KLU
};

/// The text of main() (the template includes mbgrt/features.hpp).
std::string simulator_main(const EntryPoint& e);

}  // namespace mbgc::codegen
