// mbgrt/fmu.hpp — what a generated model tells the runtime's Functional
// Mock-up Interface (FMI 3.0 and 2.0) shim when it is built into an FMU
// (`mbgc model.mbg --fmu model.fmu`, docs/fmi.md).
//
// The compiler writes modelDescription.xml and, into the FMU's C++ source,
// the same variables as a table: a value reference is its row's index. The
// runtime (runtime/src/fmi/) implements the FMI functions over mbgrt::Model
// and reads nothing else of the model: what each value reference is comes
// from this table, never from names.
#pragma once

#include <cstddef>
#include <memory>

#include "mbgrt/model.hpp"

namespace mbgrt::fmu {

/// What a value reference names.
enum class Kind : unsigned char {
  time,             ///< the independent variable
  parameter,        ///< Model::parameters()[index], in its declared unit (as --set takes it)
  output,           ///< Model::outputs()[index]
  state,            ///< unknown `index` of y (a continuous state)
  derivative,       ///< its derivative
  event_indicator,  ///< Model::event_functions()[index]
  setting,          ///< a run setting of the FMU's own integrators (co-simulation): Setting(index)
  constant,         ///< a compile-time parameter (a loop bound, a beam's length): Description::constants[index]
  calculated,       ///< a parameter computed from others: Model::parameter_values()[index] (SI)
};

/// The run settings an importer may set before initialisation (co-simulation
/// integrates with the runtime's methods); their defaults are the model's
/// `simulate { }` block.
enum class Setting : unsigned char {
  solver,  ///< an Enumeration: mbgrt::Solver's value + 1
  rtol,
  atol,
  step,    ///< fixed-step methods' step (s)
};

struct Variable {
  Kind kind;
  unsigned index;
};

/// One FMU's model: its variables by value reference and how to make it.
struct Description {
  const char* model_identifier;     ///< the shared object's name, the FMI functions' prefix-free identity
  const char* instantiation_token;  ///< FMI 3 instantiationToken, FMI 2 guid: a hash of the generated source
  const Variable* variables;        ///< indexed by value reference
  std::size_t variable_count;
  std::unique_ptr<Model> (*make_model)();
  const double* constants;          ///< the compile-time parameters' values (Kind::constant), in their declared units
};

/// Defined by the FMU's generated source (mbgc --fmu); the FMI functions read it.
const Description& description();

}  // namespace mbgrt::fmu
