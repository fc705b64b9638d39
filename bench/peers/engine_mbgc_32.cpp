#include "bench_chain_32.hpp"
#include "engine_mbgc.hpp"

bench::Engine bench::mbgc_engine_32() { return engine_for_generated<chain_32::chain_model>(32); }
