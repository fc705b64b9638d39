#include <cmath>
#include "solvers/sundials_util.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace mbgrt::detail {

SunContext::SunContext() {
  if (SUNContext_Create(nullptr, &ctx_) != 0) throw std::runtime_error("SUNContext_Create failed");
}

SunContext::~SunContext() { SUNContext_Free(&ctx_); }

SerialVector::SerialVector(std::size_t n, SUNContext ctx)
    : v_(N_VNew_Serial(static_cast<sunindextype>(n), ctx)) {
  if (!v_) throw std::runtime_error("N_VNew_Serial failed (out of memory?)");
}

SerialVector::~SerialVector() { N_VDestroy(v_); }

void MessageSink::handler(int error_code, const char* module, const char* function, char* msg,
                          void* self) {
  (void)module;  // the function name ("CVode", "IDASolve", ...) already identifies the solver
  auto* sink = static_cast<MessageSink*>(self);
  std::string text = fmt::format("{}: {}", function ? function : "?", msg ? msg : "");
  // SUNDIALS reports warnings with a positive code and errors with a negative one.
  if (error_code > 0) {
    // The first warning says what happened ("t + h = t ..."); later ones
    // repeat it or only announce that it will not be repeated.
    if (sink->warnings++ == 0) sink->first_warning = std::move(text);
  } else {
    sink->last_error = std::move(text);
  }
}

std::string explain_flag(const std::string& flag_name) {
  // Flags share their meaning across CVODE, ARKODE and IDA; only the prefix differs.
  std::string_view s = flag_name;
  for (std::string_view prefix : {"CV_", "ARK_", "IDA_"})
    if (s.starts_with(prefix)) s.remove_prefix(prefix.size());

  struct Entry {
    std::string_view suffix, text;
  };
  static constexpr Entry table[] = {
      {"TOO_MUCH_WORK",
       "the solver took the maximum number of internal steps without reaching the next output "
       "time"},
      {"TOO_MUCH_ACC", "the requested accuracy is finer than floating point can deliver here"},
      {"ERR_FAILURE", "the local error test failed repeatedly or at the smallest possible step"},
      {"ERR_FAIL", "the local error test failed repeatedly or at the smallest possible step"},
      {"CONV_FAILURE",
       "the Newton iteration failed to converge repeatedly or at the smallest possible step"},
      {"CONV_FAIL",
       "the Newton iteration failed to converge repeatedly or at the smallest possible step"},
      {"RHSFUNC_FAIL", "the right-hand side function failed in an unrecoverable manner"},
      {"FIRST_RHSFUNC_ERR", "the right-hand side function failed at its first call"},
      {"REPTD_RHSFUNC_ERR", "the right-hand side function failed repeatedly"},
      {"UNREC_RHSFUNC_ERR", "the right-hand side function failed and could not recover"},
      {"RES_FAIL", "the residual function failed in an unrecoverable manner"},
      {"FIRST_RES_FAIL", "the residual function failed at its first call"},
      {"REP_RES_ERR", "the residual function failed repeatedly"},
      {"LSETUP_FAIL",
       "setting up the linear solver failed: a singular Jacobian, or a function failure while "
       "building it by finite differences"},
      {"LSOLVE_FAIL", "the linear solve failed"},
      {"NLS_FAIL", "the nonlinear solver failed in an unrecoverable manner"},
      {"NO_RECOVERY",
       "the residual function kept failing while computing consistent initial values"},
      {"LINESEARCH_FAIL",
       "the line search for consistent initial values failed; the initial guess may be far "
       "from consistent"},
      {"CONSTR_FAIL", "the inequality constraints could not be met"},
      {"BAD_EWT",
       "an error weight became zero or negative (a component with atol = 0 reached zero)"},
      {"ILL_INPUT", "an input to the solver was invalid (check tolerances and times)"},
      {"TOO_CLOSE", "the output time is too close to the start time"},
      {"MEM_FAIL", "out of memory"},
  };
  for (const Entry& e : table)
    if (s == e.suffix) return std::string(e.text);
  return "see the solver message below";
}

SolverFailure make_failure(double t, char* flag_name, const MessageSink& sink) {
  SolverFailure f;
  f.t = t;
  f.flag_name = flag_name ? flag_name : "UNKNOWN";
  std::free(flag_name);
  f.explanation = explain_flag(f.flag_name);
  f.solver_message = sink.last_error;
  return f;
}

int largest_weighted_error(N_Vector local_errors, N_Vector weights) {
  const double* e = N_VGetArrayPointer(local_errors);
  const double* w = N_VGetArrayPointer(weights);
  const auto n = N_VGetLength(local_errors);
  int best = -1;
  double best_value = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    double v = std::abs(e[i] * w[i]);
    if (!std::isfinite(v)) return static_cast<int>(i);
    if (v > best_value) {
      best_value = v;
      best = static_cast<int>(i);
    }
  }
  return best;
}

void check_setup(int flag, const char* what, const MessageSink& sink) {
  if (flag < 0)
    throw std::runtime_error(fmt::format("{} failed (flag {}){}{}", what, flag,
                                         sink.last_error.empty() ? "" : ": ", sink.last_error));
}

void check_setup(const void* ptr, const char* what) {
  if (!ptr) throw std::runtime_error(fmt::format("{} failed (out of memory?)", what));
}

int event_roots(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) {
  auto* m = static_cast<CallbackData*>(user_data)->model;
  return m->events().functions(t, N_VGetArrayPointer(y), nullptr, g) ? 0 : -1;
}

int error_weights(N_Vector y, N_Vector w, void* user_data) {
  const auto* data = static_cast<const CallbackData*>(user_data);
  return data->weights(N_VGetArrayPointer(y), N_VGetArrayPointer(w)) ? 0 : -1;
}

}  // namespace mbgrt::detail
