// mbgrt/model.hpp — the contract between a generated model and the runtime.
//
// mbgc emits one class deriving from mbgrt::Model. The runtime owns everything
// that is not the model: the command line, the integrators (SUNDIALS), the CSV
// writer, the run summary and the divergence report.
//
// Two shapes of model exist:
//   * ODE:  x' = f(t, x)                         (is_dae() == false)
//   * DAE:  F(t, y, y') = 0, y = [states; algebraic unknowns]   (is_dae() == true)
// An ODE model can be integrated by every solver; a DAE model only by IDA.
//
// Either shape may carry holonomic joint constraints (multibody models):
//   * `lagrange`: a DAE in the stabilised index-2 form of Gear-Gupta-Leimkuhler,
//     y = [states; lambda; mu], residual rows = [x' - f(x, lambda) - G(x)^T mu
//     for the states; gdot(x) = 0 (the rows of lambda); g(x) = 0 (the rows of
//     mu)], constraints_enforced() == true. multiplier_index() and
//     stabiliser_index() say where each row's lambda and mu sit in y, and so
//     which residual rows are the constraint rows (the row of lambda_j is
//     gdot_j = 0, the row of mu_j is g_j = 0; every other residual row is the
//     equation of the unknown of its index). The residual must not depend on
//     y' of the algebraic unknowns;
//   * `penalty`: an ODE with stiff spring-dampers; the constraints are only
//     monitored, constraints_enforced() == false.
// Such a model states its layout (unknown_role: which unknowns are positions,
// velocities, multipliers) and G = dg/dx symbolically (constraint_jacobian);
// the runtime does not discover either. It (1) assembles the initial state:
// it moves the position states so that g = 0, then the velocity states so
// that gdot = 0, both by minimum-norm Gauss-Newton steps; (2) for DAEs
// computes y' and the algebraic unknowns itself (IDACalcIC cannot handle the
// constraint rows, which depend on neither y' nor an algebraic unknown);
// (3) evaluates g and gdot at every output point and reports the drift
// (lagrange) or violation (penalty).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "mbgrt/integrators.hpp"

namespace mbgrt {


/// What a model's rank-revealing solves found during a run (the multipliers
/// of cut joints or closed contacts whose rows became dependent): the
/// generated code reports each solve (observe), the runtime prints those that
/// lost rank in the run summary. The
/// solves are grouped into episodes, one per stretch of time the rows stayed
/// dependent (a mechanism's passage through a change point): records less
/// than kEpisodeGap apart belong to one.
class RankLossLog {
 public:
  static constexpr double kEpisodeGap = 1e-3;  ///< s
  static constexpr std::size_t kMaxEpisodes = 100;  ///< kept in detail; later ones only counted

  struct Episode {
    double begin = 0.0, end = 0.0;  ///< first and last time a solve lost rank in it
    long evaluations = 0;
    int lowest_rank = 0, size = 0;  ///< of the system, at its lowest rank
    std::string rows;  ///< dependent at the lowest rank, in model terms
  };

  /// A solve of the n x n system `system` at time t (what the generated
  /// code calls after each): a rank below n is recorded. For a system of cut
  /// joints' rows (`cut_joints`), where a dependent row means a change point
  /// of the mechanism, `closest`, its smallest pivot over its largest entry
  /// (solve_rank_revealing), is kept if the closest yet, and rank losses are
  /// counted apart.
  void observe(double t, const char* system, int rank, int n, const int* dependent, const char* const* row_names,
               double closest, bool cut_joints) {
    if (cut_joints && closest < closest_) closest_ = closest, closest_t_ = t;
    if (cut_joints) keep_latest(system, rank < n ? 0.0 : closest);  // (a lost row: the kept ones may be well apart)
    if (cut_joints) cut_rank_low_ = rank < cut_rank_low_ ? rank : cut_rank_low_, cut_rank_high_ = rank > cut_rank_high_ ? rank : cut_rank_high_;
    if (rank >= n) return;
    if (cut_joints && cut_joint_count_++ == 0) cut_joint_first_t_ = t;
    record(t, system, rank, n, dependent, row_names);
  }
  /// Of the cut joints' systems: the smallest pivot ratio a solve met (1 if
  /// none ran) and when; the solves that lost rank and the first time one did.
  double closest() const { return closest_; }
  /// A cut joints' system has been solved.
  bool cut_joints_solved() const { return !latest_.empty(); }
  /// The smallest pivot ratio of the cut joints' systems as each was last
  /// solved (at the model's latest evaluation), 0 where one lost rank; 1 if
  /// none ran.
  double latest_closest() const {
    double least = 1.0;
    for (const auto& l : latest_) least = l.second < least ? l.second : least;
    return least;
  }
  double closest_t() const { return closest_t_; }
  long cut_joint_count() const { return cut_joint_count_; }
  double cut_joint_first_t() const { return cut_joint_first_t_; }
  /// The cut joints' rank changed during the run: rows became dependent and
  /// independent again (a change point), rather than some row being implied
  /// by the others throughout (a redundant loop such as Bricard's).
  bool cut_joint_rank_changed() const { return cut_rank_low_ < cut_rank_high_; }

  long count() const { return count_; }      ///< solves that lost rank (derivative evaluations)
  double first_t() const { return first_t_; }  ///< the first time one did
  int lowest_rank() const { return lowest_rank_; }
  int size() const { return size_; }
  double lowest_t() const { return lowest_t_; }  ///< when the lowest rank was first found
  const std::string& system() const { return system_; }
  const std::string& rows() const { return rows_; }  ///< the rows dependent then, in model terms
  const std::vector<Episode>& episodes() const { return episodes_; }
  /// Episodes beyond kMaxEpisodes, not kept.
  std::size_t later_episodes() const { return uncounted_; }

 private:
  /// A solve of the n x n system `system` found `rank` < n at time t, the
  /// rows dependent[0 .. n - rank) named by row_names.
  void record(double t, const char* system, int rank, int n, const int* dependent, const char* const* row_names) {
    if (count_++ == 0) first_t_ = t;
    Episode* e = nullptr;
    if (!episodes_.empty() && t >= episodes_.back().begin - kEpisodeGap && t <= episodes_.back().end + kEpisodeGap) {
      e = &episodes_.back();
    } else if (episodes_.size() < kMaxEpisodes) {
      episodes_.push_back(Episode{t, t, 0, n, n, {}});
      e = &episodes_.back();
    } else if (t > last_t_ + kEpisodeGap) {
      ++uncounted_;
    }
    last_t_ = t;
    if (e) {
      e->begin = t < e->begin ? t : e->begin;
      e->end = t > e->end ? t : e->end;
      ++e->evaluations;
      if (rank - n < e->lowest_rank - e->size)
        e->lowest_rank = rank, e->size = n, e->rows = names(rank, n, dependent, row_names);
    }
    if (rank >= lowest_rank_ && count_ > 1) return;
    lowest_rank_ = rank, size_ = n, lowest_t_ = t, system_ = system;
    rows_ = names(rank, n, dependent, row_names);
  }
  void keep_latest(const char* system, double closest) {
    for (auto& l : latest_)
      if (l.first == system || std::strcmp(l.first, system) == 0) {
        l.second = closest;
        return;
      }
    latest_.emplace_back(system, closest);
  }
  static std::string names(int rank, int n, const int* dependent, const char* const* row_names) {
    std::string out;
    for (int k = 0; k < n - rank; ++k) {
      if (k) out += ", ";
      out += row_names[dependent[k]];
    }
    return out;
  }
  int cut_rank_low_ = 1 << 30, cut_rank_high_ = -1;  ///< of the cut joints' solves
  /// per cut joints' system (its name, a literal): its last pivot ratio
  std::vector<std::pair<const char*, double>> latest_;
  long count_ = 0;
  double first_t_ = 0.0, lowest_t_ = 0.0, last_t_ = 0.0;
  double closest_ = 1.0, closest_t_ = 0.0, cut_joint_first_t_ = 0.0;
  long cut_joint_count_ = 0;
  int lowest_rank_ = 0, size_ = 0;
  std::string system_, rows_;
  std::vector<Episode> episodes_;
  std::size_t uncounted_ = 0;
};


/// IDA's linear solver: dense LU, or KLU on the model's sparsity pattern
/// (Model::residual_sparsity); `automatic` takes KLU for a DAE of at least
/// kSparseFromUnknowns unknowns that gives its pattern (measured: KLU 1.5x
/// faster than dense LU on a 42-unknown double pendulum, 1.4x slower on an
/// 8-unknown pendulum; 7.7x faster on the 32-rod chain, 736 unknowns).
enum class LinearSolver { automatic, dense, sparse };
inline constexpr std::size_t kSparseFromUnknowns = 40;

/// Run settings. The model supplies defaults from its `simulate { }` block;
/// the command line overrides them.
struct Settings {
  double t_start_s = 0.0;
  double t_end_s = 1.0;
  double interval_s = 0.01;   ///< communication interval: one CSV row per interval
  Solver solver = kDefaultOdeSolver;
  double rtol = 1e-6;
  double atol = 1e-8;
  double step_s = 0.0;        ///< fixed step of the fixed-step methods (0: use interval/10)
  double rho_inf = 0.8;       ///< generalized_alpha: the spectral radius at an infinite step, in [0, 1]
  double accuracy = 0.0;      ///< > 0: a single run picks its own solver and step to meet this error (--accuracy)
  LinearSolver linear_solver = LinearSolver::automatic;  ///< IDA only
};

/// How a body is drawn in an animation (Model::body_visual, --animate): a
/// shape in the body's axes, placed by the body's pose at each output row.
/// A flexible body also gives a surface that deforms with its modes: the
/// undeformed vertex positions and, per mode, each vertex's displacement per
/// unit modal coordinate (glTF morph targets).
///
/// A surface the bodies touch is drawn the same way (`surface` set: a
/// contact's plane, sphere, cylinder or polygon, a tyre's road), posed by its
/// point and frame; the viewer neither frames nor follows it. Unbounded ones
/// are sized when the file is written, to cover where the bodies went: a
/// plane (its x-y plane), a cylinder of length 0, a prism's extrusion, a road.
struct BodyVisual {
  enum class Shape { box, cylinder, sphere, mesh, plane, prism, road };
  std::string name;
  Shape shape = Shape::box;
  /// box: edge lengths along body x, y, z; cylinder: radius, length (along body z;
  /// 0: unbounded, sized from the run); sphere: radius (m); plane, prism, road: unused
  double size[3] = {0.1, 0.1, 0.1};
  double centre[3] = {0, 0, 0};  ///< where the shape's centre is, body axes (m)
  double colour[3] = {0.6, 0.6, 0.65};  ///< linear RGB in [0, 1]
  /// Shape::mesh: triangles over `vertices` (3 indices each); a flexible
  /// body's surface. Vertices: 3 numbers each, body axes (m).
  std::vector<double> vertices;
  std::vector<unsigned> triangles;
  /// Per mode (Model::body_poses' modal coordinates, in order): 3 numbers per vertex.
  std::vector<std::vector<double>> mode_shapes;
  bool surface = false;  ///< a contact surface or a road, not a body
  /// A surface: the bodies (indices of body_visual) touching it, whose run
  /// its unbounded extent covers (empty: all the bodies').
  std::vector<std::size_t> covers;
  /// prism: the corners (x, z) of a convex polygon in the x-z plane,
  /// counter-clockwise, extruded along y; road: (x, height) points along world
  /// x, x increasing, the height constant beyond the ends (none: flat, z = 0).
  std::vector<double> profile;
};

/// A contact of the model (Model::contact): a gap g >= 0 between two bodies
/// whose mode is one of the model's events.
struct ContactInfo {
  std::size_t event = 0;     ///< its event (Model::event_name); the event's mode is 1 while the contact is closed
  bool compliant = false;    ///< Hunt-Crossley force (else unilateral: a row while it pushes, impacts as impulses)
  double restitution = 0.0;  ///< Newton's coefficient: normal speed after an impact / before
  long friction_event = -1;  ///< unilateral with friction: the event whose mode is 1 while it sticks
};

/// What an unknown of y is (Model::unknown_role): the layout the generated
/// model states, so that the runtime need not discover it.
enum class UnknownRole {
  unspecified,  ///< the model does not say (allowed only for a model without constraints)
  position,     ///< a displacement state: q of a C (a position, an angle, a modal coordinate, a charge)
  velocity,     ///< a momentum-level state: p of an I, an independent joint rate
  algebraic,    ///< DAE: an algebraic unknown other than a multiplier
  multiplier,   ///< DAE: lambda of a lagrange row (Model::multiplier_index)
  stabiliser,   ///< DAE: the GGL multiplier mu of a lagrange row (Model::stabiliser_index)
};

/// A named, overridable model parameter (`--set NAME=VALUE`).
struct ParameterInfo {
  std::string name;
  double default_value;      ///< value from the model text, in its unit (NaN if it is computed from other parameters)
  std::string unit_or_doc;   ///< the unit the model declares it in (`deg`: set_parameter takes degrees), or
                             ///< empty (SI); "= FORMULA" for a computed one
  std::string si_unit = {};  ///< its unit in SI where the compiler's units check fixed it (declared, stated by the
                             ///< multibody layer, or inferred: `kg*m^2`, `1` for a number); empty: not known
};

class Model {
 public:
  virtual ~Model() = default;

  // ---- identity ---------------------------------------------------------
  virtual const char* name() const = 0;         ///< model name from the .mbg file
  virtual const char* source_file() const = 0;  ///< .mbg file it was generated from
  /// A new instance of the same model class with its default parameters (a
  /// parameter sweep runs one per thread); nullptr if the class cannot.
  virtual std::unique_ptr<Model> make_new() const { return nullptr; }

  // ---- sizes and names -----------------------------------------------------
  /// Number of unknowns handed to the integrator: states (ODE) or y (DAE).
  virtual std::size_t size() const = 0;
  /// Name of unknown i in model terms (e.g. "armature_l.p"); used in reports.
  virtual std::string variable_name(std::size_t i) const = 0;
  /// Output column names, in declaration order (the CSV header after `t`).
  virtual std::vector<std::string> output_names() const = 0;
  /// The unit each output is declared in (`output omega = shaft.f {rad/s}`),
  /// "" for one declared in none; empty: no output declares one. The values
  /// are in SI; the CSV header names the unit: `omega [rad/s]`.
  virtual std::vector<std::string> output_units() const { return {}; }
  virtual std::vector<ParameterInfo> parameters() const = 0;

  virtual bool is_dae() const { return false; }
  /// NOMINAL: the size of unknown i its absolute error is measured against:
  /// the adaptive integrators' absolute tolerance for it is atol x nominal(i).
  /// mbgc gives a momentum its inertia (so that atol bounds every body's
  /// velocity error alike, a 1e-9 kg body's as a 1e3 kg one's) and a modal
  /// coordinate its validity limit (reduce/nominal.hpp); 1 otherwise. Read
  /// after initial(), which may compute it from the parameters.
  virtual double nominal(std::size_t i) const { (void)i; return 1.0; }
  /// GROUP: the first unknown of unknown i's group (i itself if it is alone):
  /// the components of one vector, e.g. a body's momentum. The integrators
  /// measure a component's error relative to its own size but never to less
  /// than a tenth of its whole vector's (the group's 2-norm), so that a
  /// component that is zero in these axes but for rounding is not held to
  /// atol alone.
  virtual std::size_t unknown_group(std::size_t i) const { return i; }
  /// LAYOUT: what unknown i is. A model with constraints must say it for every
  /// unknown: the runtime moves the positions and then the velocities to
  /// assemble the initial state, and names the constraint rows from it.
  virtual UnknownRole unknown_role(std::size_t i) const { (void)i; return UnknownRole::unspecified; }
  /// DAE only: 1.0 for differential components of y, 0.0 for algebraic ones.
  virtual void differential_ids(double* id) const { (void)id; }

  /// Defaults from the model's `simulate { }` block.
  virtual Settings default_settings() const = 0;

  // ---- parameters ------------------------------------------------------------
  /// Override a parameter before initial(). Returns false for an unknown name.
  virtual bool set_parameter(const std::string& name, double value) = 0;
  /// Each parameter's value as initial() set it (overrides and formulas
  /// applied), in SI, in parameters() order. False when the model does not
  /// say: mbgc writes it into an FMU's model (its calculated parameters).
  virtual bool parameter_values(double* out) const { (void)out; return false; }

  // ---- ACSL sections ---------------------------------------------------------
  /// INITIAL: evaluate parameters (honouring overrides), then write the initial
  /// unknowns into y (and, for DAEs, a first guess of y' into yp; yp may be null
  /// for ODEs).
  virtual void initial(double t, double* y, double* yp) = 0;

  /// DERIVATIVE (ODE): ydot = f(t, y). Must not throw.
  virtual void derivative(double t, const double* y, double* ydot) { (void)t; (void)y; (void)ydot; }

  /// RESIDUAL (DAE): r = F(t, y, yp). Must not throw.
  virtual void residual(double t, const double* y, const double* yp, double* r) {
    (void)t; (void)y; (void)yp; (void)r;
  }

  /// SPARSITY (DAE, optional): where IDA's Newton matrix dF/dy + c_j dF/dy'
  /// can be nonzero, in compressed sparse columns: the rows of column k are
  /// rows[column_starts[k] .. column_starts[k + 1]), ascending. A model that
  /// gives it returns true; IDA then uses a sparse direct solver (KLU) on a
  /// large system, differencing columns that share no row together.
  virtual bool residual_sparsity(std::vector<long>& column_starts, std::vector<long>& rows) const {
    (void)column_starts; (void)rows;
    return false;
  }

  /// JACOBIAN (ODE, optional): J[i * size() + j] = d ydot_i / d y_j at (t, y),
  /// row-major. A model that provides it returns true from has_jacobian(); the
  /// implicit solvers then use it instead of finite differences.
  /// |state i| beyond which the model no longer holds (HUGE_VAL: no limit),
  /// and why; the run stops there with the reason (a beam's modal coordinates).
  virtual double state_limit(std::size_t i) const { (void)i; return HUGE_VAL; }
  virtual std::string state_limit_reason(std::size_t i) const { (void)i; return {}; }

  /// Joint coordinates with cut joints: what the multipliers' rank-revealing
  /// solves found (rows that became dependent during the run); null if the
  /// model has no such solve.
  virtual const RankLossLog* rank_loss() const { return nullptr; }

  /// POSITION RATES (ODE, optional): ydot[i] = f_i(t, y) for the unknowns
  /// whose role is a position (unknown_role), the other entries of ydot left
  /// as they are: what the symplectic Euler evaluates at the new velocities.
  /// A model that provides it returns true from has_position_rates(); the
  /// runtime otherwise evaluates the whole derivative.
  virtual bool has_position_rates() const { return false; }
  virtual void position_rates(double t, const double* y, double* ydot) { derivative(t, y, ydot); }

  virtual bool has_jacobian() const { return false; }
  virtual void jacobian(double t, const double* y, double* J) { (void)t; (void)y; (void)J; }

  /// OUTPUT: compute the declared outputs at (t, y). yp is the current
  /// derivative for DAEs and null for ODEs (the model recomputes what it needs).
  virtual void outputs(double t, const double* y, const double* yp, double* out) = 0;

  // ---- events (optional) ----------------------------------------------------
  /// The model's discontinuities: each is a step(x) the model holds as a mode
  /// (1 while on) between the zero crossings of x, which the integrators
  /// locate; the runtime switches the mode there and restarts the method, so
  /// that no step straddles a jump.
  virtual std::size_t event_count() const { return 0; }
  /// EVENTS: g[k] = x of event k at (t, y); yp as for outputs(). Must not throw.
  virtual void event_functions(double t, const double* y, const double* yp, double* g) {
    (void)t; (void)y; (void)yp; (void)g;
  }
  /// Event k in model terms, e.g. "step(t - t_bump) (time event)".
  virtual std::string event_name(std::size_t k) const { return "event " + std::to_string(k); }
  /// Switches event k's mode on or off; false if it already was.
  virtual bool set_event_mode(std::size_t k, bool on) { (void)k; (void)on; return false; }
  /// JUMP: what event k's switch does to the unknowns besides its mode (an
  /// impact's velocity jump by Newton's restitution law), written into y at t
  /// right after set_event_mode switched it. True if y changed; the runtime
  /// then restarts the integrator from the new y (for a DAE with y' and the
  /// algebraic unknowns made consistent again). Leave y on the side of the
  /// crossing its mode now says (an impact puts the contact point on the
  /// surface, not at the rounding level where the root was found), so that
  /// the next crossing is seen; a jump may switch modes back itself.
  virtual bool event_jump(std::size_t k, bool on, double t, double* y) {
    (void)k; (void)on; (void)t; (void)y;
    return false;
  }

  /// HELD STATE: what the model holds that a run changes besides y (its
  /// events' modes, what the runtime set of its contacts), as doubles: saved
  /// and restored with y where a run is (an FMU's state). 0: nothing.
  virtual std::size_t held_state_size() const { return 0; }
  virtual void get_held_state(double* out) const { (void)out; }
  virtual void set_held_state(const double* in) { (void)in; }

  // ---- bodies, for animation (optional) --------------------------------------
  /// Bodies to draw (--animate), then the surfaces they touch; 0: none (a bond graph).
  virtual std::size_t body_count() const { return 0; }
  virtual BodyVisual body_visual(std::size_t i) const { (void)i; return {}; }
  /// Per body, in order: its frame's origin (3, world, m) and its rotation
  /// (9, body to world, row-major); then every body's modal coordinates, as
  /// many as its visual's mode_shapes, in body order.
  virtual void body_poses(double t, const double* y, const double* yp, double* out) {
    (void)t; (void)y; (void)yp; (void)out;
  }

  // ---- contacts (optional) ---------------------------------------------------
  /// Each contact's event function is its gap g while open and, for a
  /// unilateral contact while closed, its normal force (which must not pull).
  /// The runtime (runtime/src/contacts.cpp) switches the modes and applies the
  /// impacts: an impulse is found from the state derivative with the contact
  /// closed and its row's bias, the extra normal acceleration it imposes.
  virtual std::size_t contact_count() const { return 0; }
  virtual ContactInfo contact(std::size_t c) const { (void)c; return {}; }
  /// CONTACT SPEEDS: v[c] = dg/dt of contact c at (t, y); yp as for outputs().
  virtual void contact_speeds(double t, const double* y, const double* yp, double* v) {
    (void)t; (void)y; (void)yp; (void)v;
  }
  /// CONTACT TANGENTS: out[2c], out[2c + 1] = contact c's sliding velocity
  /// along its two tangents, out[2C + 2c], out[2C + 2c + 1] = its friction
  /// along them (C = contact_count(); zeros for a contact without friction rows).
  virtual void contact_tangents(double t, const double* y, const double* yp, double* out) {
    (void)t; (void)y; (void)yp; (void)out;
  }
  /// Unilateral contact c with friction, sliding: the slip direction (unit,
  /// in its tangent basis); the friction is -mu push along it.
  virtual void set_contact_slip(std::size_t c, double d1, double d2) { (void)c; (void)d1; (void)d2; }
  /// Unilateral contact c while closed: its row keeps g'' + 2 w g' + w^2 g = b.
  virtual void set_contact_bias(std::size_t c, double b) { (void)c; (void)b; }
  /// Compliant contact c: its Hunt-Crossley damping chi / v- (1/(m/s)), set when it closes.
  virtual void set_contact_damping(std::size_t c, double d) { (void)c; (void)d; }

  /// TERMINAL: called once after the run (successful or not).
  virtual void terminal(double t, const double* y) { (void)t; (void)y; }

  // ---- the energy balance (optional): a witness of the integration error ------
  /// A bond graph knows where its energy goes: H(y(t)) - H(y(0)) equals the
  /// integral of the power the sources supply minus the power the
  /// dissipators, constraints and contacts absorb. The runtime integrates
  /// both powers beside the state and reports what the run misses of the
  /// balance (compiler/reduce/energy.hpp).
  virtual bool has_energy_balance() const { return false; }
  /// STORED ENERGY: out[0] = H at (t, y), every linear storage's; yp as for outputs().
  virtual void stored_energy(double t, const double* y, const double* yp, double* out) {
    (void)t; (void)y; (void)yp; out[0] = 0.0;
  }
  /// POWER at (t, y; yp as for outputs()): out[0] the power the sources
  /// deliver, out[1] the power the rest absorbs (W).
  virtual void power(double t, const double* y, const double* yp, double* out) {
    (void)t; (void)y; (void)yp; out[0] = out[1] = 0.0;
  }
  /// DERIVATIVE AND POWER (ODE): derivative() and power() at (t, y) in one
  /// call, for the methods that integrate the witness in their own stages.
  /// The powers read the kinematics and forces the derivative computes, so a
  /// generated model gives both from one pass; this default calls the two.
  virtual void derivative_and_power(double t, const double* y, double* ydot, double* rate) {
    derivative(t, y, ydot);
    power(t, y, nullptr, rate);
  }
  /// What the balance leaves out (storages counted by their power), or why
  /// the model has none; empty if neither.
  virtual std::string energy_note() const { return {}; }

  // ---- joint constraints (optional; see the top of this file) ---------------
  /// DAE only: number of differential states; y = [states; algebraic unknowns],
  /// so differential_ids() must be 1.0 for the first state_count() entries and
  /// 0.0 after them. For an ODE every unknown is a state.
  virtual std::size_t state_count() const { return size(); }
  /// Number of position-level constraints g(x) = 0.
  virtual std::size_t position_constraint_count() const { return 0; }
  /// Number of velocity-level constraints gdot(x) = 0 (normally one per g row).
  virtual std::size_t velocity_constraint_count() const { return 0; }
  /// CONSTRAINTS: c[0 .. P) = g, then c[P .. P + V) = gdot, where
  /// P = position_constraint_count() and V = velocity_constraint_count().
  /// `x` points at y; only its first state_count() entries (the states) may be
  /// read: for a DAE, lambda and mu are not inputs. Must not throw.
  virtual void constraints(double t, const double* x, double* c) { (void)t; (void)x; (void)c; }
  /// CONSTRAINT JACOBIAN (required with constraints): G = dg/dx, the
  /// derivatives of the position rows g by the states, symbolically. Its
  /// pattern, row by row: row r reads the states columns[row_starts[r] ..
  /// row_starts[r + 1]), ascending (row_starts has P + 1 entries; a model that
  /// leaves it empty gives no Jacobian). constraint_jacobian() writes the
  /// values at (t, x) in the same order. x as for constraints().
  virtual void constraint_jacobian_pattern(std::vector<long>& row_starts, std::vector<long>& columns) const {
    (void)row_starts; (void)columns;
  }
  virtual void constraint_jacobian(double t, const double* x, double* values) { (void)t; (void)x; (void)values; }
  /// Name of entry i of constraints() in model terms, e.g. "j1.g[2]" for
  /// i < P and "j1.gdot[2]" for i >= P; used in reports.
  virtual std::string constraint_name(std::size_t i) const {
    const std::size_t p = position_constraint_count();
    return i < p ? "g[" + std::to_string(i) + "]" : "gdot[" + std::to_string(i - p) + "]";
  }
  /// DAE only: the index in y of the multiplier lambda of constraint row
  /// `row` (0 <= row < P), whose residual row (of the same index) is gdot_row
  /// = 0, and of the GGL multiplier mu, whose residual row is g_row = 0; -1
  /// for a penalty row. The runtime holds both at 0 for rows it finds
  /// redundant (implied by the others), replacing their residual rows.
  virtual long multiplier_index(std::size_t row) const { (void)row; return -1; }
  virtual long stabiliser_index(std::size_t row) const { (void)row; return -1; }
  /// true (lagrange): the solver enforces the constraints, so what remains is
  /// reported as "constraint drift"; false (penalty): reported as "largest
  /// constraint violation".
  virtual bool constraints_enforced() const { return false; }
  /// Whether position row `row` is meant to hold (a lagrange row, a cut
  /// joint's Baumgarte-stabilised row) rather than be pulled back (a
  /// penalty's): a held row violated beyond what the run's tolerances allow
  /// stops the run (the loop cannot close).
  virtual bool constraint_held(std::size_t row) const { return multiplier_index(row) >= 0; }
};

/// The simulator's entry point: parse the command line (docs/cli.md), run,
/// write CSV and the summary. Returns the process exit status.
int run_main(Model& model, int argc, char** argv);

}  // namespace mbgrt
