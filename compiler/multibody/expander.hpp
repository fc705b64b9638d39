// multibody/expander.hpp — the multibody layer's third pass (private to
// compiler/multibody): it writes the bodies, joints, force elements, contacts
// and tyres of the Model, collected (collect.hpp) and with its spanning tree
// planned (spanning_tree.hpp), as multibond-graph fragments (layer-1
// statements), and defines the quantities users may name as it goes
// (quantities.hpp). Its member functions live in one file per topic, named in
// the section comments below; expand.cpp runs the passes in order.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
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
#include "multibody/quantities.hpp"
#include "multibody/rewrite.hpp"
#include "multibody/settings.hpp"
#include "multibody/shapes.hpp"

namespace mbgc::multibody::detail {

using namespace mbgc::ir;  // the multibody layer builds the expanded program's statements throughout

class Expander {
 public:
  /// Writes `m`'s fragments (run), defining its quantities in `quantities` as it goes; the joints' drive
  /// loads and the force elements' laws it writes are user expressions, which `rewrite` rewrites against them.
  /// Its references and declarations take their symbols' ids from `symbols`.
  Expander(const Model& m, Quantities& quantities, QuantityRewriter& rewrite, SymbolIds& symbols, Diagnostics& diags)
      : m_(m), quantities_(quantities), rewrite_(rewrite), symbols_(symbols), diags_(diags) {}

  /// The fragments, in the order they are written.
  std::vector<ir::ExpandedStmt> run();

 private:
  // ---- the pass: run(), and the statements it writes (expand.cpp)
  // A run-time parameter (a setting: a penalty's stiffness, a force's law,
  // an initial value), and a property (geometry, mass, frames, modal
  // integrals, gravity), folded where it depends on literals (ExpandedParam::fold).
  void param(const Build& B, const Sym& name, E value);
  void property(const Build& B, const Sym& name, E value);
  void element(const Build& B, const std::string& kind, const Sym& name, E value, std::vector<TermAttr> attrs = {});
  /// A CN `name` holding `law.g` as `law` says (ir::ConstraintLaw).
  void constraint(const Build& B, const Sym& name, ir::ConstraintLaw law);
  void junction(const Build& B, char type, const Sym& name, int dim, const std::vector<Sym>& in, const std::vector<Sym>& out);
  void bond(const Build& B, const Sym& from, const Sym& to, std::optional<int> dim = std::nullopt);
  void signal(const Build& B, const Sym& name, E value, E rate = nullptr);
  /// A 1-junction with the given elements bonded into / out of it.
  void junction_(const Build& B, const Sym& name, const std::vector<Sym>& in, const std::vector<Sym>& out = {});
  void named_bond(const Build& B, const Sym& name, const Sym& from, const Sym& to);

  // ---- 2. rigid bodies and particles; the pose of any body (rigid_body.cpp)
  void emit_body(const Body& body);
  void emit_rigid(const Body& body);
  E position(const Build& B, const std::string& body) const;
  E quaternion(const Build& B, const std::string& body) const;
  /// The frame of the body's equations (its junctions' axes), body -> world:
  /// the body's own axes, or a rotor's without its spin (rotors.hpp).
  E rotation(const Build& B, const std::string& body) const;
  /// A rotor's spin in the frame of its equations, axis times its joint's
  /// rate (null for any other body): its angular velocity there less the
  /// frame's.
  E rotor_spin(const Build& B, const Body& body) const;
  /// A rotor's turn by its joint's angle about its axis, as `form`
  /// ("rot_axis_angle" or "quat_axis_angle"): its frame -> its own axes
  /// (null for any other body; once its joint is written).
  E rotor_turn(const Build& B, const Body& body, const char* form) const;
  /// The body's own orientation, body -> world, as a rotation matrix and as a
  /// quaternion: rotation() and quaternion(), a rotor's with its spin put
  /// back (once its joint is written). What users read and what is drawn.
  E attitude(const Build& B, const std::string& body) const;
  E attitude_quaternion(const Build& B, const std::string& body) const;
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
  void emit_joint(const Joint& j);
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

  // ---- 4. initial conditions along the spanning tree (tree.cpp; the tree itself: spanning_tree.hpp)
  void place_bodies();
  std::string placed_hint(const std::string& jn) const;
  Pose pose(const Build& B, const std::string& body);
  void place(const Joint& j, bool a_is_parent);

  // ---- 5. force elements (forces.cpp)
  std::pair<E, E> world_point(const Build& B, const Side& s);
  void emit_force(const ForceElement& f);
  void apply_load(const Build& B, const LoadSym& source, const Side& s, E force, E torque, double sign);

  // ---- 5b. contacts (contacts.cpp)
  void emit_contact(const Contact& c);
  std::pair<E, E> polygon_gap(const Build& B, const Contact& c, E d);

  // ---- 5c. tyres (tyres.cpp)
  void emit_tyre(const Tyre& t);
  E sig_vector(const Build& B, const VectorSym& name, E value);

  // ---- 6b. how bodies are drawn for --animate (drawing.cpp)
  Drawing default_drawing(const Body& body, double scale) const;
  double model_scale() const;
  void draw_bodies();
  void draw_surfaces();

  // ---- 6. the quantities of bodies and joints users may name (quantities.cpp)
  void define_quantities();

  const Model& m_;              // what the collect pass read (collect.hpp), its spanning tree planned (spanning_tree.hpp)
  Quantities& quantities_;      // what users may name, as far as it is written
  QuantityRewriter& rewrite_;   // user expressions the fragments hold, rewritten against quantities_
  SymbolIds& symbols_;
  Diagnostics& diags_;
  Constants constants_{m_.params};
  std::map<std::string, std::pair<Frame, Frame>> frames_;
  std::map<std::string, E> coordinates_;
  struct CoordinateValues { E angle, rate, displacement, displacement_rate; };
  std::map<std::string, CoordinateValues> coordinate_values_;  // coordinates joints
  std::vector<std::size_t> applied_;  // generated_ indices of joint drive loads (user expressions)
  std::vector<ir::ExpandedStmt> generated_;
  // While a body moved by joint coordinates (and its tree joint) is written:
  // the tree body and its parent every element and junction is tagged with.
  ir::TreeTag tree_tag_;
  /// Tags what is written while it lives with body `n`'s tree node (if `n` moves by coordinates).
  class TreeScope {
   public:
    TreeScope(Expander& x, const std::string& n) : x_(x), saved_(x.tree_tag_) {
      const Body& b = x.m_.bodies.at(n);
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
