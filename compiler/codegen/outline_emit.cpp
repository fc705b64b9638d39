// codegen/outline_emit.cpp — outlining as the emitter writes it: see outline_emit.hpp.
#include "codegen/outline_emit.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <unordered_set>

namespace mbgc::codegen {

using namespace mbgc::ir;

std::vector<Expr> result_values(const std::vector<SectionResult>& results) {
  std::vector<Expr> values;
  values.reserve(results.size());
  for (const SectionResult& r : results) values.push_back(r.value);
  return values;
}

Outlined OutlineEmitter::outline_section(std::vector<const Assignment*>& list, std::vector<SectionResult>& results,
                                         const std::string& method, const std::unordered_set<int>* read_later) {
  Outlined out;
  out.method = method;
  out.run_at.assign(list.size(), -1);
  out.copy_after.assign(list.size(), -1);
  out.result_run_at.assign(results.size(), -1);
  if (mode_ == EmitOptions::Outline::never ||
      (mode_ == EmitOptions::Outline::automatic && !large_ && inline_count({}, list) <= kOutlineFromNodes))
    return out;
  out.o = find_shapes(list, results, read_later);
  if (out.o.shapes.empty()) return out;
  out.shape_names.resize(out.o.shapes.size());
  out.store = store_outlined(out.o, list, method);
  for (std::size_t r = 0; r < out.o.runs.size(); ++r) {
    const OutlinedRun& run = out.o.runs[r];
    if (run.results) {
      if (run.shape >= 0)
        for (std::size_t i = run.begin; i < run.end; ++i) out.result_run_at[i] = static_cast<int>(r);
    } else if (run.shape >= 0)
      for (std::size_t k = run.begin; k < run.end; ++k) out.run_at[k] = static_cast<int>(r);
    else if (!out.store[r].empty())  // an inline run an outlined one reads: copied when done
      out.copy_after[run.end - 1] = static_cast<int>(r);
  }
  return out;
}

Outlining OutlineEmitter::find_shapes(std::vector<const Assignment*>& list, std::vector<SectionResult>& results,
                                      const std::unordered_set<int>* read_later) const {
  const BondGraph& g = s_.graph;
  ReadsOf reads;
  for (const Assignment* a : list) assignment_inputs(s_, *a, reads[a]);
  std::unordered_set<int> results_read;
  collect_vars(result_values(results), results_read);
  if (read_later) results_read.insert(read_later->begin(), read_later->end());
  std::vector<SectionResult> grouped_results = results;
  group_results_by_owner(grouped_results);
  auto outline = [&](const std::vector<const Assignment*>& order, const std::vector<int>& labels, const std::vector<std::string>& names) {
    Outlining o = find_outlined_runs(order, reads, results_read, labels, names, grouped_results, g);
    return o.shapes.empty() ? Outlining{} : o;  // nothing shared: nothing stored either
  };
  std::vector<const Assignment*> grouped = list;
  std::vector<int> labels;
  Outlining o;
  if (!s_.tree) {  // no elimination: each owner's equations (a body's, a joint's), grouped
    std::vector<std::string> owners;
    group_by_owner(grouped, s_, reads, labels, owners);
    o = outline(grouped, labels, owners);
    if (o.shapes.empty()) return o;
    o.by_owner = true;
    list = grouped;
  } else {
    group_by_body(grouped, s_, reads, labels);
    Outlining by_body = outline(grouped, labels, s_.tree->names);
    for (std::size_t k = 0; k < list.size(); ++k)
      if (!from_tree_elimination(*list[k])) labels[k] = -1;
      else labels[k] = s_.tree->body_of.count(list[k]->var) ? s_.tree->body_of.at(list[k]->var) : -1;
    Outlining eliminations = outline(list, labels, s_.tree->names);
    if (inline_count(by_body, grouped) < inline_count(eliminations, list)) o = std::move(by_body), list = grouped;
    else o = std::move(eliminations);
  }
  if (std::any_of(o.runs.begin(), o.runs.end(), [](const OutlinedRun& run) { return run.results && run.shape >= 0; }))
    results = std::move(grouped_results);
  return o;
}

std::size_t OutlineEmitter::inline_count(const Outlining& o, const std::vector<const Assignment*>& list) {
  std::vector<char> out(list.size(), 0);
  for (const OutlinedRun& run : o.runs)
    if (run.shape >= 0 && !run.results) std::fill(out.begin() + static_cast<long>(run.begin), out.begin() + static_cast<long>(run.end), 1);
  std::size_t n = 0;
  for (std::size_t k = 0; k < list.size(); ++k)
    if (!out[k] && list[k]->value) n += ir::size(list[k]->value);
  return n;
}

bool OutlineEmitter::measure_dynamics() {
  std::vector<const Assignment*> list;
  for (int i : s_.for_derivative) list.push_back(&s_.assignments[static_cast<std::size_t>(i)]);
  large_ = inline_count({}, list) > kOutlineFromNodes;
  std::vector<SectionResult> none;
  return large_ && !find_shapes(list, none, nullptr).shapes.empty();
}

std::vector<std::string> OutlineEmitter::store_outlined(const Outlining& o, const std::vector<const Assignment*>& list,
                                                        const std::string& method) {
  std::size_t first_elim = list.size();  // the runs before the tree's elimination are kinematics, after it accelerations
  for (std::size_t k = 0; k < list.size() && first_elim == list.size(); ++k)
    if (from_tree_elimination(*list[k])) first_elim = k;
  std::vector<char> kept(o.runs.size(), 0);
  for (const OutlinedRun& run : o.runs)
    if (run.shape >= 0) {
      kept[static_cast<std::size_t>(&run - o.runs.data())] = !run.results;  // (a run of results writes the caller's array)
      for (int src : run.sources) kept[static_cast<std::size_t>(src)] = 1;
    }
  std::vector<std::string> store(o.runs.size());
  if (std::find(kept.begin(), kept.end(), 1) != kept.end())  // one comment heads the method's arrays
    stores_.push_back(CppStmt::comment(
        o.by_owner ? fmt::format("{}(): what the rest of it reads of each one's equations (a body's, a joint's)", method)
                   : fmt::format("{}(): what the rest of it reads of each body's kinematics (_kin), elimination (_elim) "
                                 "and accelerations (_acc)",
                                 method)));
  for (std::size_t r = 0; r < o.runs.size(); ++r) {
    if (!kept[r]) continue;
    const OutlinedRun& run = o.runs[r];
    const bool elimination = from_tree_elimination(*list[run.begin]);
    const char* phase = o.by_owner ? "eqs" : elimination ? "elim" : run.begin < first_elim ? "kin" : "acc";
    store[r] = mangle_.get(fmt::format("store:{}:{}", method, run.begin), fmt::format("{}_{}", run.body, phase));
    stores_.push_back(CppStmt::line(fmt::format("double {}[{}] = {{}};", store[r], std::max<std::size_t>(run.width, 1))));
  }
  for (const auto& [v, at] : o.stored)
    if (o.runs[static_cast<std::size_t>(at.first)].shape >= 0)
      stored_name_[v] = fmt::format("{}[{}]", store[static_cast<std::size_t>(at.first)], at.second);
  return store;
}

void OutlineEmitter::call_shape(std::vector<CppStmt>& body, Outlined& section, int r, const std::vector<const Assignment*>& list,
                                const std::vector<SectionResult>& results, CppOps& ops) {
  const Outlining& o = section.o;
  const OutlinedRun& run = o.runs[static_cast<std::size_t>(r)];
  const OutlineShape& shape = o.shapes[static_cast<std::size_t>(run.shape)];
  std::string& fn = section.shape_names[static_cast<std::size_t>(run.shape)];
  const std::string& method = section.method;
  if (fn.empty()) {
    fn = mangle_.get(fmt::format("shape:{}:{}", method, run.shape), fmt::format("{}_shape{}", method, run.shape + 1));
    CppOps one;
    outlined_.push_back(shape_function(fn, o, run.shape, list, results, s_.graph, names_, where_, cse_counter_, &one));
    shape_cost_[fn] = one;
  }
  ops += shape_cost_.at(fn);  // the work of one call
  if (run.results) {  // which places it writes: "r[13..25]", "rows_out[5..9, 205..209]"
    const SectionResult& first = results[run.begin];
    std::vector<std::string> spans;
    for (std::size_t k = run.begin, end = k; k < run.end; k = end) {
      for (end = k + 1; end < run.end && results[end].index == results[end - 1].index + 1; ++end) {
      }
      spans.push_back(end - k == 1 ? fmt::format("{}", results[k].index) : fmt::format("{}..{}", results[k].index, results[end - 1].index));
    }
    body.push_back(CppStmt::comment(fmt::format("{}{}: {}[{}] by {}() (shared by the {} with the same equations)",
                                                first.loc.valid() ? where_(first.loc) + "  " : "", run.body, first.array,
                                                fmt::join(spans, ", "), fn, shape.runs.size())));
  } else {
    const SourceLoc& loc = list[run.begin]->loc;
    body.push_back(CppStmt::comment(o.by_owner ? fmt::format("{}  {}: {}() (shared by the {} with the same equations)", where_(loc),
                                                             run.body, fn, shape.runs.size())
                                               : fmt::format("{}  body {}: {}() (the same equations as {} bodies)", where_(loc),
                                                             run.body, fn, shape.runs.size())));
  }
  std::vector<std::string> args;
  if (run.inputs.empty()) {
    args.push_back("nullptr");
  } else {
    const std::string in_name =
        mangle_.get(fmt::format("{}:{}:{}:in", run.results ? "results" : "run", method, run.begin), run.body + "_in");
    body.push_back(CppStmt::array_of(in_name, run.inputs));
    args.push_back(in_name);
  }
  for (int src : run.sources) args.push_back(section.store[static_cast<std::size_t>(src)]);
  if (!run.results) args.push_back(section.store[static_cast<std::size_t>(r)]);
  else if (const SectionResult& first = results[run.begin]; first.index == 0) args.push_back(first.array);
  else args.push_back(fmt::format("{} + {}", first.array, first.index));
  body.push_back(CppStmt::line(fmt::format("{}({});", fn, fmt::join(args, ", "))));
}

void OutlineEmitter::finish_section(const Outlined& section) {
  for (const auto& [v, at] : section.o.stored) stored_name_.erase(v);
}

}  // namespace mbgc::codegen
