// codegen/identity.hpp — the model class's metadata methods: its name and
// source file, its size, its unknowns' and outputs' names, the limits of its
// states' validity, its parameters (a computed one with its formula), the
// model's default settings and set_parameter().
#pragma once

#include <string>

#include "codegen/cpp.hpp"
#include "codegen/emit_cpp.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// Appends those methods to `c`; with `compact`, their lists of thousands
/// (a large model of repeated bodies, codegen/emit_cpp) written compactly.
void add_identity_methods(CppClass& c, const ir::ReducedSystem& s, const EmitOptions& opt, bool compact);

/// "= FORMULA" of a computed parameter (sim --list-parameters prints it); a
/// long one (a joint frame from its axis) as the parameters it is computed from.
std::string computed_doc(const ir::Parameter& p, const ir::BondGraph& g);

/// A DAE's residual_sparsity(): where IDA's matrix dF/dy + c_j dF/dy' can be
/// nonzero, by column (reduce/sparsity.hpp).
CppFunction residual_sparsity_method(const ir::ReducedSystem& s);

/// The unit an output is shown in (the CSV header, its line's comment): as
/// declared, else the SI unit the units pass found; "" for a plain number
/// or where nothing fixes it.
std::string shown_unit(const ir::Output& o);

/// Variables and parameters by their names in the model (for comments).
ir::Namer names_for_dump(const ir::BondGraph& g);

}  // namespace mbgc::codegen
