#include "fmi/instance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>

#include "messages.hpp"
#include "constraints.hpp"
#include "march.hpp"
#include "report.hpp"

namespace mbgrt::fmu {

namespace {

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::time: return "the time";
    case Kind::parameter: return "a parameter";
    case Kind::output: return "an output";
    case Kind::state: return "a continuous state";
    case Kind::derivative: return "a state derivative";
    case Kind::event_indicator: return "an event indicator";
    case Kind::setting: return "a solver setting";
    case Kind::constant: return "a compile-time parameter (fixed when mbgc compiled the model: mbgc --set changes it)";
    case Kind::calculated: return "a parameter computed from others (set those)";
  }
  return "a variable";
}

const char* phase_name(Phase p) {
  switch (p) {
    case Phase::instantiated: return "Instantiated";
    case Phase::initialization: return "Initialization Mode";
    case Phase::event: return "Event Mode";
    case Phase::continuous_time: return "Continuous-Time Mode";
    case Phase::step: return "Step Mode";
    case Phase::terminated: return "Terminated";
    case Phase::failed: return "an error state (a call failed)";
  }
  return "?";
}

/// The runtime's "mbgrt: error: ..." lines, one by one, with their severity.
void forward_lines(const std::string& text, const std::function<void(Status, const std::string&)>& to) {
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.empty()) continue;
    Status status = Status::ok;
    if (line.rfind("mbgrt: error: ", 0) == 0) status = Status::error, line.erase(0, 14);
    else if (line.rfind("mbgrt: warning: ", 0) == 0) status = Status::warning, line.erase(0, 16);
    else if (line.rfind("mbgrt: note: ", 0) == 0) line.erase(0, 13);
    to(status, line);
  }
}

}  // namespace

Instance::Instance(const Description& description, Interface interface, std::string name, Logger logger,
                   bool logging_on)
    : description_(description),
      interface_(interface),
      name_(std::move(name)),
      logger_(std::move(logger)),
      logging_on_(logging_on) {
  model_ = description_.make_model();
  n_ = model_->size();
  parameters_ = model_->parameters();
  parameter_values_.resize(parameters_.size());
  for (std::size_t i = 0; i < parameters_.size(); ++i) parameter_values_[i] = parameters_[i].default_value;
  parameter_set_.assign(parameters_.size(), 0);
  defaults_ = model_->default_settings();
  // the fixed-step methods' step as the native simulator takes it by default
  if (!(defaults_.step_s > 0)) defaults_.step_s = defaults_.interval_s / 10;
  settings_ = defaults_;
  y_.assign(n_, 0.0);
  ydot_.assign(n_, 0.0);
  outputs_.assign(model_->output_names().size(), 0.0);
  indicators_.assign(model_->event_count(), 0.0);
}

Instance::~Instance() = default;

void Instance::log(Status status, const char* category, const std::string& message) {
  // errors are always said; the rest only with logging on
  if (!logger_ || (!logging_on_ && status < Status::error)) return;
  logger_(status, category, message);
}

Status Instance::refuse(const std::string& why) {
  log(Status::error, "logStatusError", why);
  return Status::error;
}

Status Instance::fail(const std::string& why) {
  if (!why.empty()) log(Status::error, "logStatusError", why);
  phase_ = Phase::failed;
  return Status::error;
}

bool Instance::allowed(const char* what, std::initializer_list<Phase> phases) {
  if (std::find(phases.begin(), phases.end(), phase_) != phases.end()) return true;
  refuse(fmt::format("{} is not allowed in {}", what, phase_name(phase_)));
  return false;
}

template <class Body>
Status Instance::captured(Body&& body) {
  char* buffer = nullptr;
  std::size_t length = 0;
  std::FILE* stream = open_memstream(&buffer, &length);
  Status status = Status::ok;
  {
    detail::ErrorRedirect redirect(stream ? stream : stderr);
    status = body(stream ? stream : stderr);
  }
  if (stream) {
    std::fclose(stream);
    const std::string text(buffer, length);
    std::free(buffer);
    forward_lines(text, [&](Status s, const std::string& line) {
      // a report's lines belong to the call's outcome: an error's, or notes
      const Status as = s == Status::ok && status >= Status::error ? Status::error : s;
      log(as, as >= Status::error ? "logStatusError" : as == Status::warning ? "logStatusWarning" : "logEvents", line);
    });
  }
  return status;
}

const Variable* Instance::variable(std::uint32_t vr) {
  if (vr < description_.variable_count) return &description_.variables[vr];
  refuse(fmt::format("unknown value reference {} (this FMU's are 0 to {})", vr, description_.variable_count - 1));
  return nullptr;
}

std::size_t Instance::event_indicator_count() const { return indicators_.size(); }

Settings Instance::run_settings() const {
  Settings s = settings_;
  s.t_start_s = t_;
  // The integrators never step past t_end_s: the importer's stop time, if it
  // gave one, else the model's own end (as its simulator has it, so that a
  // run over the same span takes the same steps); past that, without end.
  s.t_end_s = stop_defined_                 ? stop_
              : defaults_.t_end_s > t_ * (1 + 1e-12) ? defaults_.t_end_s
                                                      : std::numeric_limits<double>::max();
  return s;
}

// ---- the lifecycle ----------------------------------------------------------------

Status Instance::setup_experiment(double start, bool tolerance_defined, double tolerance, bool stop_defined,
                                  double stop) {
  if (!allowed("SetupExperiment", {Phase::instantiated})) return Status::error;
  if (!std::isfinite(start)) return refuse(fmt::format("the start time {} is not finite", start));
  if (stop_defined && !(stop >= start)) return refuse(fmt::format("the stop time {} is before the start time {}", stop, start));
  if (tolerance_defined && !(tolerance > 0)) return refuse(fmt::format("the tolerance {} is not positive", tolerance));
  t_ = start;
  stop_defined_ = stop_defined;
  stop_ = stop;
  if (tolerance_defined) settings_.rtol = tolerance;
  return Status::ok;
}

Status Instance::enter_initialization() {
  if (!allowed("EnterInitializationMode", {Phase::instantiated})) return Status::error;
  phase_ = Phase::initialization;
  return Status::ok;
}

Status Instance::exit_initialization() {
  if (!allowed("ExitInitializationMode", {Phase::initialization})) return Status::error;
  return captured([&](std::FILE* report) {
    for (std::size_t i = 0; i < parameters_.size(); ++i)
      if (parameter_set_[i]) model_->set_parameter(parameters_[i].name, parameter_values_[i]);
    guard_ = std::make_unique<detail::GuardedModel>(*model_);
    y_.assign(n_, 0.0);
    model_->initial(t_, y_.data(), nullptr);
    std::vector<double> yp;
    const detail::ConstrainedStart start = detail::prepare_constrained_start(*model_, *guard_, t_, y_, yp);
    if (!start.ok) return fail("the initial state cannot be made consistent with the model's joints");
    if (!guard_->check_state(t_, y_.data())) return fail(guard_->describe(*guard_->blame()));
    if (!guard_->events().start(t_, y_.data(), nullptr))
      return fail("an event function (the argument of a step) is not finite at the start");
    guard_->hold_constraints(detail::held_row_bound(settings_), detail::kHeldCeiling);
    reference_.assign(indicators_.size(), 0.0);
    if (!reference_.empty()) guard_->events().functions(t_, y_.data(), nullptr, reference_.data());
    invalidate();
    if (interface_ == Interface::co_simulation) {
      const std::string why = detail::why_integrator_does_not_fit(integrator_info(settings_.solver), *model_);
      if (!why.empty()) return fail(fmt::format("solver {} cannot integrate this model: {}", integrator_info(settings_.solver).name, why));
      integrator_ = detail::make_integrator(*guard_, run_settings());
      integrate_until_ = run_settings().t_end_s;
      if (!integrator_->init(t_, y_.data(), nullptr)) {
        detail::print_stop_message(report, *guard_, *integrator_, true);
        return fail({});
      }
      phase_ = Phase::step;
    } else {
      phase_ = Phase::event;
    }
    return Status::ok;
  });
}

Status Instance::enter_event_mode() {
  if (!allowed("EnterEventMode", {Phase::continuous_time, Phase::step})) return Status::error;
  phase_ = Phase::event;
  return Status::ok;
}

Status Instance::enter_continuous_time_mode() {
  if (!allowed("EnterContinuousTimeMode", {Phase::event})) return Status::error;
  if (interface_ != Interface::model_exchange) return refuse("EnterContinuousTimeMode is for model exchange");
  phase_ = Phase::continuous_time;
  return Status::ok;
}

Status Instance::enter_step_mode() {
  if (!allowed("EnterStepMode", {Phase::event})) return Status::error;
  if (interface_ != Interface::co_simulation) return refuse("EnterStepMode is for co-simulation");
  phase_ = Phase::step;
  return Status::ok;
}

Status Instance::terminate() {
  if (!allowed("Terminate", {Phase::event, Phase::continuous_time, Phase::step})) return Status::error;
  return captured([&](std::FILE*) {
    model_->terminal(t_, y_.data());
    phase_ = Phase::terminated;
    return Status::ok;
  });
}

Status Instance::reset() {
  integrator_.reset();
  guard_.reset();
  model_ = description_.make_model();
  for (std::size_t i = 0; i < parameters_.size(); ++i) parameter_values_[i] = parameters_[i].default_value;
  std::fill(parameter_set_.begin(), parameter_set_.end(), 0);
  settings_ = defaults_;
  t_ = 0.0;
  std::fill(y_.begin(), y_.end(), 0.0);
  invalidate();
  phase_ = Phase::instantiated;
  return Status::ok;
}

// ---- values -------------------------------------------------------------------------

bool Instance::evaluate_derivatives() {
  if (derivatives_valid_) return true;
  if (guard_->derivative(t_, y_.data(), ydot_.data()) != 0) {
    fail(fmt::format("at t = {} s: {}", detail::format_time(t_), guard_->describe(*guard_->blame())));
    return false;
  }
  return derivatives_valid_ = true;
}

bool Instance::evaluate_outputs() {
  if (outputs_valid_) return true;
  model_->outputs(t_, y_.data(), nullptr, outputs_.data());
  return outputs_valid_ = true;
}

Status Instance::get_float64(const std::uint32_t* vr, std::size_t n, double* values) {
  if (phase_ == Phase::failed) return refuse("the FMU failed at an earlier call: only FreeInstance or Reset may follow");
  const bool started = guard_ != nullptr && phase_ != Phase::instantiated && phase_ != Phase::initialization;
  for (std::size_t k = 0; k < n; ++k) {
    const Variable* v = variable(vr[k]);
    if (!v) return Status::error;
    const bool computed = v->kind == Kind::output || v->kind == Kind::state || v->kind == Kind::derivative ||
                          v->kind == Kind::event_indicator || v->kind == Kind::calculated;
    if (computed && !started)
      return refuse(fmt::format("value reference {} is {}: it has a value once the initialisation is done "
                                "(ExitInitializationMode)",
                                vr[k], kind_name(v->kind)));
    switch (v->kind) {
      case Kind::time: values[k] = t_; break;
      case Kind::parameter: values[k] = parameter_values_[v->index]; break;
      case Kind::constant: values[k] = description_.constants[v->index]; break;
      case Kind::calculated:
        calculated_.resize(parameters_.size());
        if (!model_->parameter_values(calculated_.data()))
          return refuse(fmt::format("value reference {}: this model does not give its parameters' values", vr[k]));
        values[k] = calculated_[v->index];
        break;
      case Kind::output:
        evaluate_outputs();
        values[k] = outputs_[v->index];
        break;
      case Kind::state: values[k] = y_[v->index]; break;
      case Kind::derivative:
        if (!evaluate_derivatives()) return Status::error;
        values[k] = ydot_[v->index];
        break;
      case Kind::event_indicator:
        if (!guard_->events().functions(t_, y_.data(), nullptr, indicators_.data()))
          return fail(fmt::format("at t = {} s an event function is not finite", detail::format_time(t_)));
        values[k] = indicators_[v->index];
        break;
      case Kind::setting:
        switch (static_cast<Setting>(v->index)) {
          case Setting::rtol: values[k] = settings_.rtol; break;
          case Setting::atol: values[k] = settings_.atol; break;
          case Setting::step: values[k] = settings_.step_s; break;
          case Setting::solver: return refuse(fmt::format("value reference {} is an Enumeration (GetInt64)", vr[k]));
        }
        break;
    }
  }
  return Status::ok;
}

Status Instance::set_float64(const std::uint32_t* vr, std::size_t n, const double* values) {
  for (std::size_t k = 0; k < n; ++k) {
    const Variable* v = variable(vr[k]);
    if (!v) return Status::error;
    if (v->kind != Kind::parameter && v->kind != Kind::setting)
      return refuse(fmt::format("value reference {} is {}: only parameters and solver settings can be set",
                                vr[k], kind_name(v->kind)));
    const std::string name = v->kind == Kind::parameter ? parameters_[v->index].name : "a solver setting";
    if (phase_ != Phase::instantiated && phase_ != Phase::initialization)
      return refuse(fmt::format("'{}' (value reference {}) is fixed: it can be set only before "
                                "ExitInitializationMode, not in {}",
                                name, vr[k], phase_name(phase_)));
    if (!std::isfinite(values[k]))
      return refuse(fmt::format("'{}' (value reference {}) cannot be set to {}", name, vr[k], values[k]));
    if (v->kind == Kind::parameter) {
      parameter_values_[v->index] = values[k];
      parameter_set_[v->index] = 1;
      continue;
    }
    const auto setting = static_cast<Setting>(v->index);
    if (setting == Setting::solver) return refuse(fmt::format("value reference {} is an Enumeration (SetInt64)", vr[k]));
    if (!(values[k] > 0)) return refuse(fmt::format("solver setting (value reference {}) must be positive, not {}", vr[k], values[k]));
    if (setting == Setting::rtol) settings_.rtol = values[k];
    if (setting == Setting::atol) settings_.atol = values[k];
    if (setting == Setting::step) settings_.step_s = values[k];
  }
  return Status::ok;
}

Status Instance::get_int64(const std::uint32_t* vr, std::size_t n, std::int64_t* values) {
  for (std::size_t k = 0; k < n; ++k) {
    const Variable* v = variable(vr[k]);
    if (!v) return Status::error;
    if (v->kind != Kind::setting || static_cast<Setting>(v->index) != Setting::solver)
      return refuse(fmt::format("value reference {} is {} of type Float64", vr[k], kind_name(v->kind)));
    values[k] = static_cast<std::int64_t>(settings_.solver) + 1;
  }
  return Status::ok;
}

Status Instance::set_int64(const std::uint32_t* vr, std::size_t n, const std::int64_t* values) {
  for (std::size_t k = 0; k < n; ++k) {
    const Variable* v = variable(vr[k]);
    if (!v) return Status::error;
    if (v->kind != Kind::setting || static_cast<Setting>(v->index) != Setting::solver)
      return refuse(fmt::format("value reference {} is {} of type Float64", vr[k], kind_name(v->kind)));
    if (phase_ != Phase::instantiated && phase_ != Phase::initialization)
      return refuse(fmt::format("the solver (value reference {}) is fixed: it can be set only before "
                                "ExitInitializationMode",
                                vr[k]));
    if (values[k] < 1 || values[k] > static_cast<std::int64_t>(kIntegrators.size()))
      return refuse(fmt::format("the solver (value reference {}) has no item {}", vr[k], values[k]));
    settings_.solver = static_cast<Solver>(values[k] - 1);
  }
  return Status::ok;
}

// ---- model exchange ---------------------------------------------------------------

Status Instance::set_time(double t) {
  if (!allowed("SetTime", {Phase::event, Phase::continuous_time})) return Status::error;
  if (!std::isfinite(t)) return refuse(fmt::format("SetTime: the time {} is not finite", t));
  t_ = t;
  invalidate();
  return Status::ok;
}

Status Instance::set_states(const double* x, std::size_t n) {
  if (!allowed("SetContinuousStates", {Phase::event, Phase::continuous_time})) return Status::error;
  if (n != n_) return refuse(fmt::format("SetContinuousStates: {} states given, the model has {}", n, n_));
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(x[i]))
      return refuse(fmt::format("SetContinuousStates: state '{}' is {}", model_->variable_name(i), x[i]));
  std::copy(x, x + n, y_.begin());
  invalidate();
  return Status::ok;
}

Status Instance::get_states(double* x, std::size_t n) {
  if (!guard_ || phase_ == Phase::failed || phase_ == Phase::initialization)
    return refuse(fmt::format("GetContinuousStates is not allowed in {}", phase_name(phase_)));
  if (n != n_) return refuse(fmt::format("GetContinuousStates: room for {} states, the model has {}", n, n_));
  std::copy(y_.begin(), y_.end(), x);
  return Status::ok;
}

Status Instance::get_derivatives(double* dx, std::size_t n) {
  if (!allowed("GetContinuousStateDerivatives", {Phase::event, Phase::continuous_time, Phase::terminated}))
    return Status::error;
  if (n != n_) return refuse(fmt::format("GetContinuousStateDerivatives: room for {} derivatives, the model has {}", n, n_));
  if (!evaluate_derivatives()) return Status::error;
  std::copy(ydot_.begin(), ydot_.end(), dx);
  return Status::ok;
}

Status Instance::get_event_indicators(double* g, std::size_t n) {
  if (!allowed("GetEventIndicators", {Phase::event, Phase::continuous_time, Phase::terminated})) return Status::error;
  if (n != indicators_.size())
    return refuse(fmt::format("GetEventIndicators: room for {} indicators, the model has {}", n, indicators_.size()));
  if (n == 0) return Status::ok;
  if (!guard_->events().functions(t_, y_.data(), nullptr, indicators_.data()))
    return fail(fmt::format("at t = {} s an event function is not finite", detail::format_time(t_)));
  std::copy(indicators_.begin(), indicators_.end(), g);
  return Status::ok;
}

Status Instance::get_nominals(double* nominal, std::size_t n) {
  if (n != n_) return refuse(fmt::format("GetNominalsOfContinuousStates: room for {} nominals, the model has {}", n, n_));
  for (std::size_t i = 0; i < n; ++i) nominal[i] = guard_ ? std::max(model_->nominal(i), 1e-300) : 1.0;
  return Status::ok;
}

Status Instance::completed_integrator_step(bool* enter_event_mode, bool* terminate_simulation) {
  if (!allowed("CompletedIntegratorStep", {Phase::continuous_time})) return Status::error;
  *enter_event_mode = false;
  *terminate_simulation = false;
  // what the native run checks after every step: finite states within their
  // limits, the joints that must hold holding
  if (guard_->check_state(t_, y_.data()) && guard_->check_constraints(t_, y_.data())) return Status::ok;
  *terminate_simulation = true;
  return fail(fmt::format("at t = {} s: {}", detail::format_time(t_), guard_->describe(*guard_->blame())));
}

Status Instance::update_discrete_states(bool* values_changed, bool* terminate_simulation) {
  if (!allowed("UpdateDiscreteStates", {Phase::event})) return Status::error;
  *values_changed = false;
  *terminate_simulation = false;
  if (indicators_.empty()) return Status::ok;
  return captured([&](std::FILE*) {
    detail::Events& events = guard_->events();
    if (!events.functions(t_, y_.data(), nullptr, indicators_.data()))
      return fail(fmt::format("at t = {} s an event function is not finite", detail::format_time(t_)));
    // Every event whose function crossed zero since the last event switches,
    // rising or falling, as a located crossing does in the runtime's own
    // methods. An importer's root finder may stop exactly on the zero: a
    // function that fell from above to 0 has crossed (step(x) is on at 0, so
    // the rise is from below to 0 or more).
    const std::size_t logged = events.log().size();
    const std::vector<double> before = y_;
    bool any = false;
    for (std::size_t k = 0; k < indicators_.size(); ++k) {
      const double was = reference_[k], now = indicators_[k];
      const bool rose = was < 0.0 && now >= 0.0;
      const bool fell = was >= 0.0 && (now < 0.0 || (now == 0.0 && was > 0.0));
      if (!rose && !fell) continue;
      if (!any) events.note_roots(t_);
      any = true;
      events.fire(t_, k, rose, y_.data());
    }
    for (std::size_t r = logged; r < events.log().size(); ++r) log(Status::ok, "logEvents", events.describe(events.log()[r]));
    detail::SolverFailure chatter;
    if (any && !detail::chatter_failure(events, t_, chatter)) {
      *terminate_simulation = true;
      return fail(chatter.explanation);
    }
    if (!guard_->check_state(t_, y_.data())) {
      *terminate_simulation = true;
      return fail(guard_->describe(*guard_->blame()));
    }
    *values_changed = y_ != before;
    events.functions(t_, y_.data(), nullptr, reference_.data());
    invalidate();
    return Status::ok;
  });
}

Status Instance::directional_derivative(const std::uint32_t* unknowns, std::size_t n_unknowns,
                                        const std::uint32_t* knowns, std::size_t n_knowns, const double* seed,
                                        double* sensitivity) {
  if (!guard_ || phase_ == Phase::instantiated || phase_ == Phase::initialization || phase_ == Phase::failed)
    return refuse(fmt::format("GetDirectionalDerivative is not allowed in {}", phase_name(phase_)));
  std::vector<double> direction(n_, 0.0);
  for (std::size_t k = 0; k < n_knowns; ++k) {
    const Variable* v = variable(knowns[k]);
    if (!v) return Status::error;
    if (v->kind != Kind::state)
      return refuse(fmt::format("GetDirectionalDerivative: value reference {} is {}; the knowns are continuous states",
                                knowns[k], kind_name(v->kind)));
    if (!std::isfinite(seed[k])) return refuse(fmt::format("GetDirectionalDerivative: seed {} is {}", k, seed[k]));
    direction[v->index] += seed[k];
  }
  std::vector<const Variable*> wanted(n_unknowns);
  bool derivatives_only = true;
  for (std::size_t u = 0; u < n_unknowns; ++u) {
    wanted[u] = variable(unknowns[u]);
    if (!wanted[u]) return Status::error;
    if (wanted[u]->kind != Kind::derivative && wanted[u]->kind != Kind::output)
      return refuse(fmt::format("GetDirectionalDerivative: value reference {} is {}; the unknowns are state "
                                "derivatives and outputs",
                                unknowns[u], kind_name(wanted[u]->kind)));
    derivatives_only = derivatives_only && wanted[u]->kind == Kind::derivative;
  }
  if (derivatives_only && guard_->has_jacobian()) {  // the Jacobian the compiler derived
    std::vector<double> jacobian(n_ * n_);
    if (guard_->jacobian(t_, y_.data(), jacobian.data()) != 0)
      return fail(fmt::format("at t = {} s: {}", detail::format_time(t_), guard_->describe(*guard_->blame())));
    for (std::size_t u = 0; u < n_unknowns; ++u) {
      const std::size_t row = wanted[u]->index;
      double sum = 0.0;
      for (std::size_t j = 0; j < n_; ++j) sum += jacobian[row * n_ + j] * direction[j];
      sensitivity[u] = sum;
    }
    return Status::ok;
  }
  // Central differences along the direction, a step of 1e-6 of the size of
  // the states it moves (at least 1) over the direction's: not of every
  // state's (a car's wheel spinning at 70 rad/s made the step along its
  // attitude's quaternion 7e-5, and the truncation error 1.4e-4).
  double size = 1.0, length = 0.0;
  for (std::size_t j = 0; j < n_; ++j)
    if (direction[j] != 0.0) size = std::max(size, std::abs(y_[j])), length = std::max(length, std::abs(direction[j]));
  if (length == 0.0) {
    std::fill(sensitivity, sensitivity + n_unknowns, 0.0);
    return Status::ok;
  }
  const double h = 1e-6 * size / length;
  std::vector<double> plus(n_), minus(n_), dplus(n_), dminus(n_), oplus(outputs_.size()), ominus(outputs_.size());
  for (std::size_t j = 0; j < n_; ++j) plus[j] = y_[j] + h * direction[j], minus[j] = y_[j] - h * direction[j];
  if (guard_->derivative(t_, plus.data(), dplus.data()) != 0 || guard_->derivative(t_, minus.data(), dminus.data()) != 0)
    return fail(fmt::format("at t = {} s: {}", detail::format_time(t_), guard_->describe(*guard_->blame())));
  model_->outputs(t_, plus.data(), nullptr, oplus.data());
  model_->outputs(t_, minus.data(), nullptr, ominus.data());
  for (std::size_t u = 0; u < n_unknowns; ++u) {
    const std::size_t i = wanted[u]->index;
    sensitivity[u] = wanted[u]->kind == Kind::derivative ? (dplus[i] - dminus[i]) / (2 * h) : (oplus[i] - ominus[i]) / (2 * h);
  }
  return Status::ok;
}

// ---- the FMU state ------------------------------------------------------------------

namespace {
constexpr char kStateTag[8] = {'m', 'b', 'g', 'c', 'F', 'M', 'U', '1'};
}  // namespace

std::vector<unsigned char> Snapshot::serialize(const std::string& token) const {
  std::vector<double> numbers{static_cast<double>(phase),
                              t,
                              stop,
                              integrate_until,
                              stop_defined ? 1.0 : 0.0,
                              static_cast<double>(settings.solver),
                              settings.rtol,
                              settings.atol,
                              settings.step_s};
  for (const std::vector<double>* v : {&parameters, &parameter_set, &y, &reference, &held, &runtime}) {
    numbers.push_back(static_cast<double>(v->size()));
    numbers.insert(numbers.end(), v->begin(), v->end());
  }
  std::vector<unsigned char> bytes(sizeof kStateTag + sizeof(std::uint32_t) + token.size() + numbers.size() * sizeof(double));
  unsigned char* at = bytes.data();
  std::memcpy(at, kStateTag, sizeof kStateTag), at += sizeof kStateTag;
  const auto length = static_cast<std::uint32_t>(token.size());
  std::memcpy(at, &length, sizeof length), at += sizeof length;
  std::memcpy(at, token.data(), token.size()), at += token.size();
  std::memcpy(at, numbers.data(), numbers.size() * sizeof(double));
  return bytes;
}

bool Snapshot::deserialize(const unsigned char* bytes, std::size_t size, const std::string& token, Snapshot& out,
                           std::string& why) {
  std::uint32_t length = 0;
  if (!bytes || size < sizeof kStateTag + sizeof length || std::memcmp(bytes, kStateTag, sizeof kStateTag) != 0) {
    why = "the bytes are not an mbgc FMU's state";
    return false;
  }
  std::memcpy(&length, bytes + sizeof kStateTag, sizeof length);
  const std::size_t head = sizeof kStateTag + sizeof length + length;
  if (size < head || std::string(reinterpret_cast<const char*>(bytes) + sizeof kStateTag + sizeof length, length) != token) {
    why = "the state is another FMU's (its instantiation token differs)";
    return false;
  }
  if ((size - head) % sizeof(double) != 0) {
    why = "the state's length is not whole numbers";
    return false;
  }
  std::vector<double> numbers((size - head) / sizeof(double));
  std::memcpy(numbers.data(), bytes + head, numbers.size() * sizeof(double));
  std::size_t k = 0;
  auto next = [&](double& v) { return k < numbers.size() ? (v = numbers[k++], true) : false; };
  double phase = 0, stop_defined = 0, solver = 0;
  bool ok = next(phase) && next(out.t) && next(out.stop) && next(out.integrate_until) && next(stop_defined) &&
            next(solver) && next(out.settings.rtol) && next(out.settings.atol) && next(out.settings.step_s);
  for (std::vector<double>* v : {&out.parameters, &out.parameter_set, &out.y, &out.reference, &out.held, &out.runtime}) {
    double count = 0;
    ok = ok && next(count) && count >= 0 && k + static_cast<std::size_t>(count) <= numbers.size();
    if (!ok) break;
    v->assign(numbers.begin() + static_cast<long>(k), numbers.begin() + static_cast<long>(k + static_cast<std::size_t>(count)));
    k += static_cast<std::size_t>(count);
  }
  ok = ok && k == numbers.size() && phase >= 0 && phase <= static_cast<double>(Phase::failed) && solver >= 0 &&
       solver < static_cast<double>(kIntegrators.size());
  if (!ok) {
    why = "the state is truncated or malformed";
    return false;
  }
  out.phase = static_cast<Phase>(static_cast<int>(phase));
  out.stop_defined = stop_defined != 0.0;
  out.settings.solver = static_cast<Solver>(static_cast<int>(solver));
  return true;
}

Snapshot* Instance::new_snapshot() {
  snapshots_.push_back(std::make_unique<Snapshot>());
  return snapshots_.back().get();
}

bool Instance::owns(const void* state) const {
  return state && std::any_of(snapshots_.begin(), snapshots_.end(), [state](const auto& s) { return s.get() == state; });
}

void Instance::release(Snapshot* state) {
  snapshots_.erase(std::remove_if(snapshots_.begin(), snapshots_.end(), [state](const auto& s) { return s.get() == state; }),
                   snapshots_.end());
}

Status Instance::get_state(Snapshot& out) {
  if (phase_ == Phase::failed) return refuse("GetFMUState: the FMU failed at an earlier call: there is no state to keep");
  out = Snapshot{};
  out.phase = phase_;
  out.t = t_;
  out.stop = stop_;
  out.stop_defined = stop_defined_;
  out.integrate_until = integrate_until_;
  out.settings = settings_;
  out.parameters = parameter_values_;
  out.parameter_set.assign(parameter_set_.begin(), parameter_set_.end());
  if (!guard_) return Status::ok;  // (not initialised: the parameters and settings are all there is)
  out.y = y_;
  out.reference = reference_;
  out.held.resize(model_->held_state_size());
  model_->get_held_state(out.held.data());
  guard_->events().save(out.runtime);
  return Status::ok;
}

Status Instance::set_state(const Snapshot& s) {
  const bool started = !s.y.empty() || s.phase == Phase::event || s.phase == Phase::continuous_time || s.phase == Phase::step;
  if (s.parameters.size() != parameters_.size() || s.parameter_set.size() != parameters_.size() ||
      (started && (s.y.size() != n_ || s.reference.size() != indicators_.size())))
    return refuse("SetFMUState: the state is not this FMU's (its sizes differ)");
  if (s.phase == Phase::failed) return refuse("SetFMUState: the state is of a failed instance");
  return captured([&](std::FILE* report) {
    integrator_.reset();
    guard_.reset();
    model_ = description_.make_model();
    parameter_values_ = s.parameters;
    for (std::size_t i = 0; i < parameters_.size(); ++i) parameter_set_[i] = s.parameter_set[i] != 0.0 ? 1 : 0;
    // the settings an importer may set (the rest are the model's own)
    settings_ = defaults_;
    settings_.solver = s.settings.solver;
    settings_.rtol = s.settings.rtol;
    settings_.atol = s.settings.atol;
    settings_.step_s = s.settings.step_s;
    t_ = s.t;
    stop_ = s.stop;
    stop_defined_ = s.stop_defined;
    integrate_until_ = s.integrate_until;
    phase_ = s.phase;
    invalidate();
    if (!started) return Status::ok;
    // the parameters and what is derived of them, then what the run changed
    for (std::size_t i = 0; i < parameters_.size(); ++i)
      if (parameter_set_[i]) model_->set_parameter(parameters_[i].name, parameter_values_[i]);
    std::vector<double> discarded(n_);
    model_->initial(t_, discarded.data(), nullptr);
    if (s.held.size() != model_->held_state_size() || s.runtime.size() != detail::Events(*model_).saved_size())
      return fail("SetFMUState: the state is not this FMU's (its model's sizes differ)");
    model_->set_held_state(s.held.data());
    guard_ = std::make_unique<detail::GuardedModel>(*model_);
    guard_->hold_constraints(detail::held_row_bound(settings_), detail::kHeldCeiling);
    const double* in = s.runtime.data();
    guard_->events().restore(in);
    y_ = s.y;
    reference_ = s.reference;
    if (interface_ == Interface::co_simulation && phase_ != Phase::terminated) {
      integrator_ = detail::make_integrator(*guard_, run_settings());
      integrate_until_ = run_settings().t_end_s;
      if (!integrator_->init(t_, y_.data(), nullptr)) {
        detail::print_stop_message(report, *guard_, *integrator_, true);
        return fail({});
      }
    }
    return Status::ok;
  });
}

// ---- co-simulation ----------------------------------------------------------------

Status Instance::do_step(double t, double h, bool* terminate_simulation, bool* early_return,
                         double* last_successful_time) {
  *terminate_simulation = false;
  *early_return = false;
  *last_successful_time = t_;
  if (!allowed("DoStep", {Phase::step})) return Status::error;
  if (!(h > 0) || !std::isfinite(h)) return refuse(fmt::format("DoStep: the step size {} is not positive", h));
  if (std::abs(t - t_) > 1e-12 * std::max(1.0, std::abs(t_)))
    return refuse(fmt::format("DoStep from t = {} s, but the FMU is at t = {} s", t, t_));
  if (stop_defined_ && t + h > stop_ + 1e-12 * std::max(1.0, std::abs(stop_)))
    return refuse(fmt::format("DoStep to t = {} s, past the stop time {} s", t + h, stop_));
  double target = stop_defined_ ? std::min(t + h, stop_) : t + h;
  // a communication point the importer summed up, a rounding past the end: the end
  if (std::abs(target - integrate_until_) <= 1e-12 * std::max(1.0, std::abs(integrate_until_))) target = integrate_until_;
  return captured([&](std::FILE* report) {
    if (target > integrate_until_) {
      // past the model's end without a stop time: the integrator starts again from here, with none
      integrator_ = detail::make_integrator(*guard_, run_settings());
      integrate_until_ = run_settings().t_end_s;
      if (!integrator_->init(t_, y_.data(), nullptr)) {
        detail::print_stop_message(report, *guard_, *integrator_, true);
        return fail({});
      }
    }
    guard_->events().pause_at_events(early_return_allowed_);
    const bool solved = integrator_->advance_to(target);
    guard_->events().pause_at_events(false);
    const bool ok = solved && guard_->check_state(integrator_->t(), integrator_->y()) &&
                    guard_->check_constraints(integrator_->t(), integrator_->y());
    if (!ok) {
      detail::print_stop_message(report, *guard_, *integrator_, !solved);
      *terminate_simulation = true;
      *last_successful_time = integrator_->t();
      return fail({});
    }
    t_ = integrator_->t();
    std::copy(integrator_->y(), integrator_->y() + n_, y_.begin());
    invalidate();
    *early_return = t_ < target;  // (an event inside the step: the importer goes on from here)
    *last_successful_time = t_;
    return Status::ok;
  });
}

Status get_fmu_state(void* instance, void** state) {
  return call(instance, "GetFMUState", [&](Instance& i) {
    if (!state) return i.refuse("GetFMUState: no place for the state");
    // a state given back is reused; anything else the importer left there is not ours to touch
    Snapshot* snapshot = i.owns(*state) ? static_cast<Snapshot*>(*state) : i.new_snapshot();
    const Status s = i.get_state(*snapshot);
    if (s == Status::ok) *state = snapshot;
    else if (snapshot != *state) i.release(snapshot);
    return s;
  });
}

Status set_fmu_state(void* instance, void* state) {
  return call(instance, "SetFMUState", [&](Instance& i) {
    if (!i.owns(state)) return i.refuse("SetFMUState: not a state this instance made (GetFMUState, DeserializeFMUState)");
    return i.set_state(*static_cast<const Snapshot*>(state));
  });
}

Status free_fmu_state(void* instance, void** state) {
  return call(instance, "FreeFMUState", [&](Instance& i) {
    if (!state || !*state) return Status::ok;
    if (i.owns(state)) {  // (an importer that passes the state where its address belongs: fmusim 0.0.36's files)
      i.release(reinterpret_cast<Snapshot*>(state));
      return Status::ok;
    }
    if (!i.owns(*state)) return i.refuse("FreeFMUState: not a state this instance made");
    i.release(static_cast<Snapshot*>(*state));
    *state = nullptr;
    return Status::ok;
  });
}

Status serialized_fmu_state_size(void* instance, void* state, std::size_t* size) {
  return call(instance, "SerializedFMUStateSize", [&](Instance& i) {
    if (!i.owns(state) || !size) return i.refuse("SerializedFMUStateSize: not a state this instance made");
    *size = static_cast<const Snapshot*>(state)->serialize(i.token()).size();
    return Status::ok;
  });
}

Status serialize_fmu_state(void* instance, void* state, unsigned char* bytes, std::size_t size) {
  return call(instance, "SerializeFMUState", [&](Instance& i) {
    if (!i.owns(state) || !bytes) return i.refuse("SerializeFMUState: not a state this instance made");
    const std::vector<unsigned char> out = static_cast<const Snapshot*>(state)->serialize(i.token());
    if (size < out.size())
      return i.refuse(fmt::format("SerializeFMUState: {} bytes given, the state takes {}", size, out.size()));
    std::memcpy(bytes, out.data(), out.size());
    return Status::ok;
  });
}

Status deserialize_fmu_state(void* instance, const unsigned char* bytes, std::size_t size, void** state) {
  return call(instance, "DeserializeFMUState", [&](Instance& i) {
    if (!state) return i.refuse("DeserializeFMUState: no place for the state");
    Snapshot read;
    std::string why;
    if (!Snapshot::deserialize(bytes, size, i.token(), read, why)) return i.refuse("DeserializeFMUState: " + why);
    Snapshot* snapshot = i.owns(*state) ? static_cast<Snapshot*>(*state) : i.new_snapshot();
    *snapshot = std::move(read);
    *state = snapshot;
    return Status::ok;
  });
}

Instance* instantiate(Interface interface, const std::string& name, const char* token, const char* token_name,
                      const Logger& logger, bool logging_on) {
  const Description& d = description();
  if (!token || std::string(token) != d.instantiation_token) {
    logger(Status::error, "logStatusError",
           fmt::format("{} '{}' is not this FMU's ('{}': the modelDescription.xml of another build?)", token_name,
                       token ? token : "(null)", d.instantiation_token));
    return nullptr;
  }
  try {
    return new Instance(d, interface, name, logger, logging_on);
  } catch (const std::exception& e) {
    logger(Status::error, "logStatusError", fmt::format("the model could not be made: {}", e.what()));
  }
  return nullptr;
}

Status absent(void* instance, const char* what) {
  return call(instance, what, [&](Instance& i) {
    return i.refuse(fmt::format("{}: this FMU has no such variables or features (modelDescription.xml lists what it has)",
                                what));
  });
}

}  // namespace mbgrt::fmu
