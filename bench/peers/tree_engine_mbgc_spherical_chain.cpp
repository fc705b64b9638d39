#include "bench_spherical_chain_32.hpp"
#include "tree_engines.hpp"

bench::Engine bench::tree::mbgc_spherical_chain_32() {
  return engine_for_generated_tree<spherical_chain_32::spherical_chain_model>();
}
