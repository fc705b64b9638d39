// codegen/outline.hpp — bodies with the same equations, computed by one function.
//
// A generated derivative is straight-line code, and for a large model the
// processor spends its time fetching it: measured on the chain of 32 and 100
// rods and the 31-rod binary tree alike, the derivative ran at about 57 bytes
// of machine code per nanosecond whatever its arithmetic (docs/notes/
// linear_time.md). Bodies made by one `for` loop have the same equations up
// to their names, so their articulated-body elimination (most of the work
// for 3-D bodies) is written once, as a function of the values it reads, and
// called once per body: the code shrinks by about the number of bodies and
// stays in the instruction cache.
//
// A run is the contiguous sequence of one body's elimination temporaries in
// a section (reduce/tree_elimination names them and their origin). What
// anything outside the run reads of it (its outputs) is kept in a member
// array of the run's own; a run that reads another outlined run's outputs
// (a parent its children's) reads them there. Two runs have the same shape
// when their expressions are the same DAG with the leaves renamed in order
// of first appearance: the run's own variables, the outputs of its source
// runs (by their position there), its other inputs (variables, and
// parameter-only subexpressions, which stay on the caller's side where
// initial() computed them once) and the same constants, bit for bit, and
// when they have the same outputs.
//
// A section's results (the residual's r[k], the constraints' rows_out[k])
// are runs too: one owner's, a body's rows or a joint's, written by their
// shape's function straight into the caller's array, at the same places
// from the first one's for every run of the shape.
#pragma once

#include <functional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "codegen/cpp.hpp"
#include "ir/expr.hpp"
#include "ir/graph.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// A value a section writes into the caller's array (`r[5] = ...`). The
/// results of one owner (a body's residual rows, a joint's constraint rows
/// and their derivatives) are outlined like a run of its equations: their
/// shape's function writes them where the caller's array has them.
struct SectionResult {
  std::string array;     // "r", "values", "rows_out", ...
  std::size_t index = 0;
  ir::Expr value;
  std::string owner;     // the body, joint or instance it is about ("": none, written inline)
  ir::SourceLoc loc;     // where it comes from (its comment in a shape's function), if known
  std::string origin;
  std::string note = {};  // after its line where written inline ("  // omega [rad/s] (model.mbg:9:1)")
};

struct OutlinedRun {
  std::size_t begin = 0, end = 0;   // [begin, end) in the section's assignment list (results: in its results)
  std::string body;                 // the body whose elimination it is
  int shape = -1;                   // index into Outlining::shapes; -1: written inline
  std::vector<int> defined;         // the variables it computes, in order
  std::vector<std::size_t> outputs; // positions in `defined` that anything outside the run reads
  std::vector<std::size_t> slots;   // per output: its place in the run's member array (by its name, see below)
  std::size_t width = 0;            // the member array's size
  std::vector<int> sources;         // runs whose outputs it reads (a parent: its children's), in order of first reading
  std::vector<ir::Expr> inputs;     // what else it reads (variables, parameter-only subexpressions), in order
  /// A run of results: nothing defined, no outputs; result k goes to
  /// array[first + offsets[k]], and the function's out[] is array + first.
  bool results = false;
  std::vector<std::size_t> offsets;
};

struct OutlineShape {
  std::vector<int> runs;            // indices into Outlining::runs, in section order
};

struct Outlining {
  std::vector<OutlinedRun> runs;
  std::vector<OutlineShape> shapes; // only shapes of two runs or more
  /// Where a run's output is kept (outlined or not): var -> (run, slot). A
  /// slot stands for a name without its owner ("pose.R11", "reaction_t.f[1]"),
  /// the same in every run of the section: a child reads its parent's
  /// omega at the same place whatever the parent's joint.
  std::unordered_map<int, std::pair<int, std::size_t>> stored;
  /// Runs are owners' (group_by_owner: bodies, joints, component instances),
  /// not a kinematic tree's bodies.
  bool by_owner = false;
};

/// The variables each assignment of a section reads (ir::assignment_inputs),
/// found once for the orders the section is tried in.
using ReadsOf = std::unordered_map<const ir::Assignment*, std::unordered_set<int>>;

/// The runs of `assignments` (one section, in order) and their shapes;
/// `results_read` what the section's results read; labels[i] the body
/// assignment i belongs to (an index into `bodies`, -1 for none). Then the
/// runs of `results`: each owner's, where they are contiguous (after the
/// assignments' runs in Outlining::runs).
Outlining find_outlined_runs(const std::vector<const ir::Assignment*>& assignments, const ReadsOf& reads,
                             const std::unordered_set<int>& results_read, const std::vector<int>& labels,
                             const std::vector<std::string>& bodies, const std::vector<SectionResult>& results,
                             const ir::BondGraph& graph);

/// "s3.m1.f2[1]" -> "s3", "der(rod3.pose.R11)" and "mu(j2.cn[1])" -> "rod3"
/// and "j2": the body, joint or component instance a variable's name is
/// qualified by ("" for none).
std::string owner_of(const std::string& name);

/// `results` in order of their owners' first appearance (stable): each
/// owner's together, so that they can be one run (a joint's g rows and its
/// gdot rows). Results do not read one another: any order gives the same values.
void group_results_by_owner(std::vector<SectionResult>& results);

/// Which body each assignment belongs to (`tree`'s, else the deepest body of
/// what it reads; -1 for none), and `assignments` reordered so that each
/// body's kinematics (everything before the tree's elimination) are
/// contiguous: parents before children, every assignment after what it
/// reads. `labels` follows the new order.
void group_by_body(std::vector<const ir::Assignment*>& assignments, const ir::ReducedSystem& system, const ReadsOf& reads,
                   std::vector<int>& labels);

/// Without a kinematic tree (the multiplier and penalty forms, a plain bond
/// graph): which owner each assignment belongs to, the body, joint or
/// component instance its variable's name is qualified by (an index into
/// `owners`, -1 for none), and `assignments` reordered so that each owner's
/// equations are contiguous where what they read allows: owners in order of
/// first appearance, every assignment after what it reads, an owner's next
/// equation before another's while it has one ready.
void group_by_owner(std::vector<const ir::Assignment*>& assignments, const ir::ReducedSystem& system, const ReadsOf& reads,
                    std::vector<int>& labels, std::vector<std::string>& owners);

/// The function that computes one shape: `static void NAME(const double* in,
/// const double* s0, ..., double* out)`: in[] the first run's inputs, sK
/// the outputs of its K-th source run, out[] its own outputs (where they are
/// kept between calls: the run's member array; a run of results: where the
/// caller's array has them). Its operations are counted into `ops` (once:
/// the caller counts each call).
CppFunction shape_function(const std::string& name, const Outlining& o, int shape,
                           const std::vector<const ir::Assignment*>& assignments,
                           const std::vector<SectionResult>& results, const ir::BondGraph& graph,
                           const ir::Namer& names, const std::function<std::string(const ir::SourceLoc&)>& where,
                           int& cse_counter, ir::CppOps* ops);

}  // namespace mbgc::codegen
