#include <stdexcept>

#include "engine_mbgc.hpp"

namespace bench {

Engine mbgc_engine(int n) {
  switch (n) {
    case 2: return mbgc_engine_2();
    case 8: return mbgc_engine_8();
    case 32: return mbgc_engine_32();
    case 100: return mbgc_engine_100();
  }
  throw std::invalid_argument("mbgc_engine: the benchmark compiles the chain for N = 2, 8, 32 and 100 only");
}

}  // namespace bench
