// codegen/outline_emit.hpp — outlining as the emitter writes it: whether a
// section is outlined (--outline), the member arrays its runs' outputs are
// kept in, the shapes' functions and the calls to them. The runs and shapes
// themselves are found by codegen/outline.hpp; the emitter (emit_cpp.cpp)
// writes everything else of a section.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "codegen/cpp.hpp"
#include "codegen/emit_cpp.hpp"
#include "codegen/names.hpp"
#include "codegen/outline.hpp"
#include "codegen/cse.hpp"
#include "ir/expr.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// The values of a section's results, in their order.
std::vector<ir::Expr> result_values(const std::vector<SectionResult>& results);

/// A section's outlining: its runs and shapes, their member arrays, per
/// assignment the outlined run it is in and the inline run whose outputs
/// are copied to their array after it (-1: none), per result the outlined
/// run it is in.
struct Outlined {
  Outlining o;
  std::vector<std::string> store;
  std::vector<int> run_at, copy_after, result_run_at;
  std::string method;                    // the method whose section it is ("derivative")
  std::vector<std::string> shape_names;  // per shape: its function's name, once written
};

/// The outlining of one file's sections: what the emitter gives it (the
/// system, --outline, the file's identifiers, the names of variables and
/// parameters, where a model line is, the cseN counter) and what it keeps
/// for the model class (the shapes' functions, the member arrays).
class OutlineEmitter {
 public:
  using Where = std::function<std::string(const ir::SourceLoc&)>;

  OutlineEmitter(const ir::ReducedSystem& system, EmitOptions::Outline mode, Mangler& mangle, const ir::Namer& names,
                 Where where, int& cse_counter)
      : s_(system), mode_(mode), mangle_(mangle), names_(names), where_(std::move(where)), cse_counter_(cse_counter) {}

  /// Measures the dynamics' assignments (the derivative's or the
  /// residual's): whether, written inline, they are past kOutlineFromNodes
  /// (remembered: --outline auto then outlines every section). Returns
  /// whether they are past it and bodies with the same equations repeat
  /// among them (the emitter then writes its long lists compactly).
  bool measure_dynamics();

  /// `list` outlined where --outline says so (see find_shapes), in a section
  /// of method `method`; `read_later`, if given, the variables other methods
  /// read of it (their places are kept, as those its results read).
  Outlined outline_section(std::vector<const ir::Assignment*>& list, std::vector<SectionResult>& results,
                           const std::string& method, const std::unordered_set<int>* read_later = nullptr);

  /// Whether the dynamics are past kOutlineFromNodes (measure_dynamics).
  bool large() const { return large_; }

  /// One outlined run: its other inputs into an array, then the shape's
  /// function (made the first time) with its sources' arrays and its own
  /// (a run of results: the caller's array, from its first result's place).
  /// The operations of one call count into `ops`, the caller's.
  void call_shape(std::vector<CppStmt>& body, Outlined& section, int r, const std::vector<const ir::Assignment*>& list,
                  const std::vector<SectionResult>& results, ir::CppOps& ops);

  /// The section is printed: its outlined outputs are named as variables again.
  void finish_section(const Outlined& section);

  /// While a section is printed, an outlined output's place ("rod3_acc[2]"), else nullptr.
  const std::string* stored_name(int var) const {
    auto it = stored_name_.find(var);
    return it == stored_name_.end() ? nullptr : &it->second;
  }

  std::vector<CppFunction>& functions() { return outlined_; }
  std::vector<CppStmt>& stores() { return stores_; }

 private:
  /// The runs and shapes of a section, `list` reordered body by body if that
  /// form is taken: of every body's equations grouped (kinematics too) and the
  /// eliminations alone in causal order, the one that leaves less inline;
  /// `results` each owner's together (group_results_by_owner) if some of them
  /// are outlined.
  Outlining find_shapes(std::vector<const ir::Assignment*>& list, std::vector<SectionResult>& results,
                        const std::unordered_set<int>* read_later) const;

  /// The expression nodes of the assignments that stay inline.
  static std::size_t inline_count(const Outlining& o, const std::vector<const ir::Assignment*>& list);

  /// The member arrays that keep the runs' outputs that an outlined run
  /// reads or computes; while the section is printed, each output of an
  /// outlined run is named by its place there (an inline run's keep their
  /// names, and are copied there after it).
  std::vector<std::string> store_outlined(const Outlining& o, const std::vector<const ir::Assignment*>& list,
                                          const std::string& method);

  const ir::ReducedSystem& s_;
  EmitOptions::Outline mode_;
  Mangler& mangle_;
  const ir::Namer& names_;
  Where where_;
  int& cse_counter_;
  bool large_ = false;                 // the dynamics are past kOutlineFromNodes (--outline auto outlines every section)
  std::vector<CppFunction> outlined_;  // the shapes' functions (codegen/outline), private
  std::vector<CppStmt> stores_;        // the member arrays of their runs' outputs
  std::unordered_map<int, std::string> stored_name_;  // while a section is printed: an outlined output -> its place
  std::map<std::string, ir::CppOps> shape_cost_;      // per shape function: the operations of one call
  /// --outline auto: outline from this many expression nodes written inline
  /// (the derivative no longer fits the instruction cache); in a model whose
  /// dynamics are that large, in every method (the others repeat the same
  /// bodies: outlined, the file is a fraction of its size). Measured in the
  /// peer benchmark: the planar chain of 8 rods (13,000 nodes) takes 0.45 ms
  /// inline and 0.60 ms outlined, of 32 (66,000) 3.44 and 3.60 ms; the
  /// 32-rod spherical chain (690,000) is 2x faster outlined.
  static constexpr std::size_t kOutlineFromNodes = 100000;
};

}  // namespace mbgc::codegen
