// parse/parse.hpp — pass 1: text -> AST.
//
// `parse_source` turns one file into statements; `load_program` reads a file,
// parses it and splices in every `import "other.mbg"` (relative to the
// importing file, each file once, cycles diagnosed).
#pragma once

#include <set>
#include <string>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"

namespace mbgc::parse {

/// The statement keywords and element kinds the parser knows (grammar/mbg.ebnf
/// lists the same; tests/unit/grammar_test.cpp keeps them in sync).
const std::set<std::string>& statement_keywords();
const std::set<std::string>& element_kinds();

/// Parse the already-registered source file `file_id`.
ir::AstProgram parse_source(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags);

/// Read `path` (shown in diagnostics as given), parse it and its imports.
ir::AstProgram load_program(const std::string& path, ir::SourceManager& sources,
                            ir::Diagnostics& diags);

}  // namespace mbgc::parse
