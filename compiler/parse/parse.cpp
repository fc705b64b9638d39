// Recursive-descent parser for grammar/mbg.ebnf. Statements need no
// terminator (`;` is optional): every statement starts with a keyword, an
// element kind or a junction type, so the next statement is always
// recognisable. On an error we report it and skip to the next statement start.
// Expressions, names and units are read by parse/expression.hpp, tokens
// looked at through parse/cursor.hpp.
#include "parse/parse.hpp"

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <set>

#include "ir/find_file.hpp"
#include "parse/expression.hpp"
#include "parse/lexer.hpp"

namespace mbgc::parse {
namespace {

using ir::AstExpr;
using ir::AstExprPtr;

const std::set<std::string> kNotInLoop = {"model", "import", "component", "simulate", "scene"};
constexpr int kMaxLoopNesting = 64;

class Parser : private ExpressionParser {
 public:
  using ExpressionParser::ExpressionParser;

  ir::AstProgram program() {
    ir::AstProgram p;
    while (!at(Tok::End)) {
      if (accept(Tok::Semi)) continue;
      statement_into(p.stmts, /*in_component=*/false);
    }
    return p;
  }

 private:
  /// Skip to the next statement. `start` is where the failed statement began:
  /// if the error was found at the start of a later statement, that statement
  /// is kept (its own errors get reported too). `open_blocks` of the failed
  /// statement's `{` are not closed yet: the next `}`s are its own.
  void recover(std::size_t start, int open_blocks) {
    // A `{` where the error was found opens the failed statement's block: it is counted below.
    if (pos_ == start || (!at_statement_start() && !at(Tok::LBrace))) next();
    int depth = open_blocks;
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
    int blocks = block_depth_;
    try {
      out.push_back(statement(in_component));
      accept(Tok::Semi);
    } catch (const ParseError&) {
      depth_ = 0;  // statements are never inside expressions
      units_here_ = true;
      int open_blocks = block_depth_ - blocks;
      block_depth_ = blocks;
      recover(start, open_blocks);
    }
  }

  ir::AstStmt statement(bool in_component) {
    const Token& t = peek();
    if (t.kind == Tok::Number && (t.text == "0" || t.text == "1")) return junction();
    if (t.kind != Tok::Ident) {
      fail(fmt::format("expected a statement, found {}", describe(t)),
           "a statement starts with a keyword (param, bond, output, body, joint, for, ...), an element kind "
           "(Se Sf I C R TF GY MTF MGY CN) or a junction (0 or 1)");
    }
    if (element_kinds().count(t.text)) return element();
    if (for_depth_ > 0 && t.text == "scene")
      fail("`scene` cannot appear inside a for loop",
           "a scene is chosen before the loops are unrolled (it may fix their bounds, as --set does): declare it at "
           "the top level; its outputs may name what a loop declares, e.g. outputs = [q1, q2]");
    if (for_depth_ > 0 && kNotInLoop.count(t.text))
      fail(fmt::format("`{}` cannot appear inside a for loop", t.text),
           "move it out of the loop; a loop repeats the statements that build the model "
           "(elements, junctions, bonds, bodies, joints, parameters, outputs, ...)");
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
      Name n = name("(the parameter's name) after `param`");
      p.name = n.text;
      p.loc = n.loc;
      expect(Tok::Assign, "after the parameter's name", fmt::format("write param {} = value", p.name));
      p.value = expr();
      p.unit = declared_unit(p.value);
      return p;
    }
    if (t.text == "signal" || t.text == "output") {
      bool is_signal = t.text == "signal";
      next();
      Name n = name(is_signal ? "(the signal's name)" : "(the output's name)");
      expect(Tok::Assign, "after the name", fmt::format("write {} {} = expression", is_signal ? "signal" : "output", n.text));
      AstExprPtr v = expr();
      std::optional<ir::AstUnit> u = declared_unit(v);
      if (is_signal) return ir::AstSignal{n.text, n.loc, v, u};
      return ir::AstOutput{n.text, n.loc, v, u};
    }
    if (t.text == "bond") return bond();
    if (t.text == "simulate") return simulate();
    if (t.text == "scene") {
      if (in_component)
        fail("a scene cannot be declared inside a component", "declare scenes at the top level of the model");
      return scene();
    }
    if (t.text == "component") {
      if (in_component)
        fail("components cannot be declared inside a component", "declare it at the top level and instantiate it here");
      return component();
    }
    if (t.text == "instance") return instance();
    if (t.text == "body" || t.text == "ground") return body();
    if (t.text == "joint") return joint();
    if (t.text == "force") return connector(ir::Connector::Force);
    if (t.text == "contact") return connector(ir::Connector::Contact);
    if (t.text == "tyre") return connector(ir::Connector::Tyre);
    if (t.text == "gravity" || t.text == "constraints") return setting();
    if (t.text == "for") return for_loop(in_component);
    if (t.text == "point")
      fail("`point` belongs inside a body or ground block",
           "write body name { point p = [x, y, z] } or ground { point p = [x, y, z] }");
    const std::string starts =
        "a statement starts with model, import, param, signal, output, bond, simulate, scene, component, instance, "
        "body, ground, joint, force, contact, tyre, gravity, constraints, for, an element kind (Se Sf I C R TF GY MTF MGY CN) "
        "or a junction (0 or 1)";
    std::vector<std::string> words(statement_keywords().begin(), statement_keywords().end());
    std::string near = ir::closest_name(t.text, words);
    fail(fmt::format("unknown statement `{}`", t.text),
         near.empty() ? starts : fmt::format("did you mean `{}`?", near));
  }


  std::optional<int> dimension(ir::SourceLoc& loc) {
    if (!at(Tok::LBracket)) return std::nullopt;
    next();
    const Token& n = expect(Tok::Number, "(the multibond dimension)");
    loc = n.loc;
    // Range first: converting a double beyond int's range is undefined (fuzz_parse found `[5…5]`).
    if (!(n.number >= 1 && n.number <= 10000) || n.number != std::floor(n.number)) {
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
    Name n = name("(the junction's name)", fmt::format("write {} name", kind.text));
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
      if (at(Tok::Ident) && !statement_word()) {
        j.outputs.push_back(endpoint("(a bond out of the junction)"));
        while (accept(Tok::Comma)) j.outputs.push_back(endpoint("after `,`"));
      }
    }
    return j;
  }

  ir::AstStmt bond() {
    ir::AstBond b;
    b.loc = next().loc;
    if (at(Tok::Ident)) {  // `bond name: ...`? (a name may interpolate, so look past it)
      std::size_t from = pos_;
      Name n = name("");
      if (accept(Tok::Colon)) b.name = n.text;
      else pos_ = from;
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
    ++block_depth_;
    while (!at(Tok::RBrace)) {
      if (accept(Tok::Semi) || accept(Tok::Comma)) continue;
      if (at(Tok::End)) fail("missing `}`", "close the block with `}`");
      attrs.push_back(attr());
    }
    next();
    --block_depth_;
    return attrs;
  }
  /// `key = expression`
  ir::AstAttr attr() {
    const Token& k = expect(Tok::Ident, "(a setting name)");
    ir::AstAttr a{k.text, k.loc, nullptr};
    expect(Tok::Assign, "after the setting name", fmt::format("write {} = value", k.text));
    a.value = expr();
    return a;
  }

  ir::AstStmt element() {
    const Token& kind = next();
    ir::AstElement e;
    e.kind = kind.text;
    e.kind_loc = kind.loc;
    Name n = name("(the element's name)", fmt::format("write {} name = value", kind.text));
    e.name = n.text;
    e.loc = n.loc;
    if (accept(Tok::Assign)) e.value = expr();
    if (at(Tok::LBrace)) e.attrs = attr_block("");
    return e;
  }

  ir::AstStmt scene() {
    next();
    ir::AstScene s;
    Name n = name("(the scene's name) after `scene`", "write scene name { outputs = [a, b] }");
    s.name = n.text;
    s.loc = n.loc;
    s.attrs = attr_block("after the scene's name");
    return s;
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
        ir::AstParam par{p.text, p.loc, nullptr, std::nullopt};
        if (accept(Tok::Assign)) par.value = expr();
        par.unit = declared_unit(par.value);
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
    Name n = name("(the instance's name)");
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

  // ---- the multibody layer ----------------------------------------------------------
  /// `body name { mass = m; point tip = [...] }` or `ground { point pivot = [...] }`.
  ir::AstStmt body() {
    const Token& kw = next();
    const bool ground = kw.text == "ground";
    const char* form = ground ? "write ground { point p = [x, y, z] }" : "write body name { mass = m; point p = [x, y, z] }";
    ir::AstBody b;
    b.kind_loc = kw.loc;
    if (ground) {
      b.name = "ground";
      b.loc = kw.loc;
    } else {
      Name n = name("(the body's name) after `body`", form);
      if (n.text == "ground") {
        diags_.error(n.loc, "`ground` is the fixed frame, not a body", "give its points with ground { point p = [x, y, z] }");
        throw ParseError{};
      }
      b.name = n.text;
      b.loc = n.loc;
    }
    expect(Tok::LBrace, ground ? "after `ground`" : "after the body's name", form);
    ++block_depth_;
    while (!at(Tok::RBrace)) {
      if (accept(Tok::Semi) || accept(Tok::Comma)) continue;
      const std::string owner = ground ? "`ground`" : fmt::format("body `{}`", b.name);
      if (at_ident("for") && peek(1).kind == Tok::Ident) {  // before the check below: `for i` also starts a statement
        b.loops.push_back(point_loop(b.points.size(), owner, block_depth_ - 1));
        continue;
      }
      if (at(Tok::End) || new_statement_here()) {
        --block_depth_;  // given up: recovery resumes at this statement
        fail(fmt::format("missing `}}` at the end of {}", owner), "close the block with `}`");
      }
      if (at_ident("point") && peek(1).kind == Tok::Ident) {
        b.points.push_back(point());
      } else {
        b.attrs.push_back(attr());
      }
    }
    next();
    --block_depth_;
    return b;
  }

  /// `point name = [x, y, z]` in a body or ground block (at `point`).
  ir::AstPoint point() {
    next();
    Name p = name("(the point's name)");
    expect(Tok::Assign, "after the point's name", fmt::format("write point {} = [x, y, z]", p.text));
    return {p.text, p.loc, expr()};
  }

  /// `for i in from..to { point p{i} = [...] }` inside the block of `owner`
  /// (a body or ground): points and nested loops of points. `position` is the
  /// number of the enclosing list's points before it; `outside` the number of
  /// open blocks outside the owner's, for recovery at a statement.
  std::shared_ptr<ir::AstPointFor> point_loop(std::size_t position, const std::string& owner, int outside) {
    const char* form = "write for i in 1..N { point p{i} = [x, y, z] }";
    auto f = std::make_shared<ir::AstPointFor>();
    f->position = position;
    loop_header(*f, form);
    ++block_depth_;
    ++for_depth_;
    struct Leave {
      int& depth;
      ~Leave() { --depth; }
    } leave{for_depth_};
    while (!at(Tok::RBrace)) {
      if (accept(Tok::Semi) || accept(Tok::Comma)) continue;
      if (at(Tok::End))
        fail(fmt::format("missing `}}` at the end of the for loop over `{}`", f->var), "close the loop with `}`");
      if (at_ident("for") && peek(1).kind == Tok::Ident) {
        f->loops.push_back(point_loop(f->points.size(), owner, outside));
      } else if (at_ident("point") && peek(1).kind == Tok::Ident) {
        f->points.push_back(point());
      } else if (new_statement_here()) {
        block_depth_ = outside;  // given up: recovery resumes at this statement
        fail(fmt::format("a for loop inside {} repeats points only, found the statement `{} {}`", owner, peek().text,
                         peek(1).text),
             fmt::format("if {} is unfinished, close its block and the loop with `}}` before this line", owner));
      } else if (at(Tok::Ident) && peek(1).kind == Tok::Assign) {
        fail(fmt::format("a for loop inside {} repeats points only, found the setting `{}`", owner, peek().text),
             "a setting is given once: move it out of the loop, into the block");
      } else {
        fail(fmt::format("a for loop inside {} repeats points only, found {}", owner, describe(peek())), form);
      }
    }
    next();
    --block_depth_;
    return f;
  }

  /// `joint name type(a, b) { key = value ... }`
  ir::AstStmt joint() {
    const char* form = "write joint name revolute(body_a.point, body_b.point)";
    ir::AstJoint j;
    j.kind_loc = next().loc;
    Name n = name("(the joint's name) after `joint`", form);
    j.name = n.text;
    j.loc = n.loc;
    if (at(Tok::LParen))  // `joint revolute(a, b)` or `joint j (a, b)`: the name or the type is missing
      fail(fmt::format("expected the joint's type after `joint {}`, found `(`", j.name),
           "a joint has a name and a type: joint NAME TYPE(a, b), e.g. joint j1 revolute(ground.pivot, arm.a)");
    const Token& type = expect(Tok::Ident, "(the joint's type)", form);
    j.type = type.text;
    j.type_loc = type.loc;
    if (j.type == "force" || j.type == "contact" || j.type == "tyre") {
      diags_.error(type.loc, fmt::format("`{}` is not a joint type", j.type),
                   fmt::format("a {} is a statement of its own: {} name(body_a.point, body_b.point) {{ ... }}",
                               j.type == "force" ? "force element" : j.type, j.type));
      throw ParseError{};
    }
    expect(Tok::LParen, fmt::format("after the joint's type `{}`", j.type).c_str(), form);
    j.a = endpoint("(the joint's first endpoint)");
    expect(Tok::Comma, "between the joint's two endpoints", "a joint connects two points: " + std::string(form));
    j.b = endpoint("(the joint's second endpoint)");
    expect(Tok::RParen, "after the joint's endpoints", form);
    if (at(Tok::LBrace)) j.attrs = attr_block("");
    return j;
  }

  /// `force name(a, b) { key = value ... }`, `contact name(a, b) { ... }` and
  /// `tyre name(wheel.centre, ground) { ... }`: joints without a type (same
  /// endpoints and settings shape).
  ir::AstStmt connector(ir::Connector kind) {
    const bool force = kind == ir::Connector::Force, tyre = kind == ir::Connector::Tyre;
    const char* what = ir::connector_noun(kind);
    const std::string form = force  ? "write force name(body_a.point, body_b.point) { force = [fx, fy, fz] }"
                             : tyre ? "write tyre name(wheel.centre, ground) { UNLOADED_RADIUS = 0.3 }"
                                    : "write contact name(ball.centre, ground.floor) { radius = 0.1; normal = [0, 0, 1] }";
    ir::AstJoint f;
    f.connector = kind;
    f.kind_loc = next().loc;
    Name n = name(fmt::format("(the {}'s name) after `{}`", what, ir::connector_keyword(kind)).c_str(), form);
    f.name = n.text;
    f.loc = n.loc;
    f.type_loc = f.kind_loc;
    expect(Tok::LParen, fmt::format("after the {}'s name", what).c_str(), form);
    f.a = endpoint(force  ? "(the first point: the reaction acts here)"
                   : tyre ? "(the wheel's centre: a point on the wheel's axle)"
                          : "(the touching point: a sphere of `radius` around it)");
    expect(Tok::Comma, fmt::format("between the {}'s two points", what).c_str(), form);
    f.b = endpoint(force  ? "(the second point: the force acts here)"
                   : tyre ? "(the road: ground)"
                          : "(the surface's point: the plane, sphere or cylinder goes through it)");
    expect(Tok::RParen, fmt::format("after the {}'s points", what).c_str(), form);
    if (at(Tok::LBrace)) f.attrs = attr_block("");
    return f;
  }

  /// `gravity = expression` or `constraints = method`.
  ir::AstStmt setting() {
    const Token& k = next();
    ir::AstSetting s{k.text, k.loc, nullptr};
    const char* form = k.text == "gravity" ? "write gravity = [0, -9.81, 0]"
                                           : "write constraints = lagrange or constraints = penalty";
    expect(Tok::Assign, fmt::format("after `{}`", k.text).c_str(), form);
    if (k.text == "gravity") {
      s.value = expr();
    } else {
      const Token& v = expect(Tok::Ident, "(the constraint method)", form);
      auto e = std::make_shared<AstExpr>();
      e->kind = AstExpr::Kind::Name;
      e->loc = v.loc;
      e->name = v.text;
      s.value = e;
    }
    return s;
  }

  /// `for i in from..to {` (at `for`) into a statement loop or a loop of points.
  template <class Loop>
  void loop_header(Loop& f, const char* form) {
    f.loc = next().loc;
    if (for_depth_ >= kMaxLoopNesting) {
      diags_.error(f.loc, fmt::format("for loops nested more than {} deep", kMaxLoopNesting),
                   "use fewer levels of loops");
      throw ParseError{};
    }
    f.var = expect(Tok::Ident, "(the loop variable) after `for`", form).text;
    if (!at_ident("in")) fail(fmt::format("expected `in` after the loop variable, found {}", describe(peek())), form);
    next();
    units_here_ = false;  // `1..3 {` opens the body
    f.from = expr();
    expect(Tok::DotDot, "between the loop's bounds", form);
    f.to = expr();
    units_here_ = true;
    expect(Tok::LBrace, "to open the loop's body", form);
  }

  /// `for i in from..to { statements }`
  ir::AstStmt for_loop(bool in_component) {
    const char* form = "write for i in 1..N { ... }";
    auto f = std::make_shared<ir::AstFor>();
    loop_header(*f, form);
    ++for_depth_;
    struct Leave {
      int& depth;
      ~Leave() { --depth; }
    } leave{for_depth_};
    while (!at(Tok::RBrace)) {
      if (at(Tok::End)) fail(fmt::format("missing `}}` at the end of the for loop over `{}`", f->var), "close the body with `}`");
      if (accept(Tok::Semi)) continue;
      statement_into(f->body, in_component);
    }
    next();
    return f;
  }

  int block_depth_ = 0;  // open { } of settings and body blocks (for recovery)
};

}  // namespace

ir::AstProgram parse_source(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags) {
  int errors_before = diags.error_count();
  std::vector<Token> toks = lex(sources, file_id, diags);
  if (diags.error_count() > errors_before) return {};  // parsing around bad characters only adds noise
  Parser p(std::move(toks), diags);
  return p.program();
}

namespace {

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
  std::uintmax_t bytes = 0;
  const ir::ReadStatus status = ir::read_text_file(path, text, bytes);
  if (status == ir::ReadStatus::Unreadable) {
    diags.error(imported_at, fmt::format("cannot read `{}`", path),
                imported_at.valid() ? "the path is relative to the importing file" : "check the file name");
    return;
  }
  if (status == ir::ReadStatus::TooLarge) {
    diags.error(imported_at, ir::too_large_message(path, bytes),
                "is this the model you meant? Models this large are not written by hand");
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
