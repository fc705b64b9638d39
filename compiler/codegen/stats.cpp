// codegen/stats.cpp — mbgc --stats: what each generated method costs per call
// (operations counted by the printer, see ir::to_cpp) and its size.
#include "codegen/stats.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace mbgc::codegen {
namespace {

struct Row {
  std::string name;
  std::size_t lines = 0, bytes = 0;
  bool has_ops = true;
  ir::CppOps ops;
  std::vector<std::size_t> solves;
  std::size_t solve_ops = 0;
  std::size_t total() const { return ops.total() + solve_ops; }
};

std::vector<Row> rows_of(const EmitStats& stats) {
  std::vector<Row> rows;
  Row total;
  total.name = "total";
  for (const FunctionStats& f : stats.functions) {
    Row r;
    r.name = f.name;
    r.lines = f.lines;
    r.bytes = f.bytes;
    r.ops = f.ops;
    r.solves = f.solves;
    r.solve_ops = f.solve_ops;
    rows.push_back(r);
    total.lines += f.lines;
    total.bytes += f.bytes;
    total.ops += f.ops;
    total.solves.insert(total.solves.end(), f.solves.begin(), f.solves.end());
    total.solve_ops += f.solve_ops;
  }
  rows.push_back(total);
  Row file;
  file.name = "file";
  file.lines = stats.file_lines;
  file.bytes = stats.file_bytes;
  file.has_ops = false;
  rows.push_back(file);
  return rows;
}

std::string sizes(const std::vector<std::size_t>& solves, const char* sep) {
  return fmt::format("{}", fmt::join(solves, sep));
}

}  // namespace

EmitStats collect_stats(const CppClass& c, const std::string& out, const std::map<std::string, MethodCost>& costs,
                        const ir::ReducedSystem& s) {
  EmitStats stats;
  stats.model = s.graph.model_name;
  stats.dae = s.dae;
  stats.states = s.states.size();
  stats.algebraic = s.algebraic.size();
  // both forms print the class inside a namespace, its methods two levels in
  const int indent = 2;
  for (const auto* methods : {&c.public_methods, &c.private_methods})
    for (const CppFunction& f : *methods) {
      FunctionStats fs;
      const std::string& sig = f.signature;
      auto open = sig.find('(');
      auto start = sig.find_last_of(' ', open);
      fs.name = sig.substr(start == std::string::npos ? 0 : start + 1, open - (start == std::string::npos ? 0 : start + 1));
      std::string text = print(f, indent);
      fs.bytes = text.size();
      fs.lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
      if (auto it = costs.find(sig); it != costs.end()) {
        fs.ops = it->second.ops;
        fs.solves = it->second.solves;
        for (std::size_t n : fs.solves) fs.solve_ops += solve_linear_ops(n);
      }
      stats.functions.push_back(std::move(fs));
    }
  // A long method's parts (NAME_partK) and its shapes' functions
  // (NAME_shapeK, whose operations count in NAME once per call) count as
  // lines and bytes of NAME. witness_values() (codegen/shared_values) has a
  // row of its own for its lines and bytes; its operations count in each of
  // its callers, once per call.
  for (auto it = stats.functions.begin(); it != stats.functions.end();) {
    auto cut = it->name.rfind("_part");
    if (cut == std::string::npos) cut = it->name.rfind("_shape");
    auto base = cut == std::string::npos ? stats.functions.end()
                                         : std::find_if(stats.functions.begin(), stats.functions.end(),
                                                        [&](const FunctionStats& g) { return g.name == it->name.substr(0, cut); });
    if (base == stats.functions.end()) {
      ++it;
      continue;
    }
    base->lines += it->lines;
    base->bytes += it->bytes;
    it = stats.functions.erase(it);
  }
  stats.file_bytes = out.size();
  stats.file_lines = static_cast<std::size_t>(std::count(out.begin(), out.end(), '\n'));
  return stats;
}

std::string format_stats(const EmitStats& stats, bool csv) {
  const std::vector<Row> rows = rows_of(stats);
  std::string out;
  if (csv) {
    out += "function,lines,bytes,ops,add,mul,div,neg,call,compare,solve_sizes,solve_ops\n";
    for (const Row& r : rows) {
      if (!r.has_ops) {
        out += fmt::format("{},{},{},,,,,,,,,\n", r.name, r.lines, r.bytes);
        continue;
      }
      out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", r.name, r.lines, r.bytes, r.total(), r.ops.add,
                         r.ops.mul, r.ops.div, r.ops.neg, r.ops.call, r.ops.compare, sizes(r.solves, ";"),
                         r.solve_ops);
    }
    return out;
  }
  out += fmt::format("model {}: {}, {} state{}", stats.model, stats.dae ? "DAE" : "ODE", stats.states,
                     stats.states == 1 ? "" : "s");
  if (stats.dae) out += fmt::format(", {} algebraic unknown{}", stats.algebraic, stats.algebraic == 1 ? "" : "s");
  out += "\n";
  out += "operations per call, as written: ops = add (+ -) + mul + div + neg (unary -) + call (math functions)\n"
         "  + compare (step, sign) + solve (mbgrt::solve_linear's arithmetic, (4n^3 + 9n^2 - 7n)/6 for n x n)\n\n";
  out += fmt::format("{:<28} {:>7} {:>9} {:>9} {:>8} {:>8} {:>7} {:>7} {:>7} {:>7} {:>8}  {}\n", "function", "lines",
                     "bytes", "ops", "add", "mul", "div", "neg", "call", "compare", "solve", "solve sizes");
  for (const Row& r : rows) {
    if (!r.has_ops) {
      out += fmt::format("{:<28} {:>7} {:>9}\n", r.name, r.lines, r.bytes);
      continue;
    }
    std::string line = fmt::format("{:<28} {:>7} {:>9} {:>9} {:>8} {:>8} {:>7} {:>7} {:>7} {:>7} {:>8}  {}", r.name,
                                   r.lines, r.bytes, r.total(), r.ops.add, r.ops.mul, r.ops.div, r.ops.neg, r.ops.call,
                                   r.ops.compare, r.solve_ops, sizes(r.solves, " "));
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

}  // namespace mbgc::codegen
