// Small RAII wrappers and shared error handling for the SUNDIALS-based integrators.
#pragma once

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "error_weights.hpp"
#include "integrator.hpp"

namespace mbgrt::detail {

/// Internal steps allowed between two communication points. SUNDIALS' default
/// of 500 is routinely exceeded by stiff mechanical models at coarse output
/// intervals; 10000 still turns a genuinely stuck run into a prompt report.
inline constexpr long kMaxStepsPerOutput = 10000;

/// What CVODE's and ARKODE's callbacks receive as user data.
class CarryAcross;

struct CallbackData {
  GuardedModel* model = nullptr;
  ErrorWeights weights;
  /// cvode: the watch on the cut joints (solvers/carry_across.hpp), a root
  /// after the events' when active; null: none.
  CarryAcross* carry = nullptr;
};

/// The EwtFn of CVODE and ARKODE (user data: CallbackData).
int error_weights(N_Vector y, N_Vector w, void* user_data);

class SunContext {
 public:
  SunContext();
  ~SunContext();
  SunContext(const SunContext&) = delete;
  SunContext& operator=(const SunContext&) = delete;
  operator SUNContext() const { return ctx_; }

 private:
  SUNContext ctx_ = nullptr;
};

class SerialVector {
 public:
  SerialVector(std::size_t n, SUNContext ctx);
  ~SerialVector();
  SerialVector(const SerialVector&) = delete;
  SerialVector& operator=(const SerialVector&) = delete;
  N_Vector get() const { return v_; }
  double* data() const { return N_VGetArrayPointer(v_); }

 private:
  N_Vector v_ = nullptr;
};

/// Keeps what SUNDIALS would otherwise print to stderr, so that our own
/// report can quote it once, in context, instead of raw interleaved output.
struct MessageSink {
  std::string last_error;
  std::string first_warning;
  long warnings = 0;

  /// Matches CVErrHandlerFn, ARKErrHandlerFn and IDAErrHandlerFn; `self` is the sink.
  static void handler(int error_code, const char* module, const char* function, char* msg,
                      void* self);
};

/// Plain-English reading of a flag name such as "CV_TOO_MUCH_WORK".
std::string explain_flag(const std::string& flag_name);

/// Builds the failure record. `flag_name` is the malloc'd string returned by
/// CVodeGetReturnFlagName and friends; it is freed here.
SolverFailure make_failure(double t, char* flag_name, const MessageSink& sink);
/// Index of the largest |local error| * weight: the unknown that forced the
/// solver's steps down — the one to name when a run fails without a NaN.
int largest_weighted_error(N_Vector local_errors, N_Vector weights);

/// The model's event functions for CVODE's and ARKODE's root finders
/// (user_data: CallbackData); -1 if one is not finite.
int event_roots(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data);

/// Has a restart at t (an event) reached the communication point t_out, up
/// to the rounding of a located root? Then the solver is not called again.
inline bool reached(double t, double t_out) { return t_out - t <= 1e-12 * std::max(1.0, std::abs(t_out)); }

/// Throws std::runtime_error naming `what` when a set-up call fails: these
/// failures are programming or input errors, not numerical events.
void check_setup(int flag, const char* what, const MessageSink& sink);
void check_setup(const void* ptr, const char* what);

}  // namespace mbgrt::detail
