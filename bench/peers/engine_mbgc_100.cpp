#include "bench_chain_100.hpp"
#include "engine_mbgc.hpp"

bench::Engine bench::mbgc_engine_100() { return engine_for_generated<chain_100::chain_model>(100); }
