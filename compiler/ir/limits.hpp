// ir/limits.hpp — how large a model mbgc takes. Past each limit the pass
// that would grow too large reports it at the statement responsible, with a
// hint, instead of running for hours or until the machine runs out of memory
// (docs/limits.md). The defaults fit every model in examples/ and the
// 2000-rod chain of bench/compiler_speed.sh with room to spare; the fuzz
// targets (fuzz/) lower them so that each input compiles in milliseconds.
#pragma once

#include <cstdint>

namespace mbgc::ir {

struct Limits {
  /// Repetitions of one `for` loop.
  long loop_iterations = 100'000;
  /// Iterations and statements of nested loops together.
  long unrolled_work = 200'000;
  /// Elements, junctions and bonds once loops, bodies and component instances
  /// are expanded. The generated C++ grows with it: the 2000-rod chain has
  /// 80,000 and gives 115 MB of C++.
  long model_size = 100'000;
};

/// The largest file mbgc reads: a model, an imported file, a modal-data file
/// or a mesh. Files this big are not typed by people; reading a mistaken
/// multi-gigabyte path would exhaust the machine's memory.
inline constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{256} << 20;

}  // namespace mbgc::ir
