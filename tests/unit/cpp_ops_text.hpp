// tests/unit/cpp_ops_text.hpp — the floating-point operations in generated C++
// text, read back from the text: the independent check of the counter that
// ir::to_cpp (and so mbgc --stats) keeps while printing.
#pragma once

#include <cctype>
#include <string>

#include "ir/expr.hpp"

namespace mbgc_test {

/// Operations in expression text as to_cpp writes it (binary operators
/// between spaces, x*x without, literals with a '.' or an exponent).
inline mbgc::ir::CppOps cpp_ops_in_text(std::string s) {
  // literals that are not numbers: no operation (a leading minus included)
  for (const char* lit : {"-std::numeric_limits<double>::infinity()", "std::numeric_limits<double>::infinity()",
                          "std::numeric_limits<double>::quiet_NaN()"})
    for (auto at = s.find(lit); at != std::string::npos; at = s.find(lit)) s.replace(at, std::string(lit).size(), "#");
  mbgc::ir::CppOps o;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const char before = i ? s[i - 1] : ' ', after = i + 1 < s.size() ? s[i + 1] : ' ';
    if (c == '*') ++o.mul;
    else if (c == '/') ++o.div;
    else if (c == '<' || c == '>') ++o.compare;
    else if ((c == '+' || c == '-') && before == ' ' && after == ' ') ++o.add;
    // a minus that is not a literal's sign nor an exponent's (1e-06)
    else if (c == '-' && before != 'e' && !std::isdigit(static_cast<unsigned char>(after)) && after != '#') ++o.neg;
    else if (s.compare(i, 5, "std::") == 0) ++o.call;
  }
  return o;
}

}  // namespace mbgc_test
