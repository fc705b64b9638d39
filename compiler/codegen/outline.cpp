// codegen/outline.cpp — runs of a body's elimination, their shapes, their functions.
#include "codegen/outline.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fmt/format.h>
#include <map>
#include <optional>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "codegen/names.hpp"
#include "codegen/cse.hpp"
#include "codegen/render.hpp"

namespace mbgc::codegen {
namespace {

using namespace mbgc::ir;

// Shorter runs stay inline: their call would cost about what it saves. (At
// 6, the planar chain's accelerations, 6 to 10 equations a body, are
// outlined: its C++ is 4.4 kB a rod at N = 100, and its derivative 8 % slower
// than with them inline, 1.89 against 1.75 us at N = 32.)
constexpr std::size_t kMinRun = 6;

/// A run of results is outlined from this many operations, and two a
/// result: fewer (results mostly copies of what they read) are shorter
/// written inline than as a call with its comment and its inputs' array.
constexpr std::size_t kMinResultOperations = 24;

/// The distinct operations (nodes with arguments) of `values`.
std::size_t operations(const std::vector<Expr>& values) {
  std::unordered_set<const Node*> seen;
  std::function<void(const Expr&)> walk = [&](const Expr& e) {
    if (e->args.empty() || !seen.insert(e.get()).second) return;
    for (const Expr& a : e->args) walk(a);
  };
  for (const Expr& e : values) walk(e);
  return seen.size();
}

/// The canonical text of a run: its DAG with every leaf renamed in order of
/// first appearance, and its outputs (a run of results: where each goes).
/// Empty if the run cannot be outlined (it reads t). Fills the run's sources
/// and inputs.
class Canon {
 public:
  /// `values`: the run's expressions, in order; `stored`: where every run's
  /// outputs are kept (var -> run, slot).
  Canon(std::vector<Expr> values, OutlinedRun& run, const std::unordered_map<int, std::pair<int, std::size_t>>& stored, int self)
      : values_(std::move(values)), run_(run), stored_(stored), self_(self) {
    for (std::size_t k = 0; k < run.defined.size(); ++k) local_[run.defined[k]] = static_cast<int>(k);
    run.sources.clear();
    run.inputs.clear();
  }

  std::string key() {
    for (std::size_t i = 0; i < values_.size() && ok_; ++i) {
      const int n = node(values_[i]);
      text_ += run_.results ? fmt::format("=>{}:{};", run_.offsets[i], n) : fmt::format("=>{};", n);
    }
    text_ += run_.results ? std::string("results") : fmt::format("out({})", fmt::join(run_.slots, ","));
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

  const std::vector<Expr> values_;
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

/// "s3.m1.f2[1]" -> "m1.f2[1]", "der(rod3.pose.R11)" -> "der(pose.R11)": a
/// variable's name without the body or joint it belongs to.
std::string without_owner(const std::string& name) {
  if (name.rfind("der(", 0) == 0) return "der(" + without_owner(name.substr(4));
  const std::size_t dot = name.find('.');
  return dot == std::string::npos ? name : name.substr(dot + 1);
}


/// list[0, end) in Kahn's order, the lowest (key of its label, name without
/// its owner, place) first: the same order for every owner with the same
/// equations. An unlabelled assignment takes the highest key of what it
/// reads. With `stay`, the key taken last goes on while it has an
/// assignment ready, even when a lower one has one again: an owner's
/// equations that a lower one's wait for (a joint's forces on its bodies)
/// stay one run, not one equation between each of the other's. `labels` follows.
void order_by_key(std::vector<const Assignment*>& list, std::size_t end, std::vector<int>& labels, const std::vector<int>& label_key,
                  const std::vector<const std::unordered_set<int>*>& reads, const BondGraph& graph, bool stay) {
  std::unordered_map<int, std::size_t> defined_at;
  for (std::size_t i = 0; i < end; ++i) defined_at[list[i]->var] = i;
  std::vector<std::vector<std::size_t>> readers(end);
  std::vector<int> waiting(end, 0), key(end, -1);
  for (std::size_t i = 0; i < end; ++i) {
    if (labels[i] >= 0) key[i] = label_key[static_cast<std::size_t>(labels[i])];
    for (int v : *reads[i])
      if (auto d = defined_at.find(v); d != defined_at.end() && d->second != i) {
        readers[d->second].push_back(i);
        ++waiting[i];
        if (labels[i] < 0) key[i] = std::max(key[i], key[d->second]);
      }
  }
  using Item = std::pair<std::string, std::size_t>;
  using Queue = std::priority_queue<Item, std::vector<Item>, std::greater<>>;
  std::map<int, Queue> ready;  // by key
  auto push = [&](std::size_t i) { ready[key[i]].push({without_owner(graph.vars[static_cast<std::size_t>(list[i]->var)].name), i}); };
  for (std::size_t i = 0; i < end; ++i)
    if (!waiting[i]) push(i);
  std::vector<const Assignment*> order;
  std::vector<int> order_labels;
  std::optional<int> last;
  while (!ready.empty()) {
    auto q = stay && last ? ready.find(*last) : ready.end();
    if (q == ready.end()) q = ready.begin();
    last = q->first;
    const std::size_t i = q->second.top().second;
    q->second.pop();
    if (q->second.empty()) ready.erase(q);
    order.push_back(list[i]), order_labels.push_back(labels[i]);
    for (std::size_t r : readers[i])
      if (--waiting[r] == 0) push(r);
  }
  if (order.size() != end) return;  // (a cycle: cannot be, the list was in causal order)
  std::copy(order.begin(), order.end(), list.begin());
  std::copy(order_labels.begin(), order_labels.end(), labels.begin());
}

}  // namespace

std::string owner_of(const std::string& name) {
  // a variable made for another one (der(x), the GGL multiplier mu(row)): that one's
  for (const char* wrapper : {"der(", "mu("})
    if (name.rfind(wrapper, 0) == 0) return owner_of(name.substr(std::strlen(wrapper)));
  const std::size_t dot = name.find('.');
  return dot == std::string::npos ? std::string{} : name.substr(0, dot);
}

void group_results_by_owner(std::vector<SectionResult>& results) {
  std::unordered_map<std::string, std::size_t> first;
  for (const SectionResult& r : results) first.emplace(r.owner, first.size());
  std::stable_sort(results.begin(), results.end(),
                   [&](const SectionResult& a, const SectionResult& b) { return first.at(a.owner) < first.at(b.owner); });
}

Outlining find_outlined_runs(const std::vector<const Assignment*>& list, const ReadsOf& reads,
                             const std::unordered_set<int>& results_read, const std::vector<int>& labels,
                             const std::vector<std::string>& bodies, const std::vector<SectionResult>& results,
                             const BondGraph& graph) {
  Outlining o;
  auto label = [&](std::size_t i) { return list[i]->block >= 0 || !list[i]->value ? -1 : labels[i]; };
  for (std::size_t i = 0; i < list.size();) {
    const int body = label(i);
    std::size_t j = i + 1;
    if (body >= 0)
      while (j < list.size() && label(j) == body) ++j;
    if (body >= 0 && j - i >= kMinRun) {
      OutlinedRun run;
      run.begin = i, run.end = j, run.body = bodies[static_cast<std::size_t>(body)];
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
  for (std::size_t i = 0; i <= list.size(); ++i)  // i == list.size(): the section's results
    for (int v : i < list.size() ? reads.at(list[i]) : results_read) {
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
  // Slots: one per name without its owner, numbered in order of first appearance.
  std::unordered_map<std::string, std::size_t> slot_of;
  for (std::size_t r = 0; r < o.runs.size(); ++r) {
    OutlinedRun& run = o.runs[r];
    std::unordered_map<std::string, int> seen;  // a name twice in one run: the second is name#2
    for (std::size_t k : run.outputs) {
      std::string name = without_owner(graph.vars[static_cast<std::size_t>(run.defined[k])].name);
      if (const int n = ++seen[name]; n > 1) name += fmt::format("#{}", n);
      const std::size_t slot = slot_of.emplace(name, slot_of.size()).first->second;
      run.slots.push_back(slot);
      run.width = std::max(run.width, slot + 1);
      o.stored[run.defined[k]] = {static_cast<int>(r), slot};
    }
  }
  std::vector<std::string> keys;
  for (std::size_t r = 0; r < o.runs.size(); ++r) {
    std::vector<Expr> values;
    for (std::size_t k = o.runs[r].begin; k < o.runs[r].end; ++k) values.push_back(list[k]->value);
    keys.push_back(Canon(std::move(values), o.runs[r], o.stored, static_cast<int>(r)).key());
  }
  // The results' runs: each owner's (contiguous, group_results_by_owner),
  // into one array, none before the first. Where no other owner's results
  // have the same shape, each span of consecutive places of them on its own:
  // a joint's position rows, among its velocity rows that the other joints'
  // interleave differently.
  auto result_run = [&](std::size_t i, std::size_t j) -> std::optional<std::pair<OutlinedRun, std::string>> {
    OutlinedRun run;
    run.begin = i, run.end = j, run.body = results[i].owner, run.results = true;
    std::vector<Expr> values;
    for (std::size_t k = i; k < j; ++k) {
      if (k > i && results[k].index <= results[i].index) return std::nullopt;
      run.offsets.push_back(results[k].index - results[i].index);
      values.push_back(results[k].value);
    }
    const std::size_t ops = operations(values);
    if (ops < kMinResultOperations || ops < 2 * (j - i)) return std::nullopt;
    std::string key = Canon(std::move(values), run, o.stored, -1).key();
    if (key.empty()) return std::nullopt;
    return std::pair{std::move(run), std::move(key)};
  };
  std::vector<std::pair<std::size_t, std::size_t>> owned;  // each owner's results, [begin, end)
  for (std::size_t i = 0, j = 0; i < results.size(); i = j) {
    for (j = i + 1; j < results.size() && results[j].owner == results[i].owner && results[j].array == results[i].array; ++j) {
    }
    if (!results[i].owner.empty()) owned.push_back({i, j});
  }
  std::vector<std::optional<std::pair<OutlinedRun, std::string>>> whole;
  std::map<std::string, std::size_t> owners_of_key;
  for (const auto& [i, j] : owned) {
    whole.push_back(result_run(i, j));
    if (whole.back()) ++owners_of_key[whole.back()->second];
  }
  auto add = [&](std::pair<OutlinedRun, std::string>&& run) {
    o.runs.push_back(std::move(run.first));
    keys.push_back(std::move(run.second));
  };
  for (std::size_t c = 0; c < owned.size(); ++c) {
    if (whole[c] && owners_of_key.at(whole[c]->second) > 1) {
      add(std::move(*whole[c]));
      continue;
    }
    for (std::size_t a = owned[c].first, b = a; a < owned[c].second; a = b) {
      for (b = a + 1; b < owned[c].second && results[b].index == results[b - 1].index + 1; ++b) {
      }
      if (auto run = result_run(a, b)) add(std::move(*run));
    }
  }
  std::map<std::string, std::vector<int>> by_key;
  for (std::size_t r = 0; r < o.runs.size(); ++r)
    if (!keys[r].empty()) by_key[keys[r]].push_back(static_cast<int>(r));
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

void group_by_body(std::vector<const Assignment*>& list, const ReducedSystem& s, const ReadsOf& reads_of,
                   std::vector<int>& labels) {
  const std::size_t n = list.size();
  labels.assign(n, -1);
  if (!s.tree) return;
  const BodyTree& t = *s.tree;
  const std::size_t bodies = t.names.size();
  // Depth and preorder of the bodies (children in index order).
  std::vector<std::vector<int>> children(bodies);
  std::vector<int> roots, depth(bodies, 0), pre(bodies, 0);
  for (std::size_t b = 0; b < bodies; ++b)
    (t.parent[b] < 0 ? roots : children[static_cast<std::size_t>(t.parent[b])]).push_back(static_cast<int>(b));
  int next = 0;
  std::function<void(int, int)> visit = [&](int b, int d) {
    depth[static_cast<std::size_t>(b)] = d, pre[static_cast<std::size_t>(b)] = next++;
    for (int c : children[static_cast<std::size_t>(b)]) visit(c, d + 1);
  };
  for (int r : roots) visit(r, 0);
  // Labels: the tree's, else the deepest body of what it reads.
  std::unordered_map<int, int> label_of(t.body_of.begin(), t.body_of.end());
  std::vector<const std::unordered_set<int>*> reads(n);
  for (std::size_t i = 0; i < n; ++i) {
    reads[i] = &reads_of.at(list[i]);
    if (list[i]->block >= 0) continue;
    int best = -1;
    if (auto it = t.body_of.find(list[i]->var); it != t.body_of.end()) {
      best = it->second;
    } else {
      for (int v : *reads[i])
        if (auto it = label_of.find(v); it != label_of.end() && (best < 0 || depth[static_cast<std::size_t>(it->second)] > depth[static_cast<std::size_t>(best)]))
          best = it->second;
    }
    labels[i] = best;
    if (best >= 0) label_of[list[i]->var] = best;
  }
  // The kinematics: everything before the elimination (all of a section
  // without one: kinematics(), the poses), unless a linear block is among them.
  std::size_t end = 0;
  while (end < n && !from_tree_elimination(*list[end])) {
    if (list[end]->block >= 0) return;
    ++end;
  }
  std::vector<int> body_key(bodies);
  for (std::size_t b = 0; b < bodies; ++b) body_key[b] = pre[b];
  order_by_key(list, end, labels, body_key, reads, s.graph, /*stay=*/false);
}

void group_by_owner(std::vector<const Assignment*>& list, const ReducedSystem& s, const ReadsOf& reads_of,
                    std::vector<int>& labels, std::vector<std::string>& owners) {
  const std::size_t n = list.size();
  labels.assign(n, -1);
  owners.clear();
  std::unordered_map<std::string, int> index;
  std::vector<const std::unordered_set<int>*> reads(n);
  for (std::size_t i = 0; i < n; ++i) {
    reads[i] = &reads_of.at(list[i]);
    if (list[i]->block >= 0) continue;
    std::string owner = owner_of(s.graph.vars[static_cast<std::size_t>(list[i]->var)].name);
    if (owner.empty()) continue;
    auto [it, fresh] = index.emplace(std::move(owner), static_cast<int>(owners.size()));
    if (fresh) owners.push_back(it->first);
    labels[i] = it->second;
  }
  std::vector<int> key(owners.size());
  for (std::size_t k = 0; k < key.size(); ++k) key[k] = static_cast<int>(k);  // in order of first appearance
  order_by_key(list, n, labels, key, reads, s.graph, /*stay=*/true);
}

CppFunction shape_function(const std::string& name, const Outlining& o, int shape, const std::vector<const Assignment*>& list,
                           const std::vector<SectionResult>& results, const BondGraph& g, const Namer& names, const std::function<std::string(const SourceLoc&)>& where,
                           int& cse_counter, CppOps* ops) {
  const OutlineShape& s = o.shapes[static_cast<std::size_t>(shape)];
  const OutlinedRun& run = o.runs[static_cast<std::size_t>(s.runs[0])];
  // Names: the first body's, without its prefix; in[k], sK[k] and out[k] for what crosses the call.
  const std::string prefix = run.body + ".";
  Mangler mangle;  // the locals' identifiers: unique, never a parameter's, a keyword or cseN
  for (const std::string p : {"in", "out"}) mangle.get(p, p);
  for (std::size_t i = 0; i < run.sources.size(); ++i) mangle.get(fmt::format("s{}", i), fmt::format("s{}", i));
  std::unordered_map<int, std::string> local;
  for (int v : run.defined) {
    const std::string& full = g.vars[static_cast<std::size_t>(v)].name;
    local[v] = mangle.get(fmt::format("v{}", v), full.rfind(prefix, 0) == 0 ? full.substr(prefix.size()) : full);
  }
  std::vector<std::string> bodies, params = {"const double* in"}, outs;
  for (int r : s.runs) bodies.push_back(o.runs[static_cast<std::size_t>(r)].body);
  ExprNames known;
  for (std::size_t k = 0; k < run.inputs.size(); ++k) known.emplace(run.inputs[k], fmt::format("in[{}]", k));
  for (std::size_t i = 0; i < run.sources.size(); ++i) {
    const OutlinedRun& src = o.runs[static_cast<std::size_t>(run.sources[i])];
    for (std::size_t k = 0; k < src.outputs.size(); ++k)
      known.emplace(var(src.defined[src.outputs[k]]), fmt::format("s{}[{}]", i, src.slots[k]));
    params.push_back(fmt::format("const double* s{}", i));
  }
  params.push_back("double* out");
  for (std::size_t k = 0; k < run.outputs.size(); ++k) outs.push_back(local.at(run.defined[run.outputs[k]]));
  const char* sources = run.sources.empty() ? "" : ", sK[] the outputs of the runs they read";
  CppFunction f{run.results ? fmt::format("{}[] of {}, the same up to their names (written with {}'s): in[] what they read{}, "
                                          "out[] the caller's {}[] from the first one's place.",
                                          results[run.begin].array, fmt::join(bodies, ", "), run.body, sources, results[run.begin].array)
                            : fmt::format("Equations of {}{}, the same up to their names (written with {}'s): in[] what they "
                                          "read{}, out[] what the rest of the model reads of them: {}.",
                                          o.by_owner ? "" : "bodies ", fmt::join(bodies, ", "), run.body, sources, fmt::join(outs, ", ")),
                fmt::format("static void {}({})", name, fmt::join(params, ", ")),
                {}};
  if (run.inputs.empty()) f.body.push_back(CppStmt::line("(void)in;  // (reads nothing but its sources: called with nullptr)"));
  Namer inside = names;
  inside.var = [&](int id) { return local.count(id) ? local.at(id) : names.var(id); };
  const std::size_t from = f.body.size();
  std::string last;
  if (run.results) {
    for (std::size_t i = run.begin; i < run.end; ++i) {
      const SectionResult& r = results[i];
      std::string origin = !r.loc.valid() ? r.origin : r.origin.empty() ? where(r.loc) : fmt::format("{}  {}", where(r.loc), r.origin);
      if (!origin.empty() && origin != last) f.body.push_back(CppStmt::comment(origin));
      last = std::move(origin);
      f.body.push_back(CppStmt::assign(fmt::format("out[{}]", run.offsets[i - run.begin]), r.value));
    }
  } else {
    for (std::size_t i = run.begin; i < run.end; ++i) {
      const Assignment& a = *list[i];
      std::string origin = fmt::format("{}  {}", where(a.loc), a.origin);
      if (origin != last) f.body.push_back(CppStmt::comment(origin));
      last = std::move(origin);
      f.body.push_back(CppStmt::local(local.at(a.var), a.value));
      f.body.back().may_name = CppStmt::Naming::unnamed;
    }
    for (std::size_t k = 0; k < outs.size(); ++k) f.body.push_back(CppStmt::assign(fmt::format("out[{}]", run.slots[k]), outs[k]));
  }
  share_subexpressions(f.body, from, known, cse_counter);
  render(f.body, from, known, inside, ops);
  return f;
}

}  // namespace mbgc::codegen
