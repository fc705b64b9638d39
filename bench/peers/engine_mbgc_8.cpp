#include "bench_chain_8.hpp"
#include "engine_mbgc.hpp"

bench::Engine bench::mbgc_engine_8() { return engine_for_generated<chain_8::chain_model>(8); }
