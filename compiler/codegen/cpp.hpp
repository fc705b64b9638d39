// codegen/cpp.hpp — a very small C++ syntax tree: enough for the generated
// model class (members, methods, statements), printed with consistent layout.
#pragma once

#include <string>
#include <vector>

namespace mbgc::codegen {

struct CppStmt {
  enum class Kind { Comment, Blank, Line };
  Kind kind = Kind::Line;
  std::string text;  // Line: a full statement without indentation
  static CppStmt comment(std::string t) { return {Kind::Comment, std::move(t)}; }
  static CppStmt blank() { return {Kind::Blank, {}}; }
  static CppStmt line(std::string t) { return {Kind::Line, std::move(t)}; }
};

struct CppFunction {
  std::string doc;        // one-line comment above the function
  std::string signature;  // e.g. "void derivative(double t, const double* x, double* xdot) override"
  std::vector<CppStmt> body;
};

struct CppClass {
  std::string name;
  std::string base;
  std::vector<CppFunction> public_methods;
  std::vector<CppFunction> private_methods;
  std::vector<CppStmt> private_members;
};

std::string print(const CppClass& c, int indent = 0);
std::string print(const CppFunction& f, int indent);

/// `static const TYPE NAME[] = {...};`, 20 entries per line: a generated
/// method's constant table (sparsity patterns, index and group tables).
void static_table(std::vector<CppStmt>& body, const char* type, const char* name, const std::vector<long>& v);

}  // namespace mbgc::codegen
