// multibody/beam.hpp — the built-in beam (`flexible = beam`): a uniform
// Euler-Bernoulli beam along the body's x axis with assumed modes of bending
// (deflections along body y and z), stretch and twist, whose inertia
// invariants the compiler integrates (compiler/flex).
#pragma once

#include <map>
#include <optional>
#include <string>

#include "flex/beam_modes.hpp"
#include "flex/rod_modes.hpp"
#include "multibody/deformation.hpp"
#include "multibody/flexible_symbols.hpp"

namespace mbgc::multibody::detail {

/// A floating frame at the beam's start (x = 0, the body frame origin; x
/// along the beam), or at its centre or mean axes (`frame = ...`), and
/// assumed modes. Lengths and point positions are compile-time numbers (the
/// compiler integrates the modes); material and section may be parameters.
class Beam final : public Deformation {
 public:
  const std::vector<const Setting*>& settings() const override { return beam_setting::kAll; }
  int count() const override { return offset_torsion() + (torsion ? torsion->count() : 0); }
  std::map<std::string, std::array<double, 3>> points() const override;
  Eta split(const std::function<E(int)>& eta) const override;
  void params(const FieldParams& p) const override;
  E first_moment(const Build& B, const FlexibleSym& n, const Eta& eta) const override;
  Rows translation_coupling(const Build& B, const FlexibleSym& n, const Eta& eta) const override;
  Rows mass_matrix(const Build& B, const FlexibleSym& n, const Eta& eta) const override;
  E point(const Build& B, const FlexibleSym& n, const std::string& pt, const Eta& eta) const override;
  E slope(const Build& B, const FlexibleSym& n, const std::string& pt, const Eta& eta) const override;
  bool origin_fixed() const override;
  Limits limits(const std::string& body) const override;
  void stiffness_and_damping(const Build& B, const FlexibleSym& n, Rows& K, Rows& D) const override;
  ir::Drawing drawing(double scale) const override;

  // eta = [eta_y; eta_z; eta_axial; eta_torsion]
  int offset_z() const { return y ? y->count() : 0; }
  int offset_axial() const { return offset_z() + (z ? z->count() : 0); }
  int offset_torsion() const { return offset_axial() + (axial ? axial->count() : 0); }

  double length_m = 0;
  std::optional<flex::BeamModes> y, z;   // mode sets per bending plane
  std::optional<flex::RodModes> axial;   // stretch along x (modes_axial)
  std::optional<flex::RodModes> torsion; // twist about x (modes_torsion)
  bool geometric_stiffness = false;     // on: as given, or its default in the settings table
  bool mean_axes = false;                // frame = buckens or tisserand: the couplings int phi dm, int x phi dm are left out
  bool tisserand = false;                // frame = tisserand: origin at the mass centre, the foreshortening moves no mass
  double origin_m = 0;                   // where along the beam the frame's origin is (frame = centre: L / 2)
  std::map<std::string, double> point_x; // point name -> x along the beam

 private:
  void add_stretch_and_twist(const Build& B, const BeamSym& n, const Eta& eta, Rows& M) const;
  void rod_params(const FieldParams& p) const;
  void add_bending_limits(const std::string& body, Limits& limits) const;
  static constexpr double kStrainLimit = 0.01;
};

}  // namespace mbgc::multibody::detail
