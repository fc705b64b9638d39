// fmu/interface.hpp — what an FMU of the model offers (mbgc --fmu): its
// variables in value-reference order, built once from the reduced system.
// modelDescription.xml (fmu/model_description.hpp) and the table compiled
// into the FMU (fmu/entry.hpp, read by runtime/src/fmi/) are both written
// from it, so that the two cannot disagree.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"
#include "ir/reduced.hpp"
#include "mbgrt/fmu.hpp"
#include "mbgrt/model.hpp"
#include "units/unit.hpp"

namespace mbgc::fmu {

using mbgrt::fmu::Kind;

enum class Causality { independent, parameter, calculated_parameter, output, local };
enum class Variability { continuous, fixed, constant };
enum class Type { float64, enumeration };

struct Variable {
  std::string name;
  Kind kind = Kind::time;
  unsigned index = 0;  ///< within its kind (mbgrt::fmu::Variable::index)
  Type type = Type::float64;
  Causality causality = Causality::local;
  Variability variability = Variability::continuous;
  std::optional<double> start;  ///< given for what the importer may set (parameters, settings)
  std::string unit;             ///< a Unit's name (Interface::units), or empty
  std::string description;
  long derivative_of = -1;      ///< a derivative: its state's value reference
  /// An output, a derivative or an event indicator: the value references of
  /// the knowns it reads (states, time), ascending (ModelStructure).
  std::optional<std::vector<unsigned>> dependencies;
};

/// A unit of the FMU's variables: its name (as the model writes it) and, where
/// its exponents are whole, its SI base units and factor (FMI's BaseUnit).
struct Unit {
  std::string name;
  std::optional<units::Dimension> dimension;
  double factor = 1.0;  ///< SI value = value x factor
};

struct Interface {
  std::string model_name;
  std::string description;  ///< the model file's first comment line, if any
  std::vector<Variable> variables;  ///< indexed by value reference
  std::vector<Unit> units;
  std::vector<double> constants;    ///< Kind::constant's values, by index
  mbgrt::Settings defaults;         ///< the model's simulate { } block (DefaultExperiment)
  std::size_t states = 0, event_indicators = 0;
  bool dae = false;
};

/// The FMU's interface of `system`; descriptions come from the model lines'
/// trailing comments (`param R = 0.4 {Ohm}  // armature resistance`). A
/// parameter the run never reads (the compiler used it up: a loop bound, a
/// beam's length) is a constant.
Interface describe(const ir::ReducedSystem& system, const ir::SourceManager& sources);

/// The table the FMU's shared object reads (mbgrt::fmu::description()): C++
/// text defining it, with `class_name` the generated model class and the
/// instantiation token spelled kTokenPlaceholder (fmu::seal replaces it).
std::string entry_source(const Interface& fmu, const std::string& class_name);

/// What entry_source writes where the token goes.
inline constexpr const char* kTokenPlaceholder = "@MBGC_FMU_TOKEN@";

/// The instantiation token of a generated source (with the placeholder in
/// it): a hash of its text, as a UUID in braces, the same on every platform.
std::string token_of(const std::string& source);

}  // namespace mbgc::fmu
