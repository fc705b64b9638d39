// Joint constraints at run time: assembly of the initial state, consistent
// initial values for constrained DAEs, and the drift / violation monitor.
// See the constraint section of mbgrt/model.hpp for what the model provides.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// The layout the constraint code works with, read once from the model: the
/// sizes, what each unknown is, where the multipliers sit and the pattern of
/// G = dg/dx. All of it is stated by the model; none is discovered.
struct ConstraintShape {
  std::size_t n = 0;   ///< unknowns handed to the integrator (Model::size())
  std::size_t ns = 0;  ///< states: the leading entries of y that constraints() reads
  std::size_t np = 0;  ///< position constraints g
  std::size_t nv = 0;  ///< velocity constraints gdot
  bool dae = false;
  bool enforced = false;  ///< lagrange (drift) rather than penalty (violation)

  /// Per unknown (Model::unknown_role); filled only for a model with constraints.
  std::vector<UnknownRole> role;
  /// DAE: per position row, the index in y of its multipliers lambda and mu
  /// (-1 for a penalty row); empty for an ODE.
  std::vector<long> lambda_at, mu_at;
  /// G's pattern (Model::constraint_jacobian_pattern): row r reads the states
  /// g_columns[g_row_starts[r] .. g_row_starts[r + 1]).
  std::vector<long> g_row_starts, g_columns;
  /// Lagrange rows implied by the others (found after assembly): their
  /// multipliers are held at 0 (see pin_redundant_multipliers).
  std::vector<std::size_t> redundant;

  std::size_t count() const { return np + nv; }
  bool any() const { return count() > 0; }
  /// The states of the given role, ascending.
  std::vector<std::size_t> states_with(UnknownRole r) const;
};

/// What a residual row of a DAE is: the equation of the unknown of its index,
/// or (at a lagrange row's lambda) that row's gdot = 0, or (at its mu) g = 0.
struct RowRole {
  enum Kind { equation, velocity_constraint, position_constraint } kind = equation;
  std::size_t row = 0;  ///< the constraint row (a position row's index), for the constraint kinds
};
RowRole residual_row_role(const ConstraintShape& shape, std::size_t row);

ConstraintShape constraint_shape(const Model& model);

/// Empty when the model keeps the constraint part of the contract (the
/// layout above, consistent with `ids`, the model's differential ids, all 1
/// for an ODE; G's pattern over position states); otherwise what it breaks (a
/// code generator bug, reported before anything runs).
std::string contract_violation(const Model& model, const ConstraintShape& shape,
                               const std::vector<double>& ids);

/// "constraint 'j1.gdot[0]'" for a residual row of a lagrange DAE that is a
/// constraint row (residual_row_role), otherwise "the equation of 'name'".
std::string residual_row_name(const Model& model, const ConstraintShape& shape, std::size_t row);

/// A position row's name without the " g" the model gives it ("q1.cn[1] g"
/// is "q1.cn[1]"): the joint's row, in the summary's lists of rows.
std::string joint_row_name(const Model& model, std::size_t row);

/// After model.residual(): for each redundant row, its lambda and mu rows
/// become lambda = 0 and mu = 0, so the Newton matrix stays regular.
void pin_redundant_multipliers(const ConstraintShape& shape, const double* y, double* r);

/// model.residual() followed by pin_redundant_multipliers().
void constrained_residual(Model& model, const ConstraintShape& shape, double t, const double* y,
                          const double* yp, double* r);

inline constexpr int kAssemblyMaxIterations = 50;

struct AssemblyReport {
  bool ok = false;
  int position_iterations = 0;
  int velocity_iterations = 0;
  std::size_t position_states = 0;  ///< position states g reads
  std::size_t velocity_states = 0;  ///< velocity states (momenta, joint rates)
  double g_residual = 0.0;          ///< max |g| after assembly
  double gdot_residual = 0.0;       ///< max |gdot| after assembly
  double moved_positions = 0.0;     ///< max |change| of a position state
  double moved_velocities = 0.0;    ///< max |change| of a velocity state
  std::string error;                ///< the whole message when !ok
};

/// Moves the states in y (the first shape.ns entries; the rest is untouched)
/// so that g = 0, then gdot = 0:
///   (a) positions: Gauss-Newton with the minimum-norm step on g(x) = 0 over
///       the position states g reads, with the model's symbolic G = dg/dx;
///   (b) velocities: the same on gdot(x) = 0 over the velocity states (gdot
///       is affine in them, so one or two steps; its derivatives by them are
///       central differences, exact up to rounding for an affine function).
/// Convergence: max |residual| <= 1e-12 * (1 + scale), where scale is the
/// size of the terms the rows balance, max_i sum_j |dr_i/dx_j| |x_j| over the
/// states the phase moves (for g = (x^2 + y^2 - L^2)/2 that is about L^2).
/// At most kAssemblyMaxIterations steps per phase.
/// `to_rounding`: each phase goes on beyond its tolerance while a step still
/// lowers the residual (a restart of an integrator whose tolerances are
/// tighter than the convergence test above).
AssemblyReport assemble(Model& model, const ConstraintShape& shape, double t, double* y, bool to_rounding = false);

/// A lagrange row whose unit gradient keeps less than this after projection
/// onto the rows before it is redundant: far above the ~1e-10 error of a
/// central-difference gradient, far below the component an independent row
/// keeps away from singular configurations.
inline constexpr double kRedundantRowThreshold = 1e-6;

struct RedundancyReport {
  std::size_t lagrange_rows = 0;       ///< rows with multipliers
  std::vector<std::size_t> redundant;  ///< rows implied by the others
  double smallest_kept = 0.0;          ///< smallest independent component of a kept row
};

/// Rows of a planar loop of revolute joints in 3-D (and any over-determined
/// set) are linearly dependent, which makes the DAE's Newton matrix singular.
/// At the assembled state this picks, in row order, the lagrange rows whose
/// gradient dg/dx (the model's symbolic G) is a combination of the rows
/// before it (relative residual below kRedundantRowThreshold after row
/// equilibration).
RedundancyReport find_redundant_constraints(Model& model, const ConstraintShape& shape, double t,
                                            const double* y);

/// For a run that stopped at (t, y): a sentence if the lagrange rows there
/// are much closer to dependent than at the start (t0, y0) — a dead point or
/// aligned links —, else empty.
std::string rank_loss_note(Model& model, const ConstraintShape& shape, double t0, const double* y0, double t,
                           const double* y);

struct InitialValuesReport {
  bool ok = false;
  std::size_t differentiated_rows = 0;  ///< residual rows replaced by their time derivative
  std::size_t unknowns = 0;             ///< y' of the states plus the algebraic unknowns
  std::size_t rank = 0;                 ///< of the final Newton matrix
  int iterations = 0;
  double residual = 0.0;                ///< max |row| of the system solved, at the solution
  bool least_squares = false;           ///< the rows were contradictory: their least-squares solution
  std::string error;
};

/// The size from which consistent_initial_values works on the residual's
/// sparsity pattern (rates.cpp).
inline constexpr std::size_t kSparseRatesFromUnknowns = 200;

struct RatesOptions {
  /// Rows that contradict each other at a rank-deficient Newton matrix (a
  /// change point, where the velocities meet the dependent rows' second-order
  /// condition only approximately) give their minimum-norm least-squares
  /// solution instead of an error.
  bool least_squares = false;
  /// The index-1 form: mu = 0 instead of the position rows' derivatives, so
  /// that q' is the velocities' as they are (a Runge-Kutta stage off the
  /// constraints is not projected onto their tangent, which near a change
  /// point amplifies its violation by the inverse of the rows' independence).
  bool index_one = false;
  /// From this many unknowns the Newton matrix is differenced and solved on
  /// the residual's sparsity pattern (rates.cpp says why not below).
  std::size_t sparse_from = kSparseRatesFromUnknowns;
};

/// For a constrained DAE at an assembled y: computes y' of the states and the
/// algebraic unknowns (z = [y'_states; y_algebraic]) from the residual rows,
/// each constraint row (residual_row_role; they depend on no entry of z)
/// being replaced by its time derivative dr/dt + (dr/dy_states) y'_states = 0.
/// Newton with a finite-difference Jacobian. y' of the algebraic unknowns is
/// left as given.
InitialValuesReport consistent_initial_values(Model& model, const ConstraintShape& shape, double t,
                                              double* y, double* yp, const RatesOptions& options = {});

/// Largest |g| and |gdot| seen at the output points, and where.
class ConstraintMonitor {
 public:
  struct Peak {
    double value = -1.0;  ///< < 0: nothing seen yet (a non-finite value is +Inf)
    std::size_t index = 0;
    double t = 0.0;
  };

  ConstraintMonitor(Model& model, const ConstraintShape& shape);

  /// Evaluates the constraints at (t, y) and updates the peaks.
  void observe(double t, const double* y);

  const ConstraintShape& shape() const { return shape_; }
  const Model& model() const { return model_; }
  double last_position() const { return last_g_; }  ///< max |g| at the last point (0 if none)
  double last_velocity() const { return last_gdot_; }
  const Peak& position() const { return g_; }
  const Peak& velocity() const { return gdot_; }
  long points() const { return points_; }

 private:
  Model& model_;
  ConstraintShape shape_;
  std::vector<double> c_;
  double last_g_ = 0.0, last_gdot_ = 0.0;
  Peak g_, gdot_;
  long points_ = 0;
};

/// How far a row that must hold (a lagrange or cut joint's; Model::
/// constraint_held) may be violated at an output point before the run stops:
/// kHeldFactor times what the tolerances ask of a unit quantity (rtol x 1 +
/// atol, rows being metres or radians; rtol never below
/// ErrorWeights::kResolvedRtol), and never more than kHeldCeiling (a
/// centimetre, or 0.01 rad, whatever the tolerances). A loop that closes stays
/// within a few times the tolerances (Baumgarte pulls it back; IDA holds it),
/// but not below what rounding leaves where rows become dependent: through
/// the aligned passages of IFToMM's N four-bar (N = 4, 10 s) the cut joints'
/// rows drifted by up to 4.3e-9, 2.0e-9, 2.5e-10 and 1.4e-9 m under IDA at
/// rtol 1e-10 to 1e-13, and by 5e-10 m under dopri5 at 1e-11 to 1e-13.
/// A penalty's row gives as its spring does, whatever the tolerances: it
/// stops the run beyond kHeldCeiling alone (a compliance that large belongs
/// in a spring-damper, not a joint).
double held_row_bound(const Settings& s);
inline constexpr double kHeldFactor = 1e3;
inline constexpr double kHeldCeiling = 1e-2;

/// The run-summary lines (without indentation or newline).
std::string describe(const AssemblyReport& a);
std::string describe(const RedundancyReport& r, const Model& model);
std::string describe(const InitialValuesReport& r, const ConstraintShape& shape);
std::string describe(const ConstraintMonitor& m);

}  // namespace mbgrt::detail
