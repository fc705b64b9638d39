// mbgrt/integrators.hpp — what each integrator can do, in one table.
//
// Every part that needs to know an integrator's capabilities reads them here:
// the compiler's check of `simulate { solver = ... }` (sema/resolve.cpp,
// reduce/reduce.cpp), the simulator's command line (--solver, --step,
// --linear-solver, --help), the run report's hints, the stiffness note and
// the work-precision sweep. Adding an integrator is a row here and its class
// in runtime/src/solvers/. Header-only and free of SUNDIALS, so that the
// compiler can read it too.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace mbgrt {

/// Integrators the runtime offers (names as used by --solver).
enum class Solver {
  euler,
  heun,
  symplectic_euler,
  rk4,
  dopri5,
  linearly_implicit_euler,
  ros2,
  generalized_alpha,
  cvode,
  ida
};

/// The form of model an integrator works on natively: x' = f(t, x), or
/// F(t, y, y') = 0. One that takes a DAE also takes an ODE (as F = y' - f),
/// at the cost of a Newton iteration an ODE method would not need.
enum class ModelForm { ode, dae };

struct IntegratorInfo {
  Solver solver;
  const char* name;       ///< --solver NAME, simulate { solver = NAME }
  const char* method;     ///< what it is, one line (--help)
  int order;              ///< its order of accuracy (the highest, for a variable-order method)
  bool implicit;          ///< solves a linear or nonlinear system each step: for stiff models
  bool adaptive;          ///< error-controlled steps (--rtol, --atol); else a fixed --step
  bool multistep;         ///< carries past steps (BDF), whose corrector solves for the end of each step
  ModelForm form;         ///< what it integrates natively (a DAE integrator also takes ODEs)
  bool needs_layout;      ///< needs the unknowns' split into positions and velocities (Model::unknown_role)
  bool linear_solver;     ///< takes --linear-solver (dense LU or KLU on the model's pattern)
  /// An explicit method is stable while h |lambda| stays below this on the
  /// negative real axis (lambda: the fastest decaying mode); 0 for methods
  /// without such a bound (BDF, stiffly stable).
  double stability_bound;

  bool takes(ModelForm f) const { return f == ModelForm::ode || form == ModelForm::dae; }
};

// (every integrator locates the model's events: at its own order, by its
// own steps to the crossing or by its interpolant)
inline constexpr std::array<IntegratorInfo, 10> kIntegrators = {{
    {Solver::euler, "euler", "explicit Euler, order 1, fixed step, one derivative per step", 1, false, false, false,
     ModelForm::ode, false, false, 2.0},
    {Solver::heun, "heun", "Heun (explicit trapezoidal, RK2), order 2, fixed step", 2, false, false, false,
     ModelForm::ode, false, false, 2.0},
    {Solver::symplectic_euler, "symplectic_euler",
     "semi-implicit (symplectic) Euler, order 1, fixed step: velocities, then positions from the new velocities", 1,
     false, false, false, ModelForm::ode, true, false, 2.0},
    {Solver::rk4, "rk4", "classical Runge-Kutta of order 4, fixed step", 4, false, false, false, ModelForm::ode, false,
     false, 2.78},
    {Solver::dopri5, "dopri5", "Dormand-Prince 5(4), explicit, adaptive (SUNDIALS ARKODE)", 5, false, true, false,
     ModelForm::ode, false, false, 3.3},
    {Solver::linearly_implicit_euler, "linearly_implicit_euler",
     "linearly implicit Euler, order 1, fixed step: one Jacobian and one LU per step, no Newton loop", 1, true, false,
     false, ModelForm::ode, false, false, 0.0},
    {Solver::ros2, "ros2", "Rosenbrock-W ROS2, order 2, L-stable, fixed step: one Jacobian and one LU per step", 2, true,
     false, false, ModelForm::ode, false, false, 0.0},
    {Solver::generalized_alpha, "generalized_alpha",
     "generalized-alpha, order 2, fixed step, high-frequency damping set by --rho-inf (Newton, Jacobian kept)", 2,
     true, false, false, ModelForm::ode, false, false, 0.0},
    {Solver::cvode, "cvode", "BDF of orders 1 to 5, implicit, adaptive (SUNDIALS CVODE)", 5, true, true, true,
     ModelForm::ode, false, false, 0.0},
    {Solver::ida, "ida", "BDF for DAEs, orders 1 to 5, implicit, adaptive (SUNDIALS IDA)", 5, true, true, true,
     ModelForm::dae, false, true, 0.0},
}};

/// The default integrator for a model of each form (a model's `simulate`
/// block and the command line override it).
inline constexpr Solver kDefaultOdeSolver = Solver::cvode;
inline constexpr Solver kDefaultDaeSolver = Solver::ida;

constexpr const IntegratorInfo& integrator_info(Solver s) {
  for (const IntegratorInfo& i : kIntegrators)
    if (i.solver == s) return i;
  return kIntegrators[0];  // (unreachable: every Solver has a row)
}

/// The integrator called `name`, or null.
constexpr const IntegratorInfo* find_integrator(std::string_view name) {
  for (const IntegratorInfo& i : kIntegrators)
    if (name == i.name) return &i;
  return nullptr;
}

/// The names of the integrators `has` holds for, "a, b or c" (`last` joins
/// the last two).
template <class Has>
std::string integrator_names_where(Has has, std::string_view last = "or") {
  std::string s;
  std::size_t count = 0, total = 0;
  for (const IntegratorInfo& i : kIntegrators) total += has(i) ? 1 : 0;
  for (const IntegratorInfo& i : kIntegrators) {
    if (!has(i)) continue;
    if (count > 0) s += count + 1 == total ? " " + std::string(last) + " " : ", ";
    s += i.name;
    ++count;
  }
  return s;
}

/// "euler, heun, ..., cvode or ida".
inline std::string integrator_names(std::string_view last = "or") {
  return integrator_names_where([](const IntegratorInfo&) { return true; }, last);
}

}  // namespace mbgrt
