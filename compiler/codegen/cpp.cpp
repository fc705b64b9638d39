#include "codegen/cpp.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace mbgc::codegen {

static void put(std::string& out, int indent, const std::string& text) {
  out.append(static_cast<std::size_t>(indent), ' ');
  out += text;
  out += '\n';
}

std::string CppStmt::code(bool with_note) const {
  if (unprinted()) throw std::logic_error("mbgc: a statement of `" + name + "` written before its values were printed (codegen bug)");
  switch (kind) {
    case Kind::Comment:
    case Kind::Line: return text;
    case Kind::Blank: return {};
    case Kind::Local: return "const double " + name + " = " + text + ";" + (with_note ? note : "");
    case Kind::Read: return fmt::format("const double {} = {}[{}];", name, array, index);
    case Kind::Assign: return name + " = " + text + ";" + (with_note ? note : "");
    case Kind::Param: return fmt::format("{} = param({}, {});{}", name, index, text, with_note ? note : "");
    case Kind::Array: break;
  }
  return text;
}

static void put_body(std::string& out, int indent, const std::vector<CppStmt>& body) {
  for (const CppStmt& s : body) {
    if (s.kind == CppStmt::Kind::Blank) out += '\n';
    else if (s.kind == CppStmt::Kind::Comment) put(out, indent, "// " + s.text);
    else put(out, indent, s.code());
  }
}

std::string print(const CppFunction& f, int indent) {
  std::string out;
  if (!f.doc.empty()) put(out, indent, "// " + f.doc);
  if (f.body.empty()) {
    put(out, indent, f.signature + " {}");
    return out;
  }
  put(out, indent, f.signature + " {");
  put_body(out, indent + 2, f.body);
  put(out, indent, "}");
  return out;
}

std::string print(const CppClass& c, int indent) {
  std::string out;
  put(out, indent, "class " + c.name + " final : public " + c.base + " {");
  put(out, indent, " public:");
  for (std::size_t i = 0; i < c.public_methods.size(); ++i) {
    if (i) out += '\n';
    out += print(c.public_methods[i], indent + 2);
  }
  out += '\n';
  put(out, indent, " private:");
  for (std::size_t i = 0; i < c.private_methods.size(); ++i) out += print(c.private_methods[i], indent + 2);
  if (!c.private_members.empty()) out += '\n';
  put_body(out, indent + 2, c.private_members);
  put(out, indent, "};");
  return out;
}

void initialiser_lines(std::vector<CppStmt>& out, const std::string& head, const std::vector<std::string>& items,
                       std::size_t per_line, const char* close) {
  out.push_back(CppStmt::line(head + "{"));
  for (std::size_t i = 0; i < items.size(); i += per_line) {
    const auto first = items.begin() + static_cast<long>(i);
    const auto last = items.begin() + static_cast<long>(std::min(items.size(), i + per_line));
    out.push_back(CppStmt::line(fmt::format("    {},", fmt::join(first, last, ", "))));
  }
  out.push_back(CppStmt::line(close));
}

void static_table(std::vector<CppStmt>& body, const char* type, const char* name, const std::vector<long>& v) {
  std::vector<std::string> items;
  for (long x : v) items.push_back(std::to_string(x));
  initialiser_lines(body, fmt::format("static const {} {}[] = ", type, name), items, 20, "};");
}

}  // namespace mbgc::codegen
