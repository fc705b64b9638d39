// codegen/names.hpp — C++ identifiers and literals for the generated code:
// which names a model may not take, model names made into unique
// identifiers, strings and doubles written exactly.
#pragma once

#include <string>
#include <unordered_map>
#include <unordered_set>

namespace mbgc::codegen {

/// Reserved by C++, by the standard library's macros or by the generated class itself.
bool reserved(const std::string& id);

/// Unique C++ identifiers for model names ("m1.rotor.p" -> "m1_rotor_p").
class Mangler {
 public:
  /// The identifier for `key`, made from `model_name` the first time.
  std::string get(const std::string& key, const std::string& model_name);

 private:
  std::unordered_map<std::string, std::string> given_;  // looked up only: hashed (N = 1000 rods: 300k names)
  std::unordered_set<std::string> used_;
};

std::string cpp_string(const std::string& s);  ///< a C++ string literal
std::string cpp_double(double v);              ///< a double literal that reads back exactly
}  // namespace mbgc::codegen
