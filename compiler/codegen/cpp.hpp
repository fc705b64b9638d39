// codegen/cpp.hpp — a very small C++ syntax tree: enough for the generated
// model class (members, methods, statements), printed with consistent layout.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace mbgc::codegen {

/// A statement of a generated method. The ones later passes reason about
/// are typed: a local's definition, an unknown read from the method's
/// input, an assignment (codegen/split moves them between a long method's
/// parts without reading their text); anything else is a line as written.
struct CppStmt {
  enum class Kind {
    Comment,  // `// text`
    Blank,
    Line,     // `text`: a full statement without indentation
    Local,    // `const double name = text;`
    Read,     // `const double name = array[index];`: an unknown read from one of the method's inputs
    Assign,   // `name = text;` (name: a variable, a member or an array's place)
  };
  Kind kind = Kind::Line;
  std::string text;
  std::string name;   // Local, Read, Assign
  std::string array;  // Read
  std::size_t index = 0;

  static CppStmt comment(std::string t) { return {Kind::Comment, std::move(t), {}, {}, 0}; }
  static CppStmt blank() { return {Kind::Blank, {}, {}, {}, 0}; }
  static CppStmt line(std::string t) { return {Kind::Line, std::move(t), {}, {}, 0}; }
  static CppStmt local(std::string name, std::string value) { return {Kind::Local, std::move(value), std::move(name), {}, 0}; }
  static CppStmt read(std::string name, std::string array, std::size_t index) {
    return {Kind::Read, {}, std::move(name), std::move(array), index};
  }
  static CppStmt assign(std::string name, std::string value) { return {Kind::Assign, std::move(value), std::move(name), {}, 0}; }
  /// Whether it defines a local (`const double name = ...;`).
  bool defines_local() const { return kind == Kind::Local || kind == Kind::Read; }
  /// The statement as printed, without indentation (a comment without its `// `).
  std::string code() const;
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
