// multibody/deformation.hpp — what a flexible body's deformation field gives
// the floating-frame equations.
//
// A flexible body (thesis Ch. 4 and 6) is a floating frame with a rigid
// motion and a deformation u(x) = Phi(x) eta on it. The multibond-graph
// fragment is the same for every such body (flexible_body.cpp: the I field
// p = M(eta) nu on nu = [V; omega; eta'], its velocity terms, gravity, the
// selectors to position, orientation and the modal junction, stiffness and
// damping). What differs is the field: the built-in beam's assumed modes
// (beam.hpp: integrals computed by the compiler) or a reduced body's
// modal-data file (modal_body.hpp: inertia invariants read from the file).
// A kind says how many coordinates it has, where its points are and how they
// move with eta, which constants it writes, and M(eta) in terms of them.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/drawing.hpp"
#include "multibody/build.hpp"
#include "multibody/modal_algebra.hpp"
#include "multibody/settings.hpp"

namespace mbgc::multibody::detail {

/// The modal coordinates of a flexible body by group (bending along body y
/// and z, stretch, twist; a modal-data body has all of them in y), as expressions.
struct Eta { std::vector<E> y, z, axial, torsion; };

/// Per modal coordinate: the magnitude where the linear model stops holding, and why.
using Limits = std::vector<std::pair<double, std::string>>;

/// Where a field writes its compile-time constants.
struct FieldParams {
  const Build& B;
  const ir::AstBody& decl;                                 // the body's declaration (its settings)
  std::function<void(const Sym&, E)> param;               // writes `param NAME = value`
  ir::Diagnostics& diags;                                  // for notes on what the compiler left out
};

class Deformation {
 public:
  virtual ~Deformation() = default;
  /// The settings its body takes (settings.hpp), with their dimensions.
  virtual const std::vector<const Setting*>& settings() const = 0;
  /// The number of modal coordinates.
  virtual int count() const = 0;
  /// Undeformed body-frame position of each point.
  virtual std::map<std::string, std::array<double, 3>> points() const = 0;
  /// eta split into its groups, given eta_k.
  virtual Eta split(const std::function<E(int)>& eta) const = 0;
  /// Mass, J0, the inertia invariants, stiffness, damping and the points' shapes, as parameters.
  virtual void params(const FieldParams& p) const = 0;
  // What follows reads the parameters params() wrote for body n (through
  // its own symbols: flexible_symbols.hpp).
  /// s(eta) = int (r0 + u) dm about the frame origin, body axes.
  virtual E first_moment(const Build& B, const FlexibleSym& n, const Eta& eta) const = 0;
  /// d s / d eta (3 x count): the translational coupling M_V,eta.
  virtual Rows translation_coupling(const Build& B, const FlexibleSym& n, const Eta& eta) const = 0;
  /// The generalised mass matrix M(eta), (6 + count) x (6 + count).
  virtual Rows mass_matrix(const Build& B, const FlexibleSym& n, const Eta& eta) const = 0;
  /// A point's deflected body-frame position.
  virtual E point(const Build& B, const FlexibleSym& n, const std::string& pt, const Eta& eta) const = 0;
  /// The small rotation of the section at a point (body axes).
  virtual E slope(const Build& B, const FlexibleSym& n, const std::string& pt, const Eta& eta) const = 0;
  /// Does the frame's origin stay put and unturned whatever the modes do (a
  /// clamped root with the frame there)? A joint may then hold the body there.
  virtual bool origin_fixed() const = 0;
  /// Where each modal coordinate leaves the model's range (`body`: the
  /// declared name, for the messages).
  virtual Limits limits(const std::string& body) const = 0;
  /// The modal stiffness and damping matrices, count x count, from the parameters.
  virtual void stiffness_and_damping(const Build& B, const FlexibleSym& n, Rows& K, Rows& D) const = 0;
  /// How it is drawn (--animate): a surface in body axes from the frame
  /// origin with one displacement field per modal coordinate. `scale`: the
  /// model's size, for parts the field does not give.
  virtual ir::Drawing drawing(double scale) const = 0;
  /// The file a modal-data body's points come from (empty for other kinds).
  virtual std::string point_file() const { return {}; }

  /// The run stops where one mode alone tilts the body further.
  double slope_limit_rad = beam_setting::slope_limit.by_default.number();
};

}  // namespace mbgc::multibody::detail
