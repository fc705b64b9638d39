// flex/rod_modes.hpp — assumed modes of axial stretch and of torsion of a
// uniform beam (a rod and a shaft obey the same second-order equation), and
// the integrals a beam's equations need of them.
//
// The deflection u(x, t) = sum_k chi_k(x) zeta_k(t) along the beam (axial:
// u is the displacement along x; torsion: u is the twist angle of the section
// about x). The shapes are the free-vibration modes of the rod with the chosen
// ends, normalised like the bending modes, (1/L) int chi_k^2 dx = 1:
//   fixed_free   sqrt(2) sin((2k - 1) pi x / (2L))
//   fixed_fixed  sqrt(2) sin(k pi x / L)
//   free_free    sqrt(2) cos(k pi x / L)   (the rigid mode k = 0 excluded: the frame carries it)
// with omega_k = (k_k L / L) sqrt(EA / rho A) (axial) or sqrt(GJ / rho Ip) (torsion).
#pragma once

#include <string>
#include <vector>

#include "flex/beam_modes.hpp"

namespace mbgc::flex {

enum class RodEnds { FixedFree, FixedFixed, FreeFree };

/// "fixed_free", ... (the names the language uses); from_name is false for an unknown name.
const char* rod_ends_name(RodEnds e);
bool rod_ends_from_name(const std::string& name, RodEnds* out);

class RodModes {
 public:
  RodModes(RodEnds ends, double length_m, int count);
  int count() const { return count_; }
  double length() const { return length_; }
  RodEnds ends() const { return ends_; }
  /// k_i L: the wavenumber of mode i times the length.
  double k_L(int i) const;
  /// chi_i and its x-derivatives (order 0..2) at x in [0, L].
  double shape(int i, double x, int derivative = 0) const;

 private:
  RodEnds ends_;
  double length_;
  int count_;
};

/// Integrals over the length, per unit mass (or rotary inertia) or stiffness:
///   mean_i = int chi_i dx, moment_i = int x chi_i dx,
///   mass_ij = int chi_i chi_j dx (= L delta_ij), stiffness_ij = int chi_i' chi_j' dx.
struct RodIntegrals {
  std::vector<double> mean, moment;
  Matrix mass, stiffness;
};
RodIntegrals rod_integrals(const RodModes& modes);

/// int_0^L chi_i phi_j dx: an axial mode against a bending mode of the same beam.
Matrix cross_mass(const RodModes& axial, const BeamModes& bending);

}  // namespace mbgc::flex
