// multibody/contact_symbols.hpp — the names contacts and tyres write
// (contacts.cpp, tyres.cpp), what is drawn of them (drawing.cpp), and the
// quantities users read of them.
// In the style of symbols.hpp: each name built once, by its entity.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "multibody/setting_names.hpp"
#include "multibody/symbols.hpp"

namespace mbgc::multibody::detail {

/// A CN: besides its effort, the flags its unilateral law gives it
/// (graph/build_graph: LawForm::Unilateral).
class ConstraintSym : public Sym {
 public:
  explicit ConstraintSym(const Sym& cn) : Sym(cn) {}
  Sym closed() const { return variable("closed", ir::Quantity::closed); }  // 1 while the contact is closed
  Sym stick() const { return variable("stick", ir::Quantity::stick); }    // 1 while its friction sticks
};

/// A 3-vector written as three signals `v_1`, `v_2`, `v_3` (a signal is a
/// scalar); `v` itself names the quantity their list is.
class VectorSym : public Sym {
 public:
  explicit VectorSym(const Sym& vector) : Sym(vector) {}
  Sym component(int i) const { return VectorSym(fmt::format("{}_{}", str(), i)); }

 private:
  explicit VectorSym(std::string name) : Sym(std::move(name)) {}
};

/// A contact (`contact c (a.p, b.q) { ... }`): its settings as parameters,
/// the surface's directions in body b's frame, its row(s) written like a
/// joint's (the 0-junction of their rates, the MTFs from each body, the CN),
/// its friction's loads (a compliant contact's), the quantities users read.
class ContactSym : public Sym {
 public:
  explicit ContactSym(const std::string& contact) : Sym(contact) {}
  // settings
  Sym radius() const { return part(contact_setting::radius); }
  Sym restitution() const { return part(contact_setting::restitution); }
  Sym stiffness() const { return part("stiffness"); }
  Sym exponent() const { return part(contact_setting::exponent); }
  Sym stabilisation() const { return part(contact_setting::stabilisation); }
  Sym friction() const { return part(contact_setting::friction); }  // the coefficient mu
  Sym slip_speed() const { return part(contact_setting::slip_speed); }
  Sym surface_radius() const { return part(contact_setting::surface_radius); }
  // the surface's unit directions in body b's frame: a plane's normal, a
  // cylinder's axis, a plane's first tangent (for friction rows)
  Sym normal_b() const { return part("normal_b", units::Dimension::none()); }
  Sym axis_b() const { return part("axis_b", units::Dimension::none()); }
  Sym tangent_b() const { return part("tangent_b", units::Dimension::none()); }
  // the row, as a joint's (JointSym): the 0-junction of its rate, the MTF
  // carrying side `side`'s ('a', 'b') body flow `flow` ('t' velocity, 'r'
  // angular velocity, 'e' modal rates) into it (rates_into), the CN
  Sym rows() const { return part("c"); }
  Sym row_rate(char side, char flow) const { return part(fmt::format("c{}{}", side, flow)); }
  ConstraintSym constraint() const { return ConstraintSym(part("cn")); }
  /// A compliant contact's regularised friction, a load on both bodies (its
  /// name is the coefficient's: `c.friction.on_<body>_f`).
  LoadSym friction_load() const { return LoadSym(part("friction")); }
  /// Drawn for --animate: the pose of the surface.
  Sym drawing() const { return part("drawing"); }
  // the quantities users read
  Sym gap() const { return part("gap"); }
  Sym normal() const { return part("normal"); }
  Sym normal_force() const { return part("normal_force"); }
  Sym tangents() const { return part("tangents"); }  // a unilateral contact with friction: [t1, t2]
  Sym slip_velocity() const { return part("slip_velocity"); }
  Sym friction_force() const { return part("friction_force"); }
  Sym force() const { return part("force"); }
  Sym closed() const { return part("closed"); }
  Sym stuck() const { return part("stuck"); }
};

/// A tyre (`tyre t (wheel.centre, ground) { ... }`): a load on its wheel; its
/// settings as properties, the signals of the Magic Formula, its lagged
/// slips, the quantities users read.
class TyreSym : public LoadSym {
 public:
  explicit TyreSym(const std::string& tyre) : LoadSym(tyre) {}
  /// A setting as a .tir file names it (`FNOMIN`, `PCX1`, ...).
  Sym setting(const std::string& key) const { return part(key, tyre_setting_dimension(key)); }
  /// A scalar signal of the tyre's equations (`Fz`, `Vsx`, `slip_angle`, ...).
  Sym signal(const std::string& what) const { return part(what); }
  /// A lagged slip (`kappa`, `tan_alpha`): the C whose state it is, the Sf of
  /// its rate, the 1-junction joining them.
  Sym lag(const std::string& slip) const { return part(slip); }
  Sym lag_rate(const std::string& slip) const { return part(slip + "_rate"); }
  Sym lag_junction(const std::string& slip) const { return part(slip + "_lag"); }
  // vectors (signals by component, and quantities): the road's normal, the
  // tyre's forward and left directions, the road's force on the wheel
  VectorSym normal() const { return VectorSym(part("normal")); }
  VectorSym forward() const { return VectorSym(part("forward")); }
  VectorSym left() const { return VectorSym(part("left")); }
  VectorSym force() const { return VectorSym(part("force")); }
  // the quantities users read besides its signals
  Sym slip_ratio() const { return part("slip_ratio"); }
  Sym contact_point() const { return part("contact_point"); }
  Sym power() const { return part("power"); }
};

/// A road the tyres run on, as drawn for --animate: one per distinct profile,
/// `road`, `road_2`, ... (k from 1).
class RoadSym : public Sym {
 public:
  explicit RoadSym(std::size_t k) : Sym(k == 1 ? std::string("road") : fmt::format("road_{}", k)) {}
  Sym drawing() const { return part("drawing"); }
};

}  // namespace mbgc::multibody::detail
