// multibody/symbols.hpp — the names of what the multibody layer writes.
//
// Every parameter, signal, element, junction and bond the layer writes is
// named here, once, by the entity it belongs to: `BodySym(n).mass()` is the
// parameter `n.mass`, `BodySym(n).v()` the junction of its velocity. The
// fragments refer to one another only through these symbols (Build::ref,
// and the Expander's writers take them), never by building a name, so that
// what one fragment reads is what another wrote. The other kinds' symbols:
// flexible_symbols.hpp, joint_symbols.hpp, contact_symbols.hpp.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "ir/term.hpp"
#include "multibody/settings.hpp"
#include "units/unit.hpp"

namespace mbgc::multibody::detail {

/// A name the layer writes or reads: a parameter, a signal, an element, a
/// junction, a bond, or one of their variables; a parameter's symbol also
/// says its dimension where the layer knows it (the units check and the
/// report read it: ExpandedParam::dimension).
class Sym {
 public:
  /// Its name as the generated program shows it (`arm.v.f`).
  const std::string& str() const { return name_; }
  const std::optional<units::Dimension>& dimension() const { return dimension_; }
  /// What a reference to it is: a declared entity's symbol (the owner's, for
  /// one of its variables), an element's own quantity inside its law, or pi.
  enum class Kind { Entity, Own, Pi };
  Kind kind() const { return kind_; }
  /// The entity a reference reads: itself, or the element or junction whose variable it is.
  const std::string& owner() const { return owner_.empty() ? name_ : owner_; }
  /// Which variable of its owner it is (ir::Quantity::value: the entity itself).
  ir::Quantity quantity() const { return quantity_; }

  // The variables the graph gives an element or a junction.
  Sym effort() const { return variable("e", ir::Quantity::e); }
  Sym flow() const { return variable("f", ir::Quantity::f); }
  Sym momentum() const { return variable("p", ir::Quantity::p); }      // an I's state
  Sym displacement() const { return variable("q", ir::Quantity::q); }  // a C's state
  /// End k (1 or 2) of a two-port (MTF, TF, GY), as a bond names it.
  Sym port(int k) const {
    Sym p = variable(fmt::format("p{}", k), ir::Quantity::value);
    p.port_ = k;
    return p;
  }
  /// The two-port end it is (port(k)), or 0.
  int end_port() const { return port_; }
  /// The effort and flow of a two-port's bond at end k (`m.e1`, `m.f1`).
  Sym effort(int k) const { return variable(fmt::format("e{}", k), k == 1 ? ir::Quantity::e1 : ir::Quantity::e2); }
  Sym flow(int k) const { return variable(fmt::format("f{}", k), k == 1 ? ir::Quantity::f1 : ir::Quantity::f2); }

  /// Inside an element's own law: its flow and its displacement.
  static Sym own_flow() { return special("f", Kind::Own, ir::Quantity::f); }
  static Sym own_displacement() { return special("q", Kind::Own, ir::Quantity::q); }
  /// The built-in constant.
  static Sym pi() { return special("pi", Kind::Pi, ir::Quantity::value); }
  /// The gravity vector (`gravity = [...]`, world frame).
  static Sym gravity() { return Sym("gravity", units::dim::velocity() / units::dim::time()); }
  /// A point the user declared on ground.
  static Sym ground_point(const std::string& point) { return Sym("ground." + point, units::dim::length()); }

 protected:
  /// An entity's own name, as its declaration gives it.
  explicit Sym(std::string name, std::optional<units::Dimension> dimension = std::nullopt)
      : name_(std::move(name)), dimension_(std::move(dimension)) {}
  /// A name the entity owns: `entity.what`, of that dimension where it is a parameter the layer knows.
  Sym part(const std::string& what, std::optional<units::Dimension> dimension = std::nullopt) const {
    return Sym(name_ + "." + what, std::move(dimension));
  }
  /// A parameter that holds setting `s`'s value: its name and its dimension.
  Sym part(const Setting& s) const { return part(s.name, s.dimension); }
  /// Variable `q` of this element or junction, shown as `entity.what`.
  Sym variable(const std::string& what, ir::Quantity q) const {
    Sym v = part(what);
    v.owner_ = name_;
    v.quantity_ = q;
    return v;
  }

 private:
  static Sym special(const std::string& name, Kind kind, ir::Quantity q) {
    Sym s(name);
    s.kind_ = kind;
    s.quantity_ = q;
    return s;
  }
  std::string name_;
  std::optional<units::Dimension> dimension_;
  Kind kind_ = Kind::Entity;
  std::string owner_;                         // a variable's element or junction
  int port_ = 0;                              // a two-port's end: 1 or 2
  ir::Quantity quantity_ = ir::Quantity::value;
};

/// The ids of the symbols the layer writes and reads, in the order first
/// named (ir::ExpandedProgram::symbols): a reference and the declaration it
/// reads share one.
class SymbolIds {
 public:
  int id(const std::string& name) {
    auto [it, fresh] = ids_.emplace(name, static_cast<int>(names_.size()));
    if (fresh) names_.push_back(name);
    return it->second;
  }
  std::vector<std::string> take() { return std::move(names_); }

 private:
  std::unordered_map<std::string, int> ids_;
  std::vector<std::string> names_;
};

/// What pushes on a body: a force element, a contact's friction, a tyre.
/// Its load on body `b` is one effort source on a flexible body's junction
/// (`on(b)`), a force and a torque on a rigid one's (`on(b, 'f')`, `on(b, 't')`).
class LoadSym : public Sym {
 public:
  explicit LoadSym(const Sym& source) : Sym(source) {}

 protected:
  explicit LoadSym(const std::string& source) : Sym(source) {}

 public:
  Sym on(const std::string& body) const { return part("on_" + body); }
  Sym on(const std::string& body, char part_) const { return part(fmt::format("on_{}_{}", body, part_)); }
};

/// A body's point (BodySym::point): a property, and the quantities users
/// read of it (`position`, `velocity`; a flexible body's also `deflection`,
/// `rotation_vector`).
class PointSym : public Sym {
 public:
  explicit PointSym(const Sym& point) : Sym(point) {}
  Sym quantity(const std::string& q) const { return part(q); }
};

/// A body: its properties, its bond-graph fragment, its pose.
class BodySym : public Sym {
 public:
  explicit BodySym(const std::string& body) : Sym(body) {}

  // properties
  Sym mass() const { return part(body_setting::mass); }
  Sym com() const { return part(body_setting::com); }
  Sym inertia() const { return part(body_setting::inertia); }
  PointSym point(const std::string& p) const { return PointSym(part(p, units::dim::length())); }
  // initial values (the orientation's a quaternion, of the setting quat0)
  Sym r0() const { return part(body_setting::r0); }
  Sym v0() const { return part(body_setting::v0); }
  Sym q0() const { return part("q0", body_setting::quat0.dimension); }
  Sym w0() const { return part(body_setting::w0); }
  // the fragment: junctions of the velocity and the angular velocity, their
  // inertias, the position and quaternion states, the weight, the Euler
  // junction structures, the quaternion's rate
  Sym v() const { return part("v"); }
  Sym w() const { return part("w"); }
  Sym m() const { return part("m"); }
  Sym J() const { return part("J"); }
  Sym r() const { return part("r"); }
  Sym q() const { return part("q"); }
  Sym weight() const { return part("weight"); }
  Sym ejs() const { return part("ejs"); }
  Sym ejs_v() const { return part("ejs_v"); }
  Sym qrate() const { return part("qrate"); }
  /// Moved by joint coordinates: its pose as signals of the tree joint
  /// (position r1..r3, quaternion q1..q4, rotation matrix R11..R33).
  Sym pose_r(int k) const { return part(fmt::format("pose.r{}", k)); }
  Sym pose_q(int k) const { return part(fmt::format("pose.q{}", k)); }
  Sym pose_R(int r, int c) const { return part(fmt::format("pose.R{}{}", r, c)); }
  /// Drawn for --animate: the pose of the drawing's origin.
  Sym drawing() const { return part("drawing"); }
  /// A quantity users read (`position`, `velocity`, ...: quantities()).
  Sym quantity(const std::string& q) const { return part(q); }

  /// The names of the parts above, which a point of the body cannot take
  /// (`arm.mass`, `arm.v` are the body's own). Keep it with the members.
  static const std::set<std::string>& parts() {
    static const std::set<std::string> all = {"mass", "com", "inertia", "r0",    "v0",  "q0",    "w0",   "v",      "w",
                                              "m",    "J",   "r",       "q",     "weight", "ejs", "ejs_v", "qrate"};
    return all;
  }
  /// The quantities users read of a body (quantities.cpp defines them).
  static const std::set<std::string>& quantities() {
    static const std::set<std::string> all = {"position", "velocity",         "momentum",       "quaternion",
                                              "rotation", "bryant",           "omega",          "omega_world",
                                              "angular_momentum", "kinetic_energy", "potential_energy"};
    return all;
  }
};

/// A flexible body: a body whose field adds modal coordinates eta (the
/// floating-frame fragment, flexible_body.cpp; what each kind adds of its
/// own: flexible_symbols.hpp).
class FlexibleSym : public BodySym {
 public:
  explicit FlexibleSym(const std::string& body) : BodySym(body) {}
  Sym eta() const { return part("eta"); }        // the C of the modal coordinates (its state: eta().displacement())
  Sym etadot() const { return part("etadot"); }  // the 1-junction of their rates
  Sym nu() const { return part("nu"); }          // the 1-junction of the body-frame velocities and the rates
  Sym M() const { return part("M"); }            // the I of the whole mass matrix
  // (ejs(), inherited: the R of M(eta)'s velocity terms on nu; weight(): gravity's Se on nu)
  /// With its own states: the MTFs selecting from nu the velocity (turned to
  /// world axes), the angular velocity and the modal rates.
  Sym sv() const { return part("sv"); }
  Sym sw() const { return part("sw"); }
  Sym se() const { return part("se"); }
  /// Moved by joint coordinates: their transposes assembling nu from the
  /// velocity, the angular velocity and the modal rates, on the 0-junction
  /// nusum; and the Sf of the free modal rates.
  Sym av() const { return part("av"); }
  Sym aw() const { return part("aw"); }
  Sym ae() const { return part("ae"); }
  Sym nusum() const { return part("nusum"); }
  Sym eta_rate() const { return part("eta_rate"); }
  Sym damp() const { return part("damp"); }  // the R of the modal damping on etadot
  /// The undeformed inertia about the frame origin, body axes (a parameter).
  Sym J0() const { return part("J0", body_setting::inertia.dimension); }
  /// Quantities users read besides a body's (BodySym::quantity): the modal
  /// coordinates and the elastic energy.
  Sym modes() const { return part("modes"); }
  Sym elastic_energy() const { return part("elastic_energy"); }

  /// A body's parts and quantities and those above: what a flexible body's
  /// point cannot be named (its kind adds its own: BeamSym, ModalSym).
  static const std::set<std::string>& parts() {
    static const std::set<std::string> all = [] {
      std::set<std::string> out = BodySym::parts();
      out.insert(BodySym::quantities().begin(), BodySym::quantities().end());
      out.insert({"eta", "etadot", "nu", "M", "sv", "sw", "se", "av", "aw", "ae", "nusum", "eta_rate", "damp", "J0",
                  "modes", "elastic_energy"});
      return out;
    }();
    return all;
  }
};

/// A force element (`force f (a, b) { ... }`): its settings as parameters,
/// its loads on the two bodies (LoadSym), the quantities users read.
class ForceSym : public LoadSym {
 public:
  explicit ForceSym(const std::string& force) : LoadSym(force) {}
  Sym stiffness() const { return part(force_setting::stiffness); }
  Sym damping() const { return part(force_setting::damping); }
  Sym length0() const { return part("length0", force_setting::length.dimension); }
  Sym quantity(const std::string& q) const { return part(q); }  // `length`, `force`, `torque`
};

}  // namespace mbgc::multibody::detail
