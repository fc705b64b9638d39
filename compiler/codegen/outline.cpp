// codegen/outline.cpp — runs of a body's elimination, their shapes, their functions.
#include "codegen/outline.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fmt/format.h>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "codegen/shared_temps.hpp"

namespace mbgc::codegen {
namespace {

using namespace mbgc::ir;

constexpr const char* kRunOrigin = "articulated-body elimination, body ";
// Shorter runs stay inline: their call would cost about what it saves.
constexpr std::size_t kMinRun = 12;

/// The body an elimination temporary belongs to ("" for anything else).
std::string body_of(const Assignment& a) {
  if (a.block >= 0 || !a.value || a.origin.rfind(kRunOrigin, 0) != 0) return {};
  const std::size_t start = std::strlen(kRunOrigin);
  const std::size_t colon = a.origin.find(": ", start);
  return colon == std::string::npos ? std::string{} : a.origin.substr(start, colon - start);
}

/// The canonical text of a run: its DAG with every leaf renamed in order of
/// first appearance, and its outputs. Empty if the run cannot be outlined
/// (it reads t). Fills the run's sources and inputs.
class Canon {
 public:
  /// `stored`: the outputs of the runs taken as outlined (var -> run, position).
  Canon(const std::vector<const Assignment*>& list, OutlinedRun& run,
        const std::unordered_map<int, std::pair<int, std::size_t>>& stored, int self)
      : list_(list), run_(run), stored_(stored), self_(self) {
    for (std::size_t k = 0; k < run.defined.size(); ++k) local_[run.defined[k]] = static_cast<int>(k);
    run.sources.clear();
    run.inputs.clear();
  }

  std::string key() {
    for (std::size_t i = run_.begin; i < run_.end && ok_; ++i) text_ += fmt::format("=>{};", node(list_[i]->value));
    text_ += fmt::format("out({})", fmt::join(run_.outputs, ","));
    return ok_ ? text_ : std::string{};
  }

 private:
  /// Reads no variable and not t: computed on the caller's side.
  bool parameter_only(const Expr& e) {
    if (e->op == Op::Var || e->op == Op::Time || e->op == Op::Der) return false;
    if (e->op == Op::Const || e->op == Op::Param) return true;
    if (auto it = param_only_.find(e.get()); it != param_only_.end()) return it->second;
    bool all = true;
    for (const Expr& a : e->args) all = all && parameter_only(a);
    return param_only_[e.get()] = all;
  }

  int node(const Expr& e) {
    if (auto it = id_.find(e.get()); it != id_.end()) return it->second;
    std::string piece;
    if (e->op == Op::Const) {
      std::uint64_t bits;
      std::memcpy(&bits, &e->value, sizeof bits);
      piece = fmt::format("C{:x}", bits);
    } else if (e->op == Op::Var && local_.count(e->id)) {
      piece = fmt::format("L{}", local_.at(e->id));
    } else if (auto st = e->op == Op::Var ? stored_.find(e->id) : stored_.end(); st != stored_.end() && st->second.first != self_) {
      auto src = std::find(run_.sources.begin(), run_.sources.end(), st->second.first);
      if (src == run_.sources.end()) src = run_.sources.insert(src, st->second.first);
      piece = fmt::format("S{}.{}", src - run_.sources.begin(), st->second.second);
    } else if (e->op == Op::Var || parameter_only(e)) {
      piece = fmt::format("I{}", run_.inputs.size());
      run_.inputs.push_back(e);
    } else if (e->op == Op::Time || e->op == Op::Der) {
      ok_ = false;
    } else {
      std::vector<int> args;
      for (const Expr& a : e->args) args.push_back(node(a));
      piece = fmt::format("{}.{}({})", static_cast<int>(e->op), static_cast<int>(e->fn), fmt::join(args, ","));
    }
    const int id = static_cast<int>(id_.size());
    id_.emplace(e.get(), id);
    keep_.push_back(e);
    text_ += fmt::format("n{}={};", id, piece);
    return id;
  }

  const std::vector<const Assignment*>& list_;
  OutlinedRun& run_;
  const std::unordered_map<int, std::pair<int, std::size_t>>& stored_;
  const int self_;
  std::unordered_map<int, int> local_;
  std::unordered_map<const Node*, int> id_;
  std::unordered_map<const Node*, bool> param_only_;
  std::vector<Expr> keep_;  // the nodes numbered stay alive (their addresses are keys)
  std::string text_;
  bool ok_ = true;
};

std::string identifier(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "t_" + out;
  return out;
}

}  // namespace

Outlining find_outlined_runs(const std::vector<const Assignment*>& list, const std::vector<std::unordered_set<int>>& reads) {
  Outlining o;
  for (std::size_t i = 0; i < list.size();) {
    const std::string body = body_of(*list[i]);
    std::size_t j = i + 1;
    if (!body.empty())
      while (j < list.size() && body_of(*list[j]) == body) ++j;
    if (!body.empty() && j - i >= kMinRun) {
      OutlinedRun run;
      run.begin = i, run.end = j, run.body = body;
      for (std::size_t k = i; k < j; ++k) run.defined.push_back(list[k]->var);
      o.runs.push_back(std::move(run));
    }
    i = j;
  }
  // Each run's outputs: what anything outside it reads.
  std::vector<int> run_at(list.size(), -1);
  std::unordered_map<int, std::pair<int, std::size_t>> defined_by;  // var -> (run, position in defined)
  for (std::size_t r = 0; r < o.runs.size(); ++r) {
    for (std::size_t i = o.runs[r].begin; i < o.runs[r].end; ++i) run_at[i] = static_cast<int>(r);
    for (std::size_t k = 0; k < o.runs[r].defined.size(); ++k) defined_by[o.runs[r].defined[k]] = {static_cast<int>(r), k};
  }
  std::vector<std::vector<char>> read_outside(o.runs.size());
  for (std::size_t r = 0; r < o.runs.size(); ++r) read_outside[r].assign(o.runs[r].defined.size(), 0);
  for (std::size_t i = 0; i <= list.size(); ++i)  // reads[list.size()]: what the section's results read
    for (int v : reads[i]) {
      auto it = defined_by.find(v);
      if (it == defined_by.end() || (i < list.size() && run_at[i] == it->second.first)) continue;
      read_outside[static_cast<std::size_t>(it->second.first)][it->second.second] = 1;
    }
  for (std::size_t r = 0; r < o.runs.size(); ++r)
    for (std::size_t k = 0; k < read_outside[r].size(); ++k)
      if (read_outside[r][k]) o.runs[r].outputs.push_back(k);
  // Every run's outputs have a place (a member array), whether its run is
  // outlined or not: so a run's shape never depends on whether its sources'
  // shapes are shared (a chain's body above the leaf reads the leaf there).
  for (std::size_t r = 0; r < o.runs.size(); ++r)
    for (std::size_t k = 0; k < o.runs[r].outputs.size(); ++k)
      o.stored[o.runs[r].defined[o.runs[r].outputs[k]]] = {static_cast<int>(r), k};
  std::map<std::string, std::vector<int>> by_key;
  for (std::size_t r = 0; r < o.runs.size(); ++r) {
    std::string key = Canon(list, o.runs[r], o.stored, static_cast<int>(r)).key();
    if (!key.empty()) by_key[std::move(key)].push_back(static_cast<int>(r));
  }
  std::vector<std::vector<int>> groups;
  for (auto& [key, runs] : by_key)
    if (runs.size() > 1) groups.push_back(runs);
  std::sort(groups.begin(), groups.end());  // in the order of their first run: deterministic
  for (const std::vector<int>& runs : groups) {
    for (int r : runs) o.runs[static_cast<std::size_t>(r)].shape = static_cast<int>(o.shapes.size());
    o.shapes.push_back({runs});
  }
  return o;
}

CppFunction shape_function(const std::string& name, const Outlining& o, int shape, const std::vector<const Assignment*>& list,
                           const BondGraph& g, const Namer& names, const std::function<std::string(const SourceLoc&)>& where,
                           int& cse_counter, CppOps* ops) {
  const OutlineShape& s = o.shapes[static_cast<std::size_t>(shape)];
  const OutlinedRun& run = o.runs[static_cast<std::size_t>(s.runs[0])];
  // Names: the first body's, without its prefix; in[k], sK[k] and out[k] for what crosses the call.
  const std::string prefix = run.body + ".";
  std::unordered_map<int, std::string> local;
  for (int v : run.defined) {
    const std::string& full = g.vars[static_cast<std::size_t>(v)].name;
    local[v] = identifier(full.rfind(prefix, 0) == 0 ? full.substr(prefix.size()) : full);
  }
  std::vector<std::string> bodies, params = {"const double* in"}, outs;
  for (int r : s.runs) bodies.push_back(o.runs[static_cast<std::size_t>(r)].body);
  ExprNames known;
  for (std::size_t k = 0; k < run.inputs.size(); ++k) known.emplace(run.inputs[k], fmt::format("in[{}]", k));
  for (std::size_t i = 0; i < run.sources.size(); ++i) {
    const OutlinedRun& src = o.runs[static_cast<std::size_t>(run.sources[i])];
    for (std::size_t k = 0; k < src.outputs.size(); ++k) known.emplace(var(src.defined[src.outputs[k]]), fmt::format("s{}[{}]", i, k));
    params.push_back(fmt::format("const double* s{}", i));
  }
  params.push_back("double* out");
  for (std::size_t k = 0; k < run.outputs.size(); ++k) outs.push_back(local.at(run.defined[run.outputs[k]]));
  CppFunction f{fmt::format("The articulated-body elimination of bodies {} (the same equations, up to their names): "
                            "in[] what it reads{}, out[] what the rest of the model reads of it: {}.",
                            fmt::join(bodies, ", "), run.sources.empty() ? "" : ", sK[] the outputs of the runs it reads",
                            fmt::join(outs, ", ")),
                fmt::format("static void {}({})", name, fmt::join(params, ", ")),
                {}};
  Namer inside = names;
  inside.var = [&](int id) { return local.count(id) ? local.at(id) : names.var(id); };
  SharedTemps shared(known, inside, cse_counter, ops);
  for (std::size_t i = run.begin; i < run.end; ++i) shared.count(list[i]->value);
  shared.finish_counting();
  std::string last;
  for (std::size_t i = run.begin; i < run.end; ++i) {
    const Assignment& a = *list[i];
    const std::size_t colon = a.origin.find(": ");
    std::string origin = fmt::format("{}  {}", where(a.loc), colon == std::string::npos ? a.origin : a.origin.substr(colon + 2));
    if (origin != last) f.body.push_back(CppStmt::comment(origin));
    last = std::move(origin);
    const bool whole = shared.take_whole(a.value);
    std::string rhs = shared.print(a.value, f.body);
    f.body.push_back(CppStmt::line(fmt::format("const double {} = {};", local.at(a.var), rhs)));
    if (whole) shared.name_whole(a.value, local.at(a.var));
  }
  for (std::size_t k = 0; k < outs.size(); ++k) f.body.push_back(CppStmt::line(fmt::format("out[{}] = {};", k, outs[k])));
  return f;
}

}  // namespace mbgc::codegen
