#include "integrator.hpp"

namespace mbgrt::detail {

const char* solver_name(Solver s) { return integrator_info(s).name; }

std::unique_ptr<Integrator> make_integrator(GuardedModel& model, const Settings& s) {
  // A purely algebraic model (no states) has nothing to integrate, and the
  // SUNDIALS solvers reject empty vectors: only time advances.
  if (model.size() == 0) return make_rk4(model, s);
  switch (s.solver) {
    case Solver::rk4:
      return make_rk4(model, s);
    case Solver::dopri5:
      return make_dopri5(model, s);
    case Solver::cvode:
      return make_cvode(model, s);
    case Solver::ida:
      return make_ida(model, s);
  }
  return nullptr;
}

}  // namespace mbgrt::detail
