// codegen/cpp.hpp — a very small C++ syntax tree: enough for the generated
// model class (members, methods, statements), printed with consistent layout.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "ir/expr.hpp"

namespace mbgc::codegen {

/// A statement of a generated method. The ones later passes reason about
/// are typed: a local's definition, an unknown read from the method's
/// input, an assignment, a parameter's value, an initialised array. Their
/// values are expressions (ir::Expr) until the method is printed: the
/// common-subexpression pass (codegen/cse.hpp) reads and names them there,
/// and codegen/render.hpp prints each one once, after it. A value that is
/// C++ already (an array's place, "blk1_x[2]") is `text` from the start.
/// codegen/split moves printed statements between a long method's parts
/// without reading their values.
struct CppStmt {
  enum class Kind {
    Comment,  // `// text`
    Blank,
    Line,     // `text`: a full statement without indentation
    Local,    // `const double name = value;note`
    Read,     // `const double name = array[index];`: an unknown read from one of the method's inputs
    Assign,   // `name = value;note` (name: a variable, a member or an array's place)
    Param,    // `name = param(index, value);note`: a parameter's value, or the one --set gives it
    Array,    // `double name[N] = {values...};`, `columns` of them a line if not 0: printed as Lines by render
  };
  Kind kind = Kind::Line;
  std::string text;   // Comment, Line; Local, Assign, Param: the value printed (from the start, or by render)
  std::string name;   // Local, Read, Assign, Param, Array
  std::string array;  // Read
  std::size_t index = 0;  // Read, Param
  ir::Expr value;                // Local, Assign, Param: the value, until printed
  std::vector<ir::Expr> values;  // Array: the entries, until printed
  std::size_t columns = 0;       // Array: entries a line (0: all on the statement's line)
  std::string note;              // Local, Assign, Param: what follows the `;` ("  // x (model.mbg:3:1)")
  /// Local, Assign: the value recurs elsewhere in the method and is read
  /// there by this statement's name (set by codegen/cse: `hub_f = hub_p /
  /// J_hub`, reused, rather than a cseN copy; every cseN definition).
  bool names_value = false;
  /// Local, Assign: whether codegen/cse may make it names_value, if its value recurs.
  enum class Naming {
    never,
    unnamed,  // if no cseN names the value yet (an equation's unknown)
    always,   // also after a cseN: later statements read this name (a derived constant's member)
  };
  Naming may_name = Naming::never;
  /// Printed with the statement before it: the subexpressions it shares are
  /// defined before that one (a linear block's two arrays stay together).
  bool with_previous = false;

  static CppStmt comment(std::string t) { return make(Kind::Comment, std::move(t)); }
  static CppStmt blank() { return make(Kind::Blank, {}); }
  static CppStmt line(std::string t) { return make(Kind::Line, std::move(t)); }
  /// A local whose value is C++ already.
  static CppStmt local(std::string name, std::string value) { return named(Kind::Local, std::move(name), std::move(value)); }
  static CppStmt local(std::string name, ir::Expr value, std::string note = {}) {
    return valued(Kind::Local, std::move(name), std::move(value), std::move(note));
  }
  static CppStmt read(std::string name, std::string array, std::size_t index) {
    CppStmt s = named(Kind::Read, std::move(name), {});
    s.array = std::move(array);
    s.index = index;
    return s;
  }
  /// An assignment whose value is C++ already.
  static CppStmt assign(std::string name, std::string value) { return named(Kind::Assign, std::move(name), std::move(value)); }
  static CppStmt assign(std::string name, ir::Expr value, std::string note = {}) {
    return valued(Kind::Assign, std::move(name), std::move(value), std::move(note));
  }
  static CppStmt param(std::string name, std::size_t index, ir::Expr value, std::string note) {
    CppStmt s = valued(Kind::Param, std::move(name), std::move(value), std::move(note));
    s.index = index;
    return s;
  }
  static CppStmt array_of(std::string name, std::vector<ir::Expr> values, std::size_t columns = 0) {
    CppStmt s = named(Kind::Array, std::move(name), {});
    s.values = std::move(values);
    s.columns = columns;
    return s;
  }

  /// Whether it defines a local (`const double name = ...;`).
  bool defines_local() const { return kind == Kind::Local || kind == Kind::Read; }
  /// Whether it holds expressions not printed yet.
  bool unprinted() const { return value || kind == Kind::Array; }
  /// The statement as printed, without indentation (a comment without its
  /// `// `). Throws std::logic_error for one with expressions not printed
  /// yet (a codegen bug).
  std::string code(bool with_note = true) const;

 private:
  static CppStmt make(Kind k, std::string text) {
    CppStmt s;
    s.kind = k;
    s.text = std::move(text);
    return s;
  }
  static CppStmt named(Kind k, std::string name, std::string text) {
    CppStmt s = make(k, std::move(text));
    s.name = std::move(name);
    return s;
  }
  static CppStmt valued(Kind k, std::string name, ir::Expr value, std::string note) {
    CppStmt s = named(k, std::move(name), {});
    s.value = std::move(value);
    s.note = std::move(note);
    return s;
  }
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

/// `head{`, then `items`, `per_line` to a line (each line ending in a
/// comma), then `close`: an initialiser written over several lines.
void initialiser_lines(std::vector<CppStmt>& out, const std::string& head, const std::vector<std::string>& items,
                       std::size_t per_line, const char* close);

/// `static const TYPE NAME[] = {...};`, 20 entries per line: a generated
/// method's constant table (sparsity patterns, index and group tables).
void static_table(std::vector<CppStmt>& body, const char* type, const char* name, const std::vector<long>& v);

}  // namespace mbgc::codegen
