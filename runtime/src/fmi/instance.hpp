// fmi/instance.hpp — one instance of an FMU, whatever the FMI version: the
// model, its state and the FMI state machine. fmi3.cpp and fmi2.cpp are thin
// C shims that translate their arguments and call these methods.
//
// Model exchange: the importer integrates; the instance evaluates the model
// at the time and states it is given (through the guard, so that a NaN or a
// state beyond its limit is an error with the runtime's report, never a
// value handed on), and at an event switches the modes whose functions
// changed sign since the last event, as the runtime's own fixed-step methods
// do (Events::fire: impacts, contacts made and lost).
// Co-simulation: doStep runs the runtime's integrator (Integrator::advance_to,
// which locates and handles the events inside the step) from the
// communication point to the next.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "guard.hpp"
#include "integrator.hpp"
#include "mbgrt/fmu.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::fmu {

/// The first five of fmi3Status and fmi2Status, in their order.
enum class Status { ok, warning, discard, error, fatal };

enum class Interface { model_exchange, co_simulation };

/// Where an instance is in the FMI state machine (the FMI 3.0 names; FMI 2.0's
/// map onto them).
enum class Phase { instantiated, initialization, event, continuous_time, step, terminated, failed };

/// An instance's state at a moment (FMI's FMU state): enough to go on from
/// there in this instance or another of the same FMU. In co-simulation the
/// integrator starts again from it (a multistep method's history is not
/// kept: an adaptive run continued from a state agrees with the uninterrupted
/// one to its tolerance, a fixed-step one exactly).
struct Snapshot {
  Phase phase = Phase::instantiated;
  double t = 0.0, stop = 0.0, integrate_until = 0.0;
  bool stop_defined = false;
  Settings settings;  ///< of which the state keeps what an importer sets: solver, rtol, atol, step_s
  std::vector<double> parameters, parameter_set;
  std::vector<double> y, reference;  ///< the states; the event functions after the last event
  std::vector<double> held;          ///< Model::get_held_state
  std::vector<double> runtime;       ///< detail::Events::save

  /// The bytes of FMI's serialised state: a tag, the FMU's token, the numbers.
  std::vector<unsigned char> serialize(const std::string& token) const;
  /// The state `bytes` hold into `out`, or false and `why` (not this FMU's, truncated).
  static bool deserialize(const unsigned char* bytes, std::size_t size, const std::string& token, Snapshot& out,
                          std::string& why);
};

/// The importer's logger: severity, category ("logEvents", "logStatusError",
/// ...), message.
using Logger = std::function<void(Status, const char*, const std::string&)>;

class Instance {
 public:
  Instance(const Description& description, Interface interface, std::string name, Logger logger, bool logging_on);
  ~Instance();

  const std::string& name() const { return name_; }
  Interface interface() const { return interface_; }
  Phase phase() const { return phase_; }
  double time() const { return t_; }
  void set_logging(bool on) { logging_on_ = on; }

  // ---- the lifecycle ------------------------------------------------------------
  /// The run's start and, if defined, its tolerance (the integrators' rtol in
  /// co-simulation) and stop time (FMI 2's SetupExperiment; FMI 3 passes them
  /// to EnterInitializationMode).
  Status setup_experiment(double start, bool tolerance_defined, double tolerance, bool stop_defined, double stop);
  Status enter_initialization();
  Status exit_initialization();
  Status enter_event_mode();
  Status enter_continuous_time_mode();
  Status enter_step_mode();
  Status terminate();
  Status reset();

  // ---- values by reference --------------------------------------------------------
  Status get_float64(const std::uint32_t* vr, std::size_t n, double* values);
  Status set_float64(const std::uint32_t* vr, std::size_t n, const double* values);
  /// The integrator (Setting::solver), an Enumeration.
  Status get_int64(const std::uint32_t* vr, std::size_t n, std::int64_t* values);
  Status set_int64(const std::uint32_t* vr, std::size_t n, const std::int64_t* values);

  // ---- model exchange -------------------------------------------------------------
  std::size_t state_count() const { return n_; }
  std::size_t event_indicator_count() const;
  Status set_time(double t);
  Status set_states(const double* x, std::size_t n);
  Status get_states(double* x, std::size_t n);
  Status get_derivatives(double* dx, std::size_t n);
  Status get_event_indicators(double* g, std::size_t n);
  Status get_nominals(double* nominal, std::size_t n);
  Status completed_integrator_step(bool* enter_event_mode, bool* terminate_simulation);
  Status update_discrete_states(bool* values_changed, bool* terminate_simulation);

  /// The derivatives of the unknowns (state derivatives, outputs) along the
  /// states' seed, at the current time and states: the model's own Jacobian
  /// where every unknown is a state derivative, else central differences.
  Status directional_derivative(const std::uint32_t* unknowns, std::size_t n_unknowns, const std::uint32_t* knowns,
                                std::size_t n_knowns, const double* seed, double* sensitivity);

  // ---- the FMU state ----------------------------------------------------------
  Status get_state(Snapshot& out);
  Status set_state(const Snapshot& state);
  const char* token() const { return description_.instantiation_token; }
  /// The states this instance handed out (the importer's handles), freed
  /// with it: a handle is only ever dereferenced if it is one of them.
  Snapshot* new_snapshot();
  bool owns(const void* state) const;
  void release(Snapshot* state);

  // ---- co-simulation ------------------------------------------------------------
  /// The importer lets doStep return early (FMI 3.0's earlyReturnAllowed):
  /// a step then ends at the first event inside it.
  void allow_early_return(bool allowed) { early_return_allowed_ = allowed; }
  /// From t over h: to t + h, or (early return allowed) to the first event
  /// inside (`early_return` set, `last_successful_time` its time).
  Status do_step(double t, double h, bool* terminate_simulation, bool* early_return, double* last_successful_time);

  /// An error of the importer's making (a call out of order, a bad argument):
  /// logged, fmi*Error returned.
  Status refuse(const std::string& why);
  /// Checks that the call `what` may come in this phase.
  bool allowed(const char* what, std::initializer_list<Phase> phases);
  /// The description of a value reference the importer passed, or null (and
  /// the error logged).
  const Variable* variable(std::uint32_t vr);

 private:
  Status fail(const std::string& why);  ///< the model cannot go on: logged, the instance fails
  void log(Status status, const char* category, const std::string& message);
  /// Runs `body` with the runtime's diagnostics (print_error and the stop
  /// reports) captured and handed to the importer's logger.
  template <class Body>
  Status captured(Body&& body);
  void invalidate() { outputs_valid_ = derivatives_valid_ = false; }
  bool evaluate_derivatives();
  bool evaluate_outputs();
  Settings run_settings() const;

  const Description& description_;
  Interface interface_;
  std::string name_;
  Logger logger_;
  bool logging_on_;
  bool early_return_allowed_ = false;
  Phase phase_ = Phase::instantiated;

  std::unique_ptr<Model> model_;
  std::unique_ptr<detail::GuardedModel> guard_;
  std::unique_ptr<detail::Integrator> integrator_;  ///< co-simulation
  std::size_t n_ = 0;
  std::vector<ParameterInfo> parameters_;
  std::vector<double> parameter_values_;  ///< in each parameter's declared unit
  std::vector<double> calculated_;        ///< Model::parameter_values() (SI), read for Kind::calculated
  std::vector<char> parameter_set_;
  Settings defaults_, settings_;
  double t_ = 0.0, stop_ = 0.0;
  double integrate_until_ = 0.0;  ///< co-simulation: the integrator's stop time (run_settings)
  bool stop_defined_ = false;
  std::vector<double> y_, ydot_, outputs_, indicators_, reference_;  ///< reference_: the event functions after the last event
  bool outputs_valid_ = false, derivatives_valid_ = false;
  std::vector<std::unique_ptr<Snapshot>> snapshots_;
};

/// What every FMI function does with its instance (void* in C): `body` on it,
/// an exception logged and turned into an error; a null instance is an error.
template <class Body>
Status call(void* instance, const char* what, Body&& body) {
  if (!instance) return Status::error;
  Instance& i = *static_cast<Instance*>(instance);
  try {
    return body(i);
  } catch (const std::exception& e) {
    return i.refuse(std::string(what) + ": " + e.what());
  } catch (...) {
    return i.refuse(std::string(what) + ": an unexpected error");
  }
}

/// A new instance of this FMU, or null with the reason logged: `token` (the
/// importer's copy of the instantiation token, FMI 2's GUID: `token_name`)
/// must be this FMU's.
Instance* instantiate(Interface interface, const std::string& name, const char* token, const char* token_name,
                      const Logger& logger, bool logging_on);

/// FMI's FMU-state functions over an instance, for both versions' shims:
/// `state` is the importer's handle (a Snapshot*).
Status get_fmu_state(void* instance, void** state);
Status set_fmu_state(void* instance, void* state);
Status free_fmu_state(void* instance, void** state);
Status serialized_fmu_state_size(void* instance, void* state, std::size_t* size);
Status serialize_fmu_state(void* instance, void* state, unsigned char* bytes, std::size_t size);
Status deserialize_fmu_state(void* instance, const unsigned char* bytes, std::size_t size, void** state);

/// A function for something this FMU does not have (clocks, types it has no
/// variables of): logged, an error.
Status absent(void* instance, const char* what);

}  // namespace mbgrt::fmu
