#include "bench_chain_2.hpp"
#include "engine_mbgc.hpp"

bench::Engine bench::mbgc_engine_2() { return engine_for_generated<chain_2::chain_model>(2); }
