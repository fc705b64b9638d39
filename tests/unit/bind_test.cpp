// Binding: the multibody layer refers to what it writes by symbol, never by
// a name; resolve binds names and symbols to what declares them; a symbol no
// statement declares is the compiler's mistake, reported as one.
#include <gtest/gtest.h>

#include <cctype>
#include <map>
#include <set>
#include <string>
#include <variant>

#include "elaborate/unroll.hpp"
#include "ir/term.hpp"
#include "multibody/expand.hpp"
#include "pipeline.hpp"

namespace {

namespace ir = mbgc::ir;
using mbgc_test::Compiled;

/// The refs of `t` and its sub-terms, by kind.
void count_refs(const ir::TermPtr& t, std::map<ir::Ref::Kind, int>& out, std::set<int>& symbols,
                std::set<std::string>& names) {
  if (!t) return;
  if (t->kind == ir::Term::Kind::Ref) {
    ++out[t->ref.kind];
    if (t->ref.kind == ir::Ref::Kind::Name) names.insert(t->name);
    if (t->ref.kind == ir::Ref::Kind::Symbol) symbols.insert(t->ref.id);
  }
  for (const ir::TermPtr& a : t->args) count_refs(a, out, symbols, names);
}

/// What the statements of `program` refer to: the layer's (generated) and the user's, apart.
struct Refs {
  std::map<ir::Ref::Kind, int> generated, user;
  std::set<int> symbols;              // read by the generated statements
  std::set<std::string> names;        // the names they read: those of the user's expressions they carry
  std::map<int, int> declarations;    // symbol -> how many statements declare it
  std::vector<int> ends;              // the symbols of the bonds' ends the layer wrote (-1: by name)
};

Refs refs_of(const ir::ExpandedProgram& program) {
  Refs r;
  for (const ir::ExpandedStmt& s : program.stmts)
    std::visit(
        [&](const auto& st) {
          using T = std::decay_t<decltype(st)>;
          std::vector<ir::TermPtr> terms;
          bool generated = false;
          if constexpr (requires { st.symbol; })
            if (st.symbol >= 0) ++r.declarations[st.symbol];
          if constexpr (std::is_same_v<T, ir::ExpandedParam>) terms = {st.value}, generated = st.generated;
          if constexpr (std::is_same_v<T, ir::ExpandedSignal>) terms = {st.value, st.rate}, generated = st.generated;
          if constexpr (std::is_same_v<T, ir::ExpandedOutput>) terms = {st.value, st.modes}, generated = st.drawing != nullptr;
          if constexpr (std::is_same_v<T, ir::ExpandedElement>) {
            generated = st.generated;
            terms.push_back(st.value);
            for (const ir::TermAttr& a : st.attrs) terms.push_back(a.value);
            if (st.constraint)
              for (const auto& f : ir::ConstraintLaw::fields()) terms.push_back((*st.constraint).*f.member);
          }
          std::set<std::string> user_names;
          if constexpr (std::is_same_v<T, ir::ExpandedJunction>)
            if (st.generated)
              for (const auto* ends : {&st.inputs, &st.outputs})
                for (const ir::ExpandedEnd& e : *ends) r.ends.push_back(e.symbol);
          if constexpr (std::is_same_v<T, ir::ExpandedBond>) {
            const bool layer = st.from.symbol >= 0 || st.to.symbol >= 0;  // (a user's bond has neither)
            if (layer) r.ends.insert(r.ends.end(), {st.from.symbol, st.to.symbol});
          }
          for (const ir::TermPtr& t : terms) count_refs(t, generated ? r.generated : r.user, r.symbols, generated ? r.names : user_names);
        },
        s);
  return r;
}

std::unique_ptr<Compiled> expand_file(const std::string& path, ir::ExpandedProgram& out) {
  auto c = std::make_unique<Compiled>();
  c->ast = mbgc::parse::load_program(path, c->sources, c->diags);
  if (c->ok()) c->ast = mbgc::elaborate::unroll_loops(c->ast, {}, c->diags);
  if (c->ok()) out = mbgc::multibody::expand(c->ast, c->sources, c->diags, {});
  return c;
}

/// Whether `name` is a whole name in `text`.
bool written_in(const std::string& text, const std::string& name) {
  auto part = [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.'; };
  for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1))
    if ((at == 0 || !part(text[at - 1])) && (at + name.size() >= text.size() || !part(text[at + name.size()]))) return true;
  return false;
}

TEST(Bind, TheMultibodyLayerRefersToWhatItWritesBySymbolsNeverByName) {
  // a pendulum, joint coordinates and cut joints, a flexible beam, a contact, tyres
  for (const char* model : {"pendulum/pendulum.mbg", "crank_rocker/crank_rocker.mbg", "rotating_beam/rotating_beam.mbg",
                            "bouncing_ball/bouncing_ball.mbg", "two_track/two_track.mbg"}) {
    SCOPED_TRACE(model);
    ir::ExpandedProgram program;
    auto c = expand_file(std::string(MBGC_SOURCE_DIR "/examples/") + model, program);
    ASSERT_TRUE(c->ok()) << c->messages();
    const Refs r = refs_of(program);
    // a name in what the layer wrote is one the user wrote (a body's `mass = m`), never one of the layer's own
    const std::string user_text = ir::print_ast(c->ast);
    for (const std::string& name : r.names) EXPECT_TRUE(written_in(user_text, name)) << "the layer wrote the name `" << name << "`";
    EXPECT_GT(r.generated.at(ir::Ref::Kind::Symbol), 10);
    // and its bonds join what it declared, by symbol
    EXPECT_GE(r.ends.size(), 8u);
    for (int s : r.ends) EXPECT_TRUE(s >= 0 && r.declarations.count(s)) << "a bond of the layer's ends at a name";
    for (int s : r.symbols) {
      ASSERT_LT(s, static_cast<int>(program.symbols.size()));
      EXPECT_EQ(r.declarations.count(s) ? r.declarations.at(s) : 0, 1) << "`" << program.symbols[static_cast<std::size_t>(s)]
                                                                        << "` is read but not declared once";
    }
  }
}

TEST(Bind, AUsersNamesStayNamesUntilResolveBindsThem) {
  ir::ExpandedProgram program;
  auto c = expand_file(MBGC_SOURCE_DIR "/examples/dc_motor/dc_motor.mbg", program);
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_GT(refs_of(program).user[ir::Ref::Kind::Name], 0);
  ir::ResolvedModel m = mbgc::sema::resolve(program, "dc_motor.mbg", c->diags);
  ASSERT_TRUE(c->ok()) << c->messages();
  std::map<ir::Ref::Kind, int> bound;
  std::set<int> none;
  std::set<std::string> names;
  for (const ir::ResolvedExpr& o : m.outputs) count_refs(o.expr, bound, none, names);
  for (const ir::ResolvedExpr& s : m.signals) count_refs(s.expr, bound, none, names);
  for (const ir::ResolvedNode& n : m.nodes)
    if (n.element) count_refs(n.element->value, bound, none, names);
  EXPECT_EQ(bound.count(ir::Ref::Kind::Name), 0u);
  EXPECT_EQ(bound.count(ir::Ref::Kind::Symbol), 0u);
  EXPECT_GT(bound[ir::Ref::Kind::Node], 0);
  EXPECT_GT(bound[ir::Ref::Kind::Param], 0);
}

/// A program of one output that reads `ref`, after the statements `decls`.
ir::ExpandedProgram reading(ir::Ref ref, std::vector<ir::ExpandedStmt> decls, std::vector<std::string> symbols) {
  ir::ExpandedProgram p;
  p.stmts = std::move(decls);
  auto t = std::make_shared<ir::Term>();
  t->kind = ir::Term::Kind::Ref;
  t->ref = ref;
  t->name = "shown";
  p.stmts.push_back(ir::ExpandedOutput{"y", {}, t, std::nullopt, nullptr, nullptr});
  p.symbols = std::move(symbols);
  return p;
}

TEST(Bind, ASymbolNothingDeclaresIsAnInternalErrorNotADiagnostic) {
  Compiled c;
  const ir::ExpandedProgram p = reading({ir::Ref::Kind::Symbol, 0, ir::Quantity::value}, {}, {"ghost"});
  try {
    mbgc::sema::resolve(p, "test.mbg", c.diags);
    FAIL() << "no internal error";
  } catch (const ir::InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("`ghost`, which it did not declare"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(c.ok());  // nothing is the user's to fix
}

TEST(Bind, AVariableItsNodeHasNotIsAnInternalError) {
  Compiled c;
  ir::ExpandedJunction j;
  j.type = '0';
  j.name = "j";
  j.symbol = 0;
  // a 0-junction has one effort, no flow of its own
  const ir::ExpandedProgram p = reading({ir::Ref::Kind::Symbol, 0, ir::Quantity::f}, {j}, {"j"});
  EXPECT_THROW(mbgc::sema::resolve(p, "test.mbg", c.diags), ir::InternalError);
  const ir::ExpandedProgram ok = reading({ir::Ref::Kind::Symbol, 0, ir::Quantity::e}, {j}, {"j"});
  const ir::ResolvedModel m = mbgc::sema::resolve(ok, "test.mbg", c.diags);
  ASSERT_EQ(m.outputs.size(), 1u);
  EXPECT_EQ(m.outputs[0].expr->ref.kind, ir::Ref::Kind::Node);
  EXPECT_EQ(m.outputs[0].expr->ref.quantity, ir::Quantity::e);
}

}  // namespace
