// fmu/interface.cpp — see interface.hpp.
#include "fmu/interface.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <map>

#include "codegen/names.hpp"
#include "codegen/events.hpp"
#include "codegen/identity.hpp"
#include "mbgrt/integrators.hpp"
#include "reduce/parameter_use.hpp"
#include "reduce/sparsity.hpp"

namespace mbgc::fmu {
namespace {

/// The comment that ends the model line at `loc` (`// armature resistance`),
/// without its slashes; empty if there is none.
std::string trailing_comment(const ir::SourceManager& sources, const ir::SourceLoc& loc) {
  if (!loc.valid()) return {};
  const std::string line = sources.line_text(loc.file, loc.line);
  bool quoted = false;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    if (line[i] == '"') quoted = !quoted;
    if (quoted || line[i] != '/' || line[i + 1] != '/') continue;
    std::string text = line.substr(i + 2);
    const auto first = text.find_first_not_of(" \t/");
    if (first == std::string::npos) return {};
    text.erase(0, first);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.pop_back();
    return text;
  }
  return {};
}

/// The model file's description: the comment lines it opens with, joined.
std::string file_description(const ir::SourceManager& sources, const ir::SourceLoc& any) {
  if (!any.valid()) return {};
  std::string out;
  const auto lines = static_cast<int>(sources.file(any.file).line_starts.size());
  for (int line = 1; line <= lines; ++line) {
    const std::string text = sources.line_text(any.file, line);
    const auto first = text.find_first_not_of(" \t");
    if (first == std::string::npos || text.compare(first, 2, "//") != 0) break;
    std::string words = text.substr(first + 2);
    const auto start = words.find_first_not_of(" \t/");
    if (start == std::string::npos) continue;
    out += (out.empty() ? "" : " ") + words.substr(start);
  }
  return out;
}

Variable variable(std::string name, Kind kind, unsigned index, Type type = Type::float64) {
  Variable v;
  v.name = std::move(name);
  v.kind = kind;
  v.index = index;
  v.type = type;
  return v;
}

class Builder {
 public:
  explicit Builder(Interface& fmu) : fmu_(fmu) {}

  unsigned add(Variable v) {
    fmu_.variables.push_back(std::move(v));
    return static_cast<unsigned>(fmu_.variables.size() - 1);
  }

  /// The unit named `name` (declared with `scale`, of `dimension`), once.
  std::string unit(const std::string& name, std::optional<units::Dimension> dimension, double scale) {
    if (name.empty()) return {};
    if (seen_.emplace(name, fmu_.units.size()).second) fmu_.units.push_back({name, dimension, scale});
    return name;
  }

 private:
  Interface& fmu_;
  std::map<std::string, std::size_t> seen_;
};

/// A parameter computed from others (a body's mass from its shape): read
/// once the model is initialised, in SI; its formula says what it is.
Variable calculated_parameter(const ir::Parameter& p, std::size_t index, Builder& b, const ir::SourceManager& sources,
                              const ir::BondGraph& g) {
  Variable v = variable(p.name, Kind::calculated, static_cast<unsigned>(index));
  v.causality = Causality::calculated_parameter;
  v.variability = Variability::fixed;
  if (p.dimension && !p.dimension->is_none()) v.unit = b.unit(units::format(*p.dimension), p.dimension, 1.0);
  const std::string comment = trailing_comment(sources, p.loc);
  v.description = (comment.empty() ? "" : comment + "; ") + codegen::computed_doc(p, g);
  return v;
}

}  // namespace

Interface describe(const ir::ReducedSystem& s, const ir::SourceManager& sources) {
  const ir::BondGraph& g = s.graph;
  Interface fmu;
  fmu.model_name = g.model_name;
  fmu.dae = s.dae;
  fmu.states = s.states.size() + s.algebraic.size();
  fmu.event_indicators = s.events.size();
  Builder b(fmu);
  Variable time = variable("time", Kind::time, 0);
  time.causality = Causality::independent;
  time.unit = "s";
  time.description = "simulation time";
  b.add(std::move(time));
  b.unit("s", units::dim::time(), 1.0);

  // Parameters: as --set takes them, in their declared unit. Those computed
  // from others have no value of their own to start from. Those the run
  // never reads (the compiler used them up) are constants, and say so.
  const std::vector<bool> read = reduce::parameters_read(s);
  for (std::size_t i = 0; i < g.params.size(); ++i) {
    const ir::Parameter& p = g.params[i];
    if (!p.literal) {
      if (read[i]) b.add(calculated_parameter(p, i, b, sources, g));
      continue;
    }
    if (fmu.description.empty()) fmu.description = file_description(sources, p.loc);
    Variable v = variable(p.name, read[i] ? Kind::parameter : Kind::constant,
                          static_cast<unsigned>(read[i] ? i : fmu.constants.size()));
    if (read[i]) {
      v.causality = Causality::parameter;
      v.variability = Variability::fixed;
    } else {
      v.variability = Variability::constant;
    }
    if (p.unit) {
      v.start = p.literal_value / p.unit->unit.scale;
      v.unit = b.unit(p.unit->unit.text, p.unit->unit.dimension, p.unit->unit.scale);
    } else {
      v.start = p.literal_value;
      if (p.dimension && !p.dimension->is_none()) v.unit = b.unit(units::format(*p.dimension), p.dimension, 1.0);
    }
    v.description = trailing_comment(sources, p.loc);
    if (!read[i]) {
      fmu.constants.push_back(*v.start);
      v.description += fmt::format("{}used up when mbgc compiled the model, fixed in this FMU (mbgc --set {}=VALUE "
                                   "exports another)",
                                   v.description.empty() ? "" : "; ", p.name);
    }
    b.add(std::move(v));
  }
  // The solver settings of co-simulation (the runtime's integrators).
  {
    const ir::SimSettings& ss = g.settings;
    mbgrt::Settings settings;
    if (ss.t_end) settings.t_end_s = *ss.t_end;
    if (ss.interval) settings.interval_s = *ss.interval;
    if (ss.rtol) settings.rtol = *ss.rtol;
    if (ss.atol) settings.atol = *ss.atol;
    settings.step_s = ss.step ? *ss.step : settings.interval_s / 10;
    const mbgrt::IntegratorInfo* solver = ss.solver ? mbgrt::find_integrator(*ss.solver) : nullptr;
    settings.solver = solver ? solver->solver : s.dae ? mbgrt::kDefaultDaeSolver : mbgrt::kDefaultOdeSolver;
    fmu.defaults = settings;
  }
  Variable solver = variable("solver.method", Kind::setting, static_cast<unsigned>(mbgrt::fmu::Setting::solver), Type::enumeration);
  solver.causality = Causality::parameter;
  solver.variability = Variability::fixed;
  solver.start = static_cast<double>(static_cast<int>(fmu.defaults.solver) + 1);
  solver.description = "co-simulation: the integrator doStep runs (the simulators' --solver)";
  b.add(solver);
  const struct {
    const char* name;
    mbgrt::fmu::Setting setting;
    double value;
    const char* unit;
    const char* description;
  } settings[] = {
      {"solver.rtol", mbgrt::fmu::Setting::rtol, fmu.defaults.rtol, "",
       "co-simulation: the adaptive integrators' relative tolerance (--rtol)"},
      {"solver.atol", mbgrt::fmu::Setting::atol, fmu.defaults.atol, "",
       "co-simulation: their absolute tolerance, times each state's nominal size (--atol)"},
      {"solver.step", mbgrt::fmu::Setting::step, fmu.defaults.step_s, "s",
       "co-simulation: the fixed-step methods' step (--step)"},
  };
  for (const auto& st : settings) {
    Variable v = variable(st.name, Kind::setting, static_cast<unsigned>(st.setting));
    v.causality = Causality::parameter;
    v.variability = Variability::fixed;
    v.start = st.value;
    v.unit = st.unit;
    v.description = st.description;
    b.add(std::move(v));
  }

  std::vector<unsigned> output_refs;
  for (std::size_t i = 0; i < g.outputs.size(); ++i) {
    const ir::Output& o = g.outputs[i];
    if (fmu.description.empty()) fmu.description = file_description(sources, o.loc);
    Variable v = variable(o.name, Kind::output, static_cast<unsigned>(i));
    v.causality = Causality::output;
    // an output's values are in SI: its declared unit where that is SI, else the SI unit of its dimension
    if (o.unit && o.unit->unit.is_si()) v.unit = b.unit(o.unit->unit.text, o.unit->unit.dimension, 1.0);
    else if (o.dimension && !o.dimension->is_none()) v.unit = b.unit(units::format(*o.dimension), o.dimension, 1.0);
    v.description = trailing_comment(sources, o.loc);
    output_refs.push_back(b.add(std::move(v)));
  }

  std::vector<unsigned> state_refs;
  for (std::size_t i = 0; i < s.states.size(); ++i) {
    const ir::Variable& var = g.vars[static_cast<std::size_t>(s.states[i].var)];
    Variable v = variable(var.name, Kind::state, static_cast<unsigned>(i));
    v.description = "a continuous state";
    state_refs.push_back(b.add(std::move(v)));
  }
  std::vector<unsigned> derivative_refs;
  for (std::size_t i = 0; i < s.states.size(); ++i) {
    const ir::Variable& var = g.vars[static_cast<std::size_t>(s.states[i].var)];
    Variable v = variable("der(" + var.name + ")", Kind::derivative, static_cast<unsigned>(i));
    v.derivative_of = state_refs[i];
    derivative_refs.push_back(b.add(std::move(v)));
  }
  const ir::Namer names = codegen::names_for_dump(g);
  const auto where = [&sources](const ir::SourceLoc& loc) { return sources.where(loc); };
  std::vector<unsigned> event_refs;
  for (std::size_t k = 0; k < s.events.size(); ++k) {
    Variable v = variable(fmt::format("events[{}]", k), Kind::event_indicator, static_cast<unsigned>(k));
    v.description = codegen::event_name(s.events[k], names, where);
    event_refs.push_back(b.add(std::move(v)));
  }

  // ModelStructure: what each output, derivative and event indicator reads
  // of the knowns (the states and time), as the reduced equations say.
  const auto depend = [&](const std::vector<unsigned>& refs, const std::vector<ir::Expr>& values) {
    const std::vector<reduce::StateReads> reads = reduce::state_reads(s, values);
    for (std::size_t i = 0; i < refs.size(); ++i) {
      std::vector<unsigned> known;
      if (reads[i].time) known.push_back(0);  // time's value reference
      for (int state : reads[i].states) known.push_back(state_refs[static_cast<std::size_t>(state)]);
      fmu.variables[refs[i]].dependencies = std::move(known);
    }
  };
  std::vector<ir::Expr> output_values, event_values;
  for (const ir::Output& o : g.outputs) output_values.push_back(o.value);
  for (const ir::EventRelation& e : s.events) event_values.push_back(e.arg);
  depend(output_refs, output_values);
  depend(derivative_refs, s.state_derivative);
  depend(event_refs, event_values);
  return fmu;
}

std::string entry_source(const Interface& fmu, const std::string& class_name) {
  static const char* const kKinds[] = {"time",       "parameter",       "output",  "state",
                                       "derivative", "event_indicator", "setting", "constant", "calculated"};
  std::string rows;
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr) {
    const Variable& v = fmu.variables[vr];
    rows += fmt::format("    {{K::{}, {}}},  // {}: {}\n", kKinds[static_cast<int>(v.kind)], v.index, vr, v.name);
  }
  // (an empty array is not C++: a 0 nobody reads)
  std::string constants = fmu.constants.empty() ? "0.0" : "";
  for (double c : fmu.constants) constants += (constants.empty() ? "" : ", ") + codegen::cpp_double(c);
  return fmt::format(
      "// The FMU's entry (mbgc --fmu): its variables by value reference, as\n"
      "// modelDescription.xml lists them, and the model they belong to. The\n"
      "// runtime's FMI functions (runtime/src/fmi/) read them.\n"
      "#include <mbgrt/fmu.hpp>\n\n"
      "namespace mbgrt::fmu {{\n\n"
      "const Description& description() {{\n"
      "  using K = Kind;\n"
      "  static const Variable kVariables[] = {{\n{}  }};\n"
      "  static const double kConstants[] = {{{}}};  // the compile-time parameters' values\n"
      "  static const Description kDescription{{\n"
      "      {}, {},\n"
      "      kVariables, {},\n"
      "      [] {{ return std::unique_ptr<Model>(new ::{}()); }},\n"
      "      kConstants}};\n"
      "  return kDescription;\n"
      "}}\n\n"
      "}}  // namespace mbgrt::fmu\n",
      rows, constants, codegen::cpp_string(fmu.model_name), codegen::cpp_string(kTokenPlaceholder), fmu.variables.size(),
      class_name);
}

std::string token_of(const std::string& source) {
  // FNV-1a, 64 bits, twice (from two offsets): 128 bits of the text, spelt as a UUID
  auto fnv = [&source](std::uint64_t h) {
    for (unsigned char c : source) h = (h ^ c) * 1099511628211ull;
    return h;
  };
  const std::uint64_t a = fnv(14695981039346656037ull), b = fnv(0x6c62272e07bb0142ull);
  return fmt::format("{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}", a >> 32, (a >> 16) & 0xffff, a & 0xffff, b >> 48,
                     b & 0xffffffffffffull);
}

}  // namespace mbgc::fmu
