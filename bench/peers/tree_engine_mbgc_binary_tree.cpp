#include "bench_binary_tree_31.hpp"
#include "tree_engines.hpp"

bench::Engine bench::tree::mbgc_binary_tree_31() {
  return engine_for_generated_tree<binary_tree_31::binary_tree_model>();
}
