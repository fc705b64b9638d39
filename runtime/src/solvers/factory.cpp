#include <fmt/format.h>

#include "integrator.hpp"

namespace mbgrt::detail {

const char* solver_name(Solver s) { return integrator_info(s).name; }

std::string why_integrator_does_not_fit(const IntegratorInfo& i, const Model& model) {
  if (model.is_dae() && !i.takes(ModelForm::dae)) return fmt::format("model '{}' is a DAE", model.name());
  if (i.needs_layout)
    for (std::size_t k = 0; k < model.size(); ++k) {
      const UnknownRole r = model.unknown_role(k);
      if (r != UnknownRole::position && r != UnknownRole::velocity)
        return fmt::format("it needs each unknown to be a position or a velocity, and model '{}' does not say which "
                           "'{}' is",
                           model.name(), model.variable_name(k));
    }
  return {};
}

std::unique_ptr<Integrator> make_integrator(GuardedModel& model, const Settings& s) {
  // A purely algebraic model (no states) has nothing to integrate, and the
  // SUNDIALS solvers reject empty vectors: only time advances.
  if (model.size() == 0) return make_rk4(model, s);
  switch (s.solver) {
    case Solver::euler:
      return make_euler(model, s);
    case Solver::heun:
      return make_heun(model, s);
    case Solver::symplectic_euler:
      return make_symplectic_euler(model, s);
    case Solver::rk4:
      return make_rk4(model, s);
    case Solver::linearly_implicit_euler:
      return make_linearly_implicit_euler(model, s);
    case Solver::ros2:
      return make_ros2(model, s);
    case Solver::generalized_alpha:
      return make_generalized_alpha(model, s);
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
