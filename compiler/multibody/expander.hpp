// multibody/expander.hpp — the multibody pass's working state (private to
// compiler/multibody). One Expander runs once per model: it collects bodies,
// joints and force elements, then writes each as multibond-graph fragments
// (layer-1 statements). Its member functions live in one file per topic,
// named in the section comments below; expand.hpp is the pass's interface.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "ir/ast.hpp"
#include "ir/constant.hpp"
#include "ir/expanded.hpp"
#include "ir/diagnostics.hpp"
#include "multibody/build.hpp"
#include "multibody/contact_symbols.hpp"
#include "multibody/expand.hpp"
#include "multibody/flexible_symbols.hpp"
#include "multibody/joint_kind.hpp"
#include "multibody/joint_symbols.hpp"
#include "multibody/model.hpp"
#include "multibody/settings.hpp"

namespace mbgc::multibody::detail {

using namespace mbgc::ir;  // the multibody layer builds the AST's statements throughout

/// Quantities `body.NAME` and `joint.NAME` users may read (defined in define_quantities).
inline const std::vector<std::string> kBodyQuantities = {"position", "velocity", "momentum", "quaternion", "rotation", "bryant",
                                                  "omega", "omega_world", "angular_momentum", "kinetic_energy",
                                                  "potential_energy"};
/// Names a flexible body's expansion adds (`arm.eta`, `arm.nu`, ...): not free for a modal body's nodes.
inline const std::set<std::string> kFlexibleInternalNames = {"eta", "nu", "M", "sv", "sw", "se", "etadot", "damp", "modes",
                                                      "J0", "first_moment", "mean", "stiffness", "damping",
                                                      "modal_mass", "J1", "J2", "Hw", "elastic_energy"};
/// Names a body's expansion uses for itself (`bob.mass`, `bob.v`, ...): not free for points.
inline const std::set<std::string> kBodyInternalNames = {"mass", "inertia", "com", "r0", "v0", "q0", "w0", "v", "m", "r",
                                                  "weight", "w", "J", "ejs", "qrate", "q"};

class Beam;

class Expander {
 public:
  Expander(ir::SourceManager& sources, Diagnostics& diags, const ExpandOptions& options)
      : sources_(sources), diags_(diags), search_dirs_(options.search_dirs), override_(options.constraints),
        strategy_(options.constraints.value_or(Strategy::Auto)), strategy_report_(options.strategy_report),
        contact_strategy_(options.contacts.value_or(ContactStrategy::Unilateral)) {}

  ir::ExpandedProgram run(const AstProgram& in);

 private:
  // ---- the pass: run(), and the statements it writes (expand.cpp)
  // A run-time parameter (a setting: a penalty's stiffness, a force's law,
  // an initial value), and a property (geometry, mass, frames, modal
  // integrals, gravity), folded where it depends on literals (ExpandedParam::fold).
  void param(const Build& B, const Sym& name, E value);
  void property(const Build& B, const Sym& name, E value);
  void element(const Build& B, const std::string& kind, const Sym& name, E value, std::vector<AstAttr> attrs = {});
  /// A CN `name` holding `law.g` as `law` says (ir::ConstraintLaw).
  void constraint(const Build& B, const Sym& name, ir::ConstraintLaw law);
  void junction(const Build& B, char type, const Sym& name, int dim, const std::vector<Sym>& in, const std::vector<Sym>& out);
  void bond(const Build& B, const Sym& from, const Sym& to, std::optional<int> dim = std::nullopt);
  void signal(const Build& B, const Sym& name, E value, E rate = nullptr);
  /// A 1-junction with the given elements bonded into / out of it.
  void junction_(const Build& B, const Sym& name, const std::vector<Sym>& in, const std::vector<Sym>& out = {});
  void named_bond(const Build& B, const Sym& name, const Sym& from, const Sym& to);

  // ---- 1. collect and check bodies, joints, force elements and settings (collect.cpp; contacts: contacts.cpp)
  void collect(const AstProgram& in);
  bool connector_name_ok(const AstJoint& j, std::map<std::string, const AstJoint*>& seen);
  void duplicate(const char* what, const std::string& name, const SourceLoc& at, const SourceLoc& first);
  void setting(const AstSetting& st);
  std::optional<Strategy> strategy_of(const AstExpr& v, const char* key);
  void add_body(const AstBody& b);
  void add_points(Body& body, const AstBody& b, const std::string& owner);
  std::optional<Side> side(const AstEndpoint& ep);
  void add_force(const AstJoint& f);
  /// A connector's settings by key into `attrs`: an unknown key (with a
  /// did-you-mean, else `unknown_hint`) or a key given twice is an error.
  bool collect_settings(const AstJoint& c, const std::vector<std::string>& keys,
                        std::map<std::string, const AstAttr*>& attrs, const std::string& unknown_hint);
  void check_joint_constant(const JointKind& kind, const AstJoint& j, const AstAttr& at);
  void add_joint(const AstJoint& j);

  // ---- shapes and constants known from the text (shapes.cpp)
  std::optional<Shape> shape_of(const AstExpr& e, int depth = 0) const;
  std::optional<double> constant_of(const AstExpr& e, int depth = 0) const;
  /// ir::constant_value's rules here: parameters by their definitions, to
  /// kMaxConstantDepth levels (a definition that refers back to itself has
  /// no value); with `functions`, also pi and the scalar functions.
  ir::ConstantRules constant_rules(bool functions) const;
  static constexpr int kMaxConstantDepth = 50;
  static bool mentions_time(const AstExpr& e);
  void check_shape(const AstExpr& value, const std::string& what, const Expected& want, bool constant = true);

  // ---- 1b. settings of flexible bodies: beams and modal-data files (flexible_settings.cpp;
  // their tables: settings.hpp)
  void check_frame(Beam& beam, const AstBody& b, const AstAttr* given);
  bool tisserand_allowed(const Beam& beam, const AstBody& b, const SourceLoc& loc);
  void add_flexible_body(Body& body, const AstBody& b, const AstAttr& kind);
  int mode_count(const AstExpr& v) const;
  void record_setting(std::map<std::string, const AstAttr*>& given, const AstAttr& a, const AstBody& b);
  void read_slope_limit(double& limit_rad, const AstBody& b, const AstAttr& a);
  void add_modal_body(Body& body, const AstBody& b, const AstExpr& v);
  void check_section(const AstExpr& v);

  // ---- 2. rigid bodies and particles; the pose of any body (rigid_body.cpp)
  void emit_body(const Body& body);
  void emit_rigid(const Body& body);
  E position(const Build& B, const std::string& body) const;
  E quaternion(const Build& B, const std::string& body) const;
  E rotation(const Build& B, const std::string& body) const;
  bool body_frame_velocity(const Body& b) const;
  E velocity(const Build& B, const std::string& body) const;

  // ---- 2b. flexible bodies: the floating-frame fragment every deformation kind shares (flexible_body.cpp;
  //      the kinds: beam.hpp, modal_body.hpp)
  Eta state_eta(const Build& B, const std::string& body, const Deformation& field) const;
  void emit_flexible(const Body& body);
  std::pair<E, E> flexible_point_motion(const Build& B, const std::string& body, E local) const;
  E flexible_load(const Build& B, const std::string& body, const std::string& point, E force, E torque);
  void flexible_quantities(const Build& B, const Body& body);

  // ---- 3. joints as constraint rows: lagrange and penalty (joint_rows.cpp)
  /// The joint frame on side 'a' or 'b' (`s`), in world axes.
  Frame frame(const Build& B, const Joint& j, const Side& s, char side);
  void joint_params(const Build& B, const Joint& j);
  std::vector<E> rows(const Build& B, const Joint& j, const Frame& A, const Frame& Bf);
  void rates_into(const Build& B, const std::function<Sym(char)>& mtf, E rows_vec, const Frame& f, const Sym& sum,
                  bool towards_sum, bool translational);
  void emit_joint(Joint& j);
  void drive_loads(const Build& B, const Joint& j);
  std::optional<E> joint_coordinate(const Build& B, const Joint& j, const Frame& A, const Frame& Bf);

  // ---- 3b. joints in joint coordinates (joint_coordinates.cpp)
  void emit_coordinate_joint(const Build& B, const Joint& j);
  /// Where a tree joint sits on a flexible body (all null for a rigid one):
  /// the deflected point, the section's small rotation theta, and (unless the
  /// joint's rotation is free) the turn rotq([1, theta/2]), its quaternion and
  /// the map W(theta) from theta' to the turn's angular velocity.
  struct FlexibleSeat { E point, slope, turn, quaternion, turn_rate; };
  FlexibleSeat flexible_seat(const Build& B, const Side& side, bool free_rotation) const;

  // ---- 4. the spanning tree and initial conditions along it (tree.cpp)
  void find_tree();
  std::vector<std::string> path_to_ground(std::string body) const;
  struct Problem { SourceLoc loc; std::string message, hint; };
  std::vector<Problem> coordinate_problems() const;
  void mark_coordinate_bodies();
  void choose_strategy();
  void check_coordinates();
  void place_bodies();
  std::string placed_hint(const std::string& jn) const;
  Pose pose(const Build& B, const std::string& body);
  void place(const Joint& j, bool a_is_parent);

  // ---- 5. force elements (forces.cpp)
  std::pair<E, E> world_point(const Build& B, const Side& s);
  void emit_force(const ForceElement& f);
  void apply_load(const Build& B, const LoadSym& source, const Side& s, E force, E torque, double sign);

  // ---- 5b. contacts (contacts.cpp)
  void add_contact(const AstJoint& c);
  void emit_contact(const Contact& c);
  void check_polygon(const Contact& c);
  std::pair<E, E> polygon_gap(const Build& B, const Contact& c, E d);

  // ---- 5c. tyres (tyres.cpp)
  void add_tyre(const AstJoint& t);
  void check_profile(const Tyre& t, const AstExpr& v);
  void emit_tyre(const Tyre& t);
  E sig_vector(const Build& B, const VectorSym& name, E value);

  // ---- 6b. how bodies are drawn for --animate (drawing.cpp)
  std::optional<std::array<double, 3>> constant_point(const AstExpr& e, int depth = 0) const;
  std::shared_ptr<Drawing> read_shape(const AstBody& b, const AstExpr& v);
  Drawing default_drawing(const Body& body, double scale) const;
  double model_scale() const;
  void draw_bodies();
  std::optional<double> drawn_number(const AstExpr& e, int depth = 0) const;
  void draw_surfaces();

  // ---- 6. quantities users may name (quantities.cpp)
  void define_quantities();
  void check_known(const AstExpr& e);
  E rewrite_expr(const E& e);
  ir::ExpandedStmt rewrite_user(const ir::ExpandedStmt& s);

  // ---- 7. the units of the values users write in these statements (units.cpp)
  void state_units(std::vector<ir::ExpandedUnitCheck>& out);
  void state_unit(const AstAttr& a, const std::optional<units::Dimension>& dimension, const std::string& what,
                  std::vector<ir::ExpandedUnitCheck>& out);

  ir::SourceManager& sources_;                // modal-data files join it (diagnostics, depfile)
  Diagnostics& diags_;
  std::vector<std::string> search_dirs_;     // mbgc -I: where modal-data files are looked for
  std::map<std::string, Body> bodies_;
  std::vector<std::string> body_order_;
  std::vector<Joint> joints_;
  std::vector<ForceElement> forces_;
  std::vector<Contact> contacts_;
  std::vector<Tyre> tyres_;
  std::map<std::string, std::vector<LoadSym>> loads_;  // body -> what pushes on it (force elements, friction, tyres)
  std::map<std::string, std::pair<Frame, Frame>> frames_;
  std::map<std::string, E> coordinates_;
  struct CoordinateValues { E angle, rate, displacement, displacement_rate; };
  std::map<std::string, CoordinateValues> coordinate_values_;  // coordinates joints
  std::vector<const Joint*> tree_order_;                        // tree joints, breadth first from ground
  std::map<std::string, E> quantity_;
  std::set<std::string> used_quantities_;  // the quantities the user's expressions name (units.cpp)
  std::map<std::string, E> params_;                // the program's top-level parameters
  std::map<std::string, SourceLoc> point_locs_;    // "body.point" -> declaration
  std::map<std::string, SourceLoc> instances_;     // component instances (their parts are named `instance.part`)
  std::set<std::string> repeated_;                 // names reported as declared in every loop iteration
  std::set<std::string> generated_names_;          // parameters, elements and junctions expand wrote
  std::vector<std::size_t> applied_;               // generated_ indices of joint drive loads (user expressions)
  E gravity_;
  SourceLoc gravity_loc_;
  std::optional<Strategy> override_;  // mbgc --constraints
  Strategy strategy_;                  // the model-level strategy
  std::string* strategy_report_;       // ExpandOptions::strategy_report
  ContactStrategy contact_strategy_;   // of contacts without their own (mbgc --contacts)
  std::vector<ir::ExpandedStmt> generated_;
  // While a body moved by joint coordinates (and its tree joint) is written:
  // the tree body and its parent every element and junction is tagged with.
  ir::TreeTag tree_tag_;
  /// Tags what is written while it lives with body `n`'s tree node (if `n` moves by coordinates).
  class TreeScope {
   public:
    TreeScope(Expander& x, const std::string& n) : x_(x), saved_(x.tree_tag_) {
      const Body& b = x.bodies_.at(n);
      if (b.by_coordinates) x.tree_tag_ = {n, b.tree_parent};
    }
    ~TreeScope() { x_.tree_tag_ = saved_; }
    TreeScope(const TreeScope&) = delete;
    TreeScope& operator=(const TreeScope&) = delete;

   private:
    Expander& x_;
    ir::TreeTag saved_;
  };
};

}  // namespace mbgc::multibody::detail
