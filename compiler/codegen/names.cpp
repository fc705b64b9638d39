#include "codegen/names.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <set>

namespace mbgc::codegen {

namespace {

// Identifiers a model name must not become: C++ keywords and alternative
// tokens, macros the included headers define, and the names the generated
// class itself uses (its methods, locals and members).
const std::set<std::string> kReserved = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case",
    "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept", "const", "consteval",
    "constexpr", "constinit", "const_cast", "continue", "co_await", "co_return", "co_yield", "decltype",
    "default", "delete", "do", "double", "dynamic_cast", "else", "enum", "explicit", "export", "extern",
    "false", "float", "for", "friend", "goto", "if", "inline", "int", "long", "mutable", "namespace",
    "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq", "private", "protected",
    "public", "register", "reinterpret_cast", "requires", "return", "short", "signed", "sizeof",
    "static", "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local",
    "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual",
    "void", "volatile", "wchar_t", "while", "xor", "xor_eq", "final", "override", "import", "module",
    // macros from <cmath>, <climits>, <cstddef>, <cstdio> and friends
    "NAN", "INFINITY", "HUGE_VAL", "HUGE_VALF", "HUGE_VALL", "NULL", "EOF", "errno", "assert",
    "offsetof", "math_errhandling", "MATH_ERRNO", "MATH_ERREXCEPT", "DOMAIN", "SING", "OVERFLOW",
    "UNDERFLOW", "TLOSS", "PLOSS", "CHAR_BIT", "INT_MAX", "INT_MIN", "stdin", "stdout", "stderr",
    "unix", "linux", "i386",
    // names the generated code uses itself
    "t", "x", "xdot", "xp", "y", "yp", "r", "jac_out", "rows_out", "out", "id", "i", "s", "value", "std", "mbgrt", "mbgc_model",
    "main", "model", "argc", "argv", "param", "overrides_", "overridden_", "kNames", "kParams",
    "name", "source_file", "make_new", "size", "variable_name", "output_names", "parameters", "is_dae",
    "differential_ids", "default_settings", "set_parameter", "initial", "derivative", "residual",
    "outputs", "terminal", "state_count", "position_constraint_count", "velocity_constraint_count",
    "constraints_enforced", "constraint_held", "kHeld", "constraint_name", "constraints", "kConstraintNames", "jacobian", "has_jacobian", "state_limit", "state_limit_reason",
    "residual_sparsity", "column_starts", "rows", "kStarts", "kRows", "rank_loss", "rank_loss_",
    "multiplier_index", "stabiliser_index", "kIndex", "row", "unknown_role", "kRoles", "R",
    "constraint_jacobian", "constraint_jacobian_pattern", "row_starts", "columns", "kColumns", "values",
    "nominal", "nominal_", "v", "unknown_group", "kGroups", "has_energy_balance", "energy_note", "stored_energy",
    "power", "witness_values", "derivative_and_power", "rate", "position_rates", "has_position_rates", "computed", "Row", "all"};

}  // namespace

/// Reserved by the C++ implementation or by the standard library's macros.
bool reserved(const std::string& id) {
  if (kReserved.count(id)) return true;
  if (id.size() > 1 && id[0] == '_' && (std::isupper(static_cast<unsigned char>(id[1])) || id[1] == '_')) return true;
  if (id.find("__") != std::string::npos) return true;
  // the parts of a long method (codegen/split.hpp): derivative_part1, ...
  for (const char* method : {"derivative_part", "residual_part", "jacobian_part", "constraint_jacobian_part"})
    if (id.rfind(method, 0) == 0) return true;
  // <cmath>/<cfloat>/<cstdint> macro families: M_PI, FP_NAN, DBL_MAX, INT8_MAX, ...
  for (const char* prefix : {"M_", "FP_", "DBL_", "FLT_", "LDBL_", "INT", "UINT", "SIZE_", "PTRDIFF_"})
    if (id.rfind(prefix, 0) == 0 && std::all_of(id.begin(), id.end(), [](char c) {
          return std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_';
        }))
      return true;
  return false;
}

std::string Mangler::get(const std::string& key, const std::string& model_name) {
  if (auto it = given_.find(key); it != given_.end()) return it->second;
  std::string id;
  for (char c : model_name) {
    bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    if (ok) id += c;
    else if (!id.empty() && id.back() != '_') id += '_';
  }
  while (!id.empty() && id.back() == '_') id.pop_back();
  while (!id.empty() && id.front() == '_') id.erase(id.begin());
  for (auto p = id.find("__"); p != std::string::npos; p = id.find("__")) id.erase(p, 1);
  if (id.empty() || std::isdigit(static_cast<unsigned char>(id[0]))) id = "v_" + id;
  if (id.rfind("cse", 0) == 0) id = "v_" + id;  // keep cseN for common subexpressions
  if (reserved(id)) id += "_v";  // lower-case suffix: no longer a keyword or a macro-like name
  std::string unique = id;
  for (int k = 2; used_.count(unique); ++k) unique = fmt::format("{}_{}", id, k);
  used_.insert(unique);
  given_[key] = unique;
  return unique;
}

std::string cpp_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string cpp_double(double v) {
  if (std::isnan(v)) return "std::numeric_limits<double>::quiet_NaN()";
  if (std::isinf(v)) return v > 0 ? "std::numeric_limits<double>::infinity()" : "-std::numeric_limits<double>::infinity()";
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

}  // namespace mbgc::codegen
