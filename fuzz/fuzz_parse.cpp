// fuzz_parse — the lexer and the parser alone. Any bytes must give an AST or
// diagnostics, each rendered with its line and caret; never a crash, a
// sanitizer report or a hang (libFuzzer's -timeout).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_check.hpp"
#include "ir/print.hpp"
#include "parse/parse.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mbgc::ir::SourceManager sources;
  const int id = sources.add("fuzz.mbg", std::string(reinterpret_cast<const char*>(data), size));
  mbgc::ir::Diagnostics diags(sources);
  const mbgc::ir::AstProgram ast = mbgc::parse::parse_source(sources, id, diags);
  std::ostringstream rendered;
  diags.render(rendered);
  mbgc::fuzz::check_diagnostics(diags, rendered.str());
  if (!diags.has_errors()) (void)mbgc::ir::print_ast(ast);
  return 0;
}
