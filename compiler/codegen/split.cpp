#include "codegen/split.hpp"

#include <algorithm>
#include <cctype>
#include <fmt/format.h>
#include <map>
#include <set>

namespace mbgc::codegen {
namespace {

bool ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// The identifiers a statement names, skipping members of other scopes
/// (after `.`, `::` or `->`), numbers (1e-08) and string literals.
std::vector<std::string> identifiers(const std::string& s) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < s.size();) {
    const char c = s[i];
    if (c == '"') {  // a string literal
      for (++i; i < s.size() && s[i] != '"'; ++i)
        if (s[i] == '\\') ++i;
      ++i;
    } else if (std::isdigit(static_cast<unsigned char>(c))) {  // a number, its exponent's sign included
      for (++i; i < s.size() && (ident_char(s[i]) || s[i] == '.' ||
                                 ((s[i] == '+' || s[i] == '-') && (s[i - 1] == 'e' || s[i - 1] == 'E')));
           ++i) {
      }
    } else if (ident_start(c)) {
      std::size_t j = i;
      while (j < s.size() && ident_char(s[j])) ++j;
      const bool qualified = (i >= 1 && s[i - 1] == '.') || (i >= 2 && s[i - 2] == ':' && s[i - 1] == ':') ||
                             (i >= 2 && s[i - 2] == '-' && s[i - 1] == '>');
      if (!qualified) out.push_back(s.substr(i, j - i));
      i = j;
    } else {
      ++i;
    }
  }
  return out;
}

/// NAME if the statement defines a local `const double NAME`, else "".
std::string defined_scalar(const CppStmt& st) { return st.defines_local() ? st.name : std::string{}; }

/// NAME if the statement defines a local that a part may not pass to the
/// next: a linear block's arrays (`double NAME[n]`, `int NAME[n]`), its rank
/// (`const int NAME = ...`) or a static table; else "".
std::string defined_block_local(const CppStmt& st) {
  if (st.kind != CppStmt::Kind::Line) return {};
  for (const std::string prefix : {"double ", "int ", "const int ", "static const char* const "}) {
    if (st.text.rfind(prefix, 0) != 0) continue;
    std::size_t j = prefix.size();
    while (j < st.text.size() && ident_char(st.text[j])) ++j;
    if (j > prefix.size() && j < st.text.size() && (st.text[j] == '[' || st.text.compare(j, 3, " = ") == 0))
      return st.text.substr(prefix.size(), j - prefix.size());
  }
  return {};
}

/// Whether the statement reads an unknown from one of `inputs` (the
/// method's `const double*` parameters).
bool reads_input(const CppStmt& st, const std::vector<std::string>& inputs) {
  return st.kind == CppStmt::Kind::Read && std::find(inputs.begin(), inputs.end(), st.array) != inputs.end();
}

struct Signature {
  std::string before;                // "void derivative"
  std::vector<std::string> params;   // "double t", "const double* x", ...
  std::vector<std::string> names;    // "t", "x", ...
  std::vector<std::string> inputs;   // the names of its `const double*` parameters: "x"
  bool is_const = false;
};

Signature parse(const std::string& sig) {
  Signature out;
  const auto open = sig.find('(');
  const auto close = sig.rfind(')');
  out.before = sig.substr(0, open);
  out.is_const = sig.find(" const", close) != std::string::npos;
  const std::string list = sig.substr(open + 1, close - open - 1);
  std::size_t start = 0;
  while (start < list.size()) {
    auto comma = list.find(',', start);
    if (comma == std::string::npos) comma = list.size();
    std::string p = list.substr(start, comma - start);
    while (!p.empty() && p.front() == ' ') p.erase(p.begin());
    if (!p.empty()) {
      const auto ids = identifiers(p);
      out.params.push_back(p);
      out.names.push_back(ids.empty() ? std::string{} : ids.back());
      if (p.rfind("const double* ", 0) == 0) out.inputs.push_back(out.names.back());
    }
    start = comma + 1;
  }
  return out;
}

}  // namespace

std::string method_name(const std::string& signature) {
  const auto open = signature.find('(');
  const auto start = signature.find_last_of(' ', open);
  return signature.substr(start == std::string::npos ? 0 : start + 1,
                          open - (start == std::string::npos ? 0 : start + 1));
}

std::optional<SplitMethod> split_method(const CppFunction& f, std::size_t max_lines) {
  if (f.body.size() <= max_lines || max_lines == 0) return std::nullopt;
  const Signature sig = parse(f.signature);
  if (sig.is_const || std::any_of(sig.names.begin(), sig.names.end(), [](const std::string& n) { return n.empty(); }))
    return std::nullopt;

  // The unknowns a section starts by reading (`const double x = y[3];`,
  // after their comment) are not passed on as members: each part reads the
  // ones it uses itself, where it starts (they do not count towards its lines).
  std::size_t first_read = 0;
  while (first_read < f.body.size() && !reads_input(f.body[first_read], sig.inputs)) ++first_read;
  std::size_t end_read = first_read;
  while (end_read < f.body.size() && reads_input(f.body[end_read], sig.inputs)) ++end_read;
  // their comment, if it heads them alone
  const bool headed = first_read > 0 && first_read < end_read && f.body[first_read - 1].kind == CppStmt::Kind::Comment &&
                      (end_read == f.body.size() || f.body[end_read].kind == CppStmt::Kind::Comment);
  const std::size_t block_begin = headed ? first_read - 1 : first_read;
  std::vector<CppStmt> body(f.body.begin(), f.body.begin() + static_cast<long>(block_begin));
  body.insert(body.end(), f.body.begin() + static_cast<long>(end_read), f.body.end());
  std::map<std::string, std::size_t> input_read;  // local -> its statement in f.body
  for (std::size_t i = first_read; i < end_read; ++i) input_read.emplace(defined_scalar(f.body[i]), i);

  // Where a part may start: at an equation's comment, outside braces and
  // outside the span from a linear block's array to its last reader.
  const std::size_t n = body.size();
  std::vector<std::vector<std::string>> reads(n);
  std::map<std::string, std::pair<std::size_t, std::size_t>> block_span;  // block local -> [definition, last use]
  std::vector<bool> may_start(n, false);
  int depth = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const CppStmt& st = body[i];
    may_start[i] = depth == 0 && st.kind == CppStmt::Kind::Comment;
    if (st.kind == CppStmt::Kind::Comment || st.kind == CppStmt::Kind::Blank) continue;
    const std::string code = st.code(/*with_note=*/false);  // (a note names the model's things, not the method's)
    reads[i] = identifiers(code);
    if (std::string a = defined_block_local(st); !a.empty()) block_span[a] = {i, i};
    for (const std::string& id : reads[i])
      if (auto it = block_span.find(id); it != block_span.end()) it->second.second = i;
    for (char c : code) depth += c == '{' ? 1 : c == '}' ? -1 : 0;
  }
  for (const auto& [name, span] : block_span)
    for (std::size_t i = span.first + 1; i <= span.second; ++i) may_start[i] = false;

  // Greedy: each part ends at the last possible start within max_lines.
  std::vector<std::size_t> starts{0};
  for (std::size_t begin = 0;;) {
    if (n - begin <= max_lines) break;
    std::size_t cut = 0;
    for (std::size_t i = begin + 1; i < n && i <= begin + max_lines; ++i)
      if (may_start[i]) cut = i;
    if (cut == 0)  // no start within the limit: the first one after it
      for (std::size_t i = begin + max_lines + 1; i < n && cut == 0; ++i)
        if (may_start[i]) cut = i;
    if (cut == 0) break;
    starts.push_back(cut);
    begin = cut;
  }
  if (starts.size() < 2) return std::nullopt;
  starts.push_back(n);

  // Which part defines each local; a later part that reads it makes it a member.
  std::map<std::string, std::size_t> defined_in, defined_at;  // local -> its part, its statement
  std::set<std::string> promoted;
  for (std::size_t p = 0; p + 1 < starts.size(); ++p)
    for (std::size_t i = starts[p]; i < starts[p + 1]; ++i) {
      for (const std::string& id : reads[i])
        if (auto it = defined_in.find(id); it != defined_in.end() && it->second < p) promoted.insert(id);
      if (std::string d = defined_scalar(body[i]); !d.empty()) defined_in.emplace(d, p), defined_at.emplace(d, i);
    }

  SplitMethod out;
  out.method = {f.doc, f.signature, {}};
  const std::string name = method_name(f.signature);
  const std::string ret = sig.before.substr(0, sig.before.size() - name.size());
  const std::size_t count = starts.size() - 1;
  std::string args;
  for (std::size_t k = 0; k < sig.names.size(); ++k) args += (k ? ", " : "") + sig.names[k];
  std::string params;
  for (std::size_t k = 0; k < sig.params.size(); ++k) params += (k ? ", " : "") + sig.params[k];
  for (std::size_t p = 0; p < count; ++p) {
    const std::string part = fmt::format("{}_part{}", name, p + 1);
    CppFunction fn{fmt::format("{}, part {} of {}: a long method is cut so that the C++ compiler handles it "
                               "quickly; what a later part reads is a member",
                               name, p + 1, count),
                   fmt::format("{}{}({})", ret, part, params), {}};
    for (const std::string& a : sig.names) fn.body.push_back(CppStmt::line(fmt::format("(void){};", a)));
    std::set<std::size_t> inputs;  // the unknowns it reads: their statements in f.body
    for (std::size_t i = starts[p]; i < starts[p + 1]; ++i)
      for (const std::string& id : reads[i])
        if (auto it = input_read.find(id); it != input_read.end()) inputs.insert(it->second);
    if (headed && !inputs.empty()) fn.body.push_back(f.body[block_begin]);
    for (std::size_t i : inputs) fn.body.push_back(f.body[i]);
    for (std::size_t i = starts[p]; i < starts[p + 1]; ++i) {
      CppStmt st = body[i];
      if (st.kind == CppStmt::Kind::Line && st.text.rfind("(void)", 0) == 0 &&
          std::find(sig.names.begin(), sig.names.end(), st.text.substr(6, st.text.size() - 7)) != sig.names.end())
        continue;  // the method's own (void) of a parameter: every part has its own
      if (std::string d = defined_scalar(st); !d.empty() && promoted.count(d))
        st = CppStmt::assign(d, st.kind == CppStmt::Kind::Read ? fmt::format("{}[{}]", st.array, st.index) : st.text);
      fn.body.push_back(std::move(st));
    }
    out.method.body.push_back(CppStmt::line(fmt::format("{}({});", part, args)));
    out.parts.push_back(std::move(fn));
  }
  // members in order of definition: the file reads in the order it computes
  std::vector<std::pair<std::size_t, std::string>> order;
  for (const std::string& m : promoted) order.push_back({defined_at.at(m), m});
  std::sort(order.begin(), order.end());
  for (auto& [p, m] : order) out.members.push_back(std::move(m));
  return out;
}

}  // namespace mbgc::codegen
