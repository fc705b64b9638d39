// fuzz_check.hpp — what every fuzz target asserts beyond "no crash": a
// failed check aborts, and libFuzzer keeps the input as a crash.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#include "ir/diagnostics.hpp"

namespace mbgc::fuzz {

inline void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz check failed: %s\n", what);
  std::abort();
}

/// Every diagnostic is at a place in a file the compiler read (line and
/// column within it), and the rendering says "error:" when there is one.
inline void check_diagnostics(const ir::Diagnostics& diags, const std::string& rendered) {
  for (const ir::Diagnostic& d : diags.all()) {
    if (!d.loc.valid()) continue;  // about the command line or the whole run
    check(d.loc.line >= 1 && d.loc.col >= 1, "a diagnostic without a line and column");
    check(!d.message.empty(), "a diagnostic without a message");
  }
  check(!diags.has_errors() || rendered.find("error:") != std::string::npos, "errors rendered without `error:`");
}

}  // namespace mbgc::fuzz
