// Recursive-descent parser for grammar/mbg.ebnf. Statements need no
// terminator (`;` is optional): every statement starts with a keyword, an
// element kind or a junction type, so the next statement is always
// recognisable. On an error we report it and skip to the next statement start.
#include "parse/parse.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <set>
#include <sstream>

#include "parse/lexer.hpp"

namespace mbgc::parse {
namespace {

using ir::AstExpr;
using ir::AstExprPtr;

const std::set<std::string> kElementKinds = {"Se", "Sf", "I", "C", "R", "TF", "GY", "MTF", "MGY"};
const std::set<std::string> kKeywords = {"model", "import", "param", "signal", "output", "bond",
                                         "simulate", "component", "instance"};

struct ParseError {};

class Parser {
 public:
  Parser(std::vector<Token> toks, ir::Diagnostics& diags) : toks_(std::move(toks)), diags_(diags) {}

  ir::AstProgram program() {
    ir::AstProgram p;
    while (!at(Tok::End)) {
      if (accept(Tok::Semi)) continue;
      statement_into(p.stmts, /*in_component=*/false);
    }
    return p;
  }

 private:
  // ---- token helpers --------------------------------------------------------
  const Token& peek(std::size_t k = 0) const {
    std::size_t j = std::min(pos_ + k, toks_.size() - 1);
    return toks_[j];
  }
  bool at(Tok k) const { return peek().kind == k; }
  bool at_ident(const char* text) const { return at(Tok::Ident) && peek().text == text; }
  const Token& next() {
    const Token& t = toks_[pos_];
    if (pos_ + 1 < toks_.size()) ++pos_;
    return t;
  }
  bool accept(Tok k) {
    if (!at(k)) return false;
    next();
    return true;
  }
  [[noreturn]] void fail(const std::string& message, const std::string& hint) {
    diags_.error(peek().loc, message, hint);
    throw ParseError{};
  }
  const Token& expect(Tok k, const char* what_for, const std::string& hint = {}) {
    if (!at(k))
      fail(fmt::format("expected {} {}, found {}", tok_name(k), what_for, describe(peek())), hint);
    return next();
  }
  static std::string describe(const Token& t) {
    if (t.kind == Tok::Ident) return fmt::format("`{}`", t.text);
    if (t.kind == Tok::Number) return fmt::format("number `{}`", t.text);
    return tok_name(t.kind);
  }
  bool at_statement_start() const {
    if (at(Tok::End) || at(Tok::RBrace)) return true;
    // A statement starts a line (or follows `;`): a 0 or 1 inside an
    // expression, or a parameter named like an element kind, does not.
    bool line_start = pos_ == 0 || toks_[pos_ - 1].loc.line != peek().loc.line ||
                      toks_[pos_ - 1].kind == Tok::Semi || toks_[pos_ - 1].kind == Tok::LBrace ||
                      toks_[pos_ - 1].kind == Tok::RBrace;
    if (at(Tok::Number))
      return line_start && (peek().text == "0" || peek().text == "1") && peek(1).kind == Tok::Ident;
    if (!at(Tok::Ident)) return false;
    return line_start && (kKeywords.count(peek().text) || kElementKinds.count(peek().text));
  }
  /// Skip to the next statement. `start` is where the failed statement began:
  /// if the error was found at the start of a later statement, that statement
  /// is kept (its own errors get reported too).
  void recover(std::size_t start) {
    if (pos_ == start || !at_statement_start()) next();
    int depth = 0;
    while (!at(Tok::End)) {
      if (at(Tok::LBrace)) ++depth;
      if (at(Tok::RBrace)) {
        if (depth == 0) return;  // the enclosing component's `}`
        --depth;
        next();  // the failed statement's own `}`
        continue;
      }
      if (depth == 0 && (at(Tok::Semi))) { next(); return; }
      if (depth == 0 && at_statement_start()) return;
      next();
    }
  }

  // ---- statements ------------------------------------------------------------
  void statement_into(std::vector<ir::AstStmt>& out, bool in_component) {
    std::size_t start = pos_;
    try {
      out.push_back(statement(in_component));
      accept(Tok::Semi);
    } catch (const ParseError&) {
      recover(start);
    }
  }

  ir::AstStmt statement(bool in_component) {
    const Token& t = peek();
    if (t.kind == Tok::Number && (t.text == "0" || t.text == "1")) return junction();
    if (t.kind != Tok::Ident) {
      fail(fmt::format("expected a statement, found {}", describe(t)),
           "a statement starts with a keyword (param, bond, output, ...), an element kind "
           "(Se Sf I C R TF GY MTF MGY) or a junction (0 or 1)");
    }
    if (kElementKinds.count(t.text)) return element();
    if (t.text == "model") {
      next();
      ir::AstModel m;
      const Token& n = expect(Tok::Ident, "(the model's name) after `model`");
      m.name = n.text;
      m.loc = n.loc;
      return m;
    }
    if (t.text == "import") {
      ir::SourceLoc loc = next().loc;
      const Token& s = expect(Tok::String, "after `import`", "write import \"file.mbg\"");
      (void)loc;
      return ir::AstImport{s.text, s.loc};
    }
    if (t.text == "param") {
      next();
      ir::AstParam p;
      const Token& n = expect(Tok::Ident, "(the parameter's name) after `param`");
      p.name = n.text;
      p.loc = n.loc;
      expect(Tok::Assign, "after the parameter's name", fmt::format("write param {} = value", p.name));
      p.value = expr();
      return p;
    }
    if (t.text == "signal" || t.text == "output") {
      bool is_signal = t.text == "signal";
      next();
      const Token& n = expect(Tok::Ident, is_signal ? "(the signal's name)" : "(the output's name)");
      std::string name = n.text;
      ir::SourceLoc loc = n.loc;
      expect(Tok::Assign, "after the name", fmt::format("write {} {} = expression", is_signal ? "signal" : "output", name));
      AstExprPtr v = expr();
      if (is_signal) return ir::AstSignal{name, loc, v};
      return ir::AstOutput{name, loc, v};
    }
    if (t.text == "bond") return bond();
    if (t.text == "simulate") return simulate();
    if (t.text == "component") {
      if (in_component)
        fail("components cannot be declared inside a component", "declare it at the top level and instantiate it here");
      return component();
    }
    if (t.text == "instance") return instance();
    fail(fmt::format("unknown statement `{}`", t.text),
         "a statement starts with model, import, param, signal, output, bond, simulate, component, "
         "instance, an element kind (Se Sf I C R TF GY MTF MGY) or a junction (0 or 1)");
  }

  ir::AstEndpoint endpoint(const char* what_for) {
    const Token& first = expect(Tok::Ident, what_for);
    ir::AstEndpoint e{first.text, first.loc};
    while (at(Tok::Dot)) {
      next();
      const Token& part = expect(Tok::Ident, "after `.`");
      e.path += "." + part.text;
      e.loc.length = part.loc.col + part.loc.length - e.loc.col;
    }
    return e;
  }

  std::optional<int> dimension(ir::SourceLoc& loc) {
    if (!at(Tok::LBracket)) return std::nullopt;
    next();
    const Token& n = expect(Tok::Number, "(the multibond dimension)");
    loc = n.loc;
    if (n.number < 1 || n.number != static_cast<int>(n.number) || n.number > 10000) {
      diags_.error(n.loc, fmt::format("multibond dimension must be a positive integer, not `{}`", n.text),
                   "write e.g. [3] for a 3-dimensional multibond");
      throw ParseError{};
    }
    expect(Tok::RBracket, "after the dimension");
    return static_cast<int>(n.number);
  }

  ir::AstStmt junction() {
    const Token& kind = next();
    ir::AstJunction j;
    j.type = kind.text[0];
    j.kind_loc = kind.loc;
    const Token& n = expect(Tok::Ident, "(the junction's name)", fmt::format("write {} name", kind.text));
    j.name = n.text;
    j.loc = n.loc;
    j.dim = dimension(j.dim_loc);
    if (accept(Tok::Colon)) {
      if (!at(Tok::Arrow)) {
        j.inputs.push_back(endpoint("(a bond into the junction)"));
        while (accept(Tok::Comma)) j.inputs.push_back(endpoint("after `,`"));
      }
      expect(Tok::Arrow, "between the bonds into and out of the junction",
             fmt::format("write {} {} : into, ... -> out, ...", kind.text, j.name));
      if (at(Tok::Ident) && !at_statement_start_ident()) {
        j.outputs.push_back(endpoint("(a bond out of the junction)"));
        while (accept(Tok::Comma)) j.outputs.push_back(endpoint("after `,`"));
      }
    }
    return j;
  }
  bool at_statement_start_ident() const {
    return at(Tok::Ident) && (kKeywords.count(peek().text) || kElementKinds.count(peek().text));
  }

  ir::AstStmt bond() {
    ir::AstBond b;
    b.loc = next().loc;
    if (at(Tok::Ident) && peek(1).kind == Tok::Colon) {
      b.name = next().text;
      next();
    }
    b.from = endpoint("(where the bond starts)");
    expect(Tok::Arrow, "between the bond's ends", "write bond from -> to (power flows from -> to)");
    b.to = endpoint("(where the bond ends)");
    b.dim = dimension(b.dim_loc);
    return b;
  }

  std::vector<ir::AstAttr> attr_block(const char* what_for) {
    std::vector<ir::AstAttr> attrs;
    expect(Tok::LBrace, what_for);
    while (!at(Tok::RBrace)) {
      if (accept(Tok::Semi) || accept(Tok::Comma)) continue;
      if (at(Tok::End)) fail("missing `}`", "close the block with `}`");
      const Token& k = expect(Tok::Ident, "(a setting name)");
      ir::AstAttr a{k.text, k.loc, nullptr};
      expect(Tok::Assign, "after the setting name", fmt::format("write {} = value", k.text));
      a.value = expr();
      attrs.push_back(std::move(a));
    }
    next();
    return attrs;
  }

  ir::AstStmt element() {
    const Token& kind = next();
    ir::AstElement e;
    e.kind = kind.text;
    e.kind_loc = kind.loc;
    const Token& n = expect(Tok::Ident, "(the element's name)", fmt::format("write {} name = value", kind.text));
    e.name = n.text;
    e.loc = n.loc;
    if (accept(Tok::Assign)) e.value = expr();
    if (at(Tok::LBrace)) e.attrs = attr_block("");
    return e;
  }

  ir::AstStmt simulate() {
    ir::AstSimulate s;
    s.loc = next().loc;
    s.settings = attr_block("after `simulate`");
    return s;
  }

  ir::AstStmt component() {
    next();
    auto c = std::make_shared<ir::AstComponent>();
    const Token& n = expect(Tok::Ident, "(the component's name)");
    c->name = n.text;
    c->loc = n.loc;
    expect(Tok::LParen, "after the component's name", "write component name(port a, param k = 1) { ... }");
    while (!at(Tok::RParen)) {
      if (at_ident("port")) {
        next();
        const Token& p = expect(Tok::Ident, "(the port's name)");
        c->ports.push_back({p.text, p.loc});
      } else if (at_ident("param")) {
        next();
        const Token& p = expect(Tok::Ident, "(the parameter's name)");
        ir::AstParam par{p.text, p.loc, nullptr};
        if (accept(Tok::Assign)) par.value = expr();
        c->params.push_back(std::move(par));
      } else {
        fail(fmt::format("expected `port` or `param` in the component's interface, found {}", describe(peek())),
             "write component name(port a, param k = 1)");
      }
      if (!accept(Tok::Comma)) break;
    }
    expect(Tok::RParen, "to close the component's interface");
    expect(Tok::LBrace, "to open the component's body");
    while (!at(Tok::RBrace)) {
      if (at(Tok::End)) fail(fmt::format("missing `}}` at the end of component `{}`", c->name), "close the body with `}`");
      if (accept(Tok::Semi)) continue;
      statement_into(c->body, /*in_component=*/true);
    }
    next();
    return c;
  }

  ir::AstStmt instance() {
    next();
    ir::AstInstance in;
    const Token& n = expect(Tok::Ident, "(the instance's name)");
    in.name = n.text;
    in.loc = n.loc;
    expect(Tok::Assign, "after the instance's name", "write instance name = component(port = node, k = 2)");
    const Token& c = expect(Tok::Ident, "(the component to instantiate)");
    in.component = c.text;
    in.component_loc = c.loc;
    expect(Tok::LParen, "after the component's name");
    while (!at(Tok::RParen)) {
      const Token& k = expect(Tok::Ident, "(a port or parameter name)");
      ir::AstAttr a{k.text, k.loc, nullptr};
      expect(Tok::Assign, "after the argument's name", fmt::format("write {} = value", k.text));
      a.value = expr();
      in.args.push_back(std::move(a));
      if (!accept(Tok::Comma)) break;
    }
    expect(Tok::RParen, "to close the instance's arguments");
    return in;
  }

  // ---- expressions -------------------------------------------------------------
  static AstExprPtr make(AstExpr::Kind k, ir::SourceLoc loc) {
    auto e = std::make_shared<AstExpr>();
    e->kind = k;
    e->loc = loc;
    return e;
  }
  static AstExprPtr binary(char op, ir::SourceLoc loc, AstExprPtr a, AstExprPtr b) {
    auto e = std::make_shared<AstExpr>();
    e->kind = AstExpr::Kind::Binary;
    e->loc = loc;
    e->op = op;
    e->args = {std::move(a), std::move(b)};
    return e;
  }

  AstExprPtr expr() {
    if (++depth_ > 200) fail("expression nested too deeply", "split it into parameters or signals");
    AstExprPtr lhs = product();
    while (at(Tok::Plus) || at(Tok::Minus)) {
      const Token& op = next();
      lhs = binary(op.text[0], op.loc, lhs, product());
    }
    --depth_;
    return lhs;
  }
  AstExprPtr product() {
    AstExprPtr lhs = unary();
    while (at(Tok::Star) || at(Tok::Slash)) {
      const Token& op = next();
      lhs = binary(op.text[0], op.loc, lhs, unary());
    }
    return lhs;
  }
  AstExprPtr unary() {
    if (at(Tok::Minus) || at(Tok::Plus)) {
      if (++depth_ > 200) fail("expression nested too deeply", "split it into parameters or signals");
      const Token& op = next();
      auto e = std::make_shared<AstExpr>();
      e->kind = AstExpr::Kind::Unary;
      e->loc = op.loc;
      e->op = op.text[0];
      e->args = {unary()};
      --depth_;
      return e;
    }
    return power();
  }
  AstExprPtr power() {
    AstExprPtr base = postfix();
    if (at(Tok::Caret)) {
      const Token& op = next();
      if (++depth_ > 200) fail("expression nested too deeply", "split it into parameters or signals");
      AstExprPtr exponent = unary();  // right-associative: a^b^c = a^(b^c); a^-1 allowed
      --depth_;
      return binary('^', op.loc, base, exponent);
    }
    return base;
  }
  AstExprPtr postfix() {
    AstExprPtr e = primary();
    while (at(Tok::LBracket)) {
      ir::SourceLoc loc = next().loc;
      auto idx = make(AstExpr::Kind::Index, loc);
      auto m = std::const_pointer_cast<AstExpr>(idx);
      m->args.push_back(e);
      m->args.push_back(expr());
      if (accept(Tok::Comma)) m->args.push_back(expr());
      expect(Tok::RBracket, "to close the index");
      e = idx;
    }
    return e;
  }
  AstExprPtr primary() {
    const Token& t = peek();
    if (t.kind == Tok::Number) {
      next();
      auto e = std::make_shared<AstExpr>();
      e->kind = AstExpr::Kind::Number;
      e->loc = t.loc;
      e->number = t.number;
      return e;
    }
    if (t.kind == Tok::Ident) {
      // `R load` here means the previous line's expression is unfinished.
      bool starts_line = pos_ > 0 && toks_[pos_ - 1].loc.line != t.loc.line;
      if (starts_line && (kKeywords.count(t.text) || kElementKinds.count(t.text)) && peek(1).kind == Tok::Ident)
        fail(fmt::format("expected an expression, found the start of a statement (`{} {}`)", t.text, peek(1).text),
             "the expression before it is incomplete");
      ir::AstEndpoint path = endpoint("");
      if (at(Tok::LParen)) {
        next();
        auto e = std::make_shared<AstExpr>();
        e->kind = AstExpr::Kind::Call;
        e->loc = path.loc;
        e->name = path.path;
        while (!at(Tok::RParen)) {
          e->args.push_back(expr());
          if (!accept(Tok::Comma)) break;
        }
        expect(Tok::RParen, fmt::format("to close the call of `{}`", path.path).c_str());
        return e;
      }
      auto e = std::make_shared<AstExpr>();
      e->kind = AstExpr::Kind::Name;
      e->loc = path.loc;
      e->name = path.path;
      return e;
    }
    if (t.kind == Tok::LParen) {
      next();
      AstExprPtr e = expr();
      expect(Tok::RParen, "to close `(`");
      return e;
    }
    if (t.kind == Tok::LBracket) {
      next();
      auto e = std::make_shared<AstExpr>();
      e->kind = AstExpr::Kind::List;
      e->loc = t.loc;
      while (!at(Tok::RBracket)) {
        e->args.push_back(expr());
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::RBracket, "to close the list", "write vectors as [a, b, c] and matrices as [[a, b], [c, d]]");
      return e;
    }
    fail(fmt::format("expected an expression, found {}", describe(t)),
         "an expression is a number, a name, a call like sin(x), or (...)");
  }

  std::vector<Token> toks_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  ir::Diagnostics& diags_;
};

}  // namespace

const std::set<std::string>& statement_keywords() { return kKeywords; }
const std::set<std::string>& element_kinds() { return kElementKinds; }

ir::AstProgram parse_source(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags) {
  int errors_before = diags.error_count();
  std::vector<Token> toks = lex(sources, file_id, diags);
  if (diags.error_count() > errors_before) return {};  // parsing around bad characters only adds noise
  Parser p(std::move(toks), diags);
  return p.program();
}

namespace {

bool read_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  text = ss.str();
  return true;
}

void load_into(const std::string& path, const ir::SourceLoc& imported_at, ir::SourceManager& sources,
               ir::Diagnostics& diags, std::set<std::string>& seen, std::vector<std::string>& stack,
               ir::AstProgram& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::string canonical = fs::weakly_canonical(fs::path(path), ec).string();
  if (ec) canonical = path;
  for (const std::string& open : stack) {
    if (open == canonical) {
      diags.error(imported_at, fmt::format("import cycle: `{}` imports itself (through other files)", path),
                  "remove one of the imports; a file is included once");
      return;
    }
  }
  if (seen.count(canonical)) return;  // imported once already
  seen.insert(canonical);
  std::string text;
  if (!read_file(path, text)) {
    diags.error(imported_at, fmt::format("cannot read `{}`", path),
                imported_at.valid() ? "the path is relative to the importing file" : "check the file name");
    return;
  }
  int id = sources.add(path, std::move(text));
  ir::AstProgram prog = parse_source(sources, id, diags);
  stack.push_back(canonical);
  for (ir::AstStmt& s : prog.stmts) {
    if (auto* imp = std::get_if<ir::AstImport>(&s)) {
      fs::path base = fs::path(path).parent_path();
      std::string target = (base / imp->path).lexically_normal().string();
      load_into(target, imp->loc, sources, diags, seen, stack, out);
      continue;
    }
    out.stmts.push_back(std::move(s));
  }
  stack.pop_back();
}

}  // namespace

ir::AstProgram load_program(const std::string& path, ir::SourceManager& sources, ir::Diagnostics& diags) {
  ir::AstProgram out;
  std::set<std::string> seen;
  std::vector<std::string> stack;
  load_into(path, ir::SourceLoc{}, sources, diags, seen, stack, out);
  return out;
}

}  // namespace mbgc::parse
