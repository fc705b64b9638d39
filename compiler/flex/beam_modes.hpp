// flex/beam_modes.hpp — assumed modes of a uniform Euler–Bernoulli beam and
// the modal integrals a flexible body's equations need (thesis Ch. 3–4).
//
// A beam of length L along its body x axis bends in one plane with the
// transverse deflection w(x, t) = sum_i phi_i(x) eta_i(t). The shapes are the
// free-vibration modes of the beam with the chosen supports, normalised so that
// (1/L) * integral_0^L phi_i^2 dx = 1 (the classical form: a cantilever's tip
// moves by 2 in mode 1). The integrals are computed once, by the compiler, with
// composite Gauss–Legendre quadrature to near machine precision, and appear in
// the generated code as constants.
//
// Used by the flexible-body expansion (issue 4); this header has no
// dependency on the rest of the compiler.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace mbgc::flex {

/// Supports of the beam at x = 0 and x = L (the mode set).
enum class Supports { ClampedFree, PinnedPinned, ClampedPinned, FreeFree };

/// "clamped_free", ... (the names the language uses); from_name is false for an unknown name.
const char* supports_name(Supports s);
bool supports_from_name(const std::string& name, Supports* out);

/// The first n elastic modes of a uniform beam of length L (free–free: the
/// two rigid-body modes are excluded, the floating frame carries them).
class BeamModes {
 public:
  BeamModes(Supports supports, double length_m, int count);

  int count() const { return static_cast<int>(beta_L_.size()); }
  double length() const { return length_; }
  Supports supports() const { return supports_; }
  /// beta_i * L, the root of the characteristic equation (omega_i = beta_i^2 sqrt(EI / rho A)).
  double beta_L(int i) const { return beta_L_[static_cast<std::size_t>(i)]; }
  double beta(int i) const { return beta_L(i) / length_; }

  /// phi_i and its x-derivatives (order 0..3) at x in [0, L].
  double shape(int i, double x, int derivative = 0) const;

  /// The same modes measured from the section at x = c: each mode's rigid
  /// motion there is subtracted, phi(x) - phi(c) - phi'(c) (x - c), so that
  /// a frame fixed to that section sees only deformation (frame = centre
  /// with free-free modes). The space spanned with the rigid motions is the same.
  BeamModes anchored_at(double c) const;
  /// The section the modes are measured from (0 for the plain modes, which
  /// every set but free_free already holds in place there).
  double anchor() const { return anchored_ ? anchor_ : 0.0; }

  /// The same (free-free) modes in Tisserand's frame (thesis §5.2.4): the
  /// origin at the mass centre c = L/2, and the foreshortening of bending
  /// measured so that it moves no mass along the beam, a_T(x) = a_c(x) - abar
  /// with abar = (1/L) int a_c dx. The relative linear momentum then vanishes
  /// to the order the model keeps (int u' dm = 0, eq. 5.30), so the load
  /// integral is zero; moment and spin are taken about the centre.
  BeamModes in_tisserand_frame() const;
  /// The section the integrals (moment, spin, load) and the foreshortening are measured from.
  double origin() const { return origin_; }
  /// true in Tisserand's frame: the foreshortening's mean over the mass is subtracted.
  bool mean_free_shortening() const { return mean_free_shortening_; }

 private:
  double plain_shape(int i, double x, int derivative) const;
  bool anchored_ = false;
  double anchor_ = 0;
  double origin_ = 0;
  bool mean_free_shortening_ = false;
  Supports supports_;
  double length_;
  std::vector<double> beta_L_;
  std::vector<double> sigma_;         // the shape's sinh/sin weight
  std::vector<double> one_minus_sigma_;  // 1 - sigma, computed without cancellation
};

/// integral_0^L f(x) dx by composite Gauss–Legendre quadrature (20 nodes per
/// panel, `panels` panels): exact for polynomials of degree 39 per panel, and
/// to near machine precision for the smooth mode shapes of the first dozen modes.
double integrate(double length_m, const std::function<double(double)>& f, int panels = 16);

/// Integrals over the beam of products of the shapes and their derivatives,
/// per unit mass or stiffness (multiply by rho A, EI, or the axial load):
///   mean_i      = int phi_i dx                      (translation coupling, S)
///   moment_i    = int x phi_i dx                    (rotation coupling)
///   mass_ij     = int phi_i phi_j dx                (= L delta_ij)
///   bending_ij  = int phi_i'' phi_j'' dx            (= beta_i^4 L delta_ij)
///   axial_ij    = int phi_i' phi_j' dx              (geometric stiffness per unit axial force)
///   spin_ij     = int (L^2 - x^2) / 2 phi_i' phi_j' dx
///                 (geometric stiffness of the centrifugal axial force per unit rho A Omega^2,
///                  for a beam spinning about an axis through x = 0, thesis eq. 3.50)
///   load_ij     = int (L - x) phi_i' phi_j' dx
///                 (per unit rho A of an axial acceleration of the frame: thesis eq. 3.30's R_x term)
/// The last three are also integrals of the foreshortening a(x) = int_0^x phi' phi'^T:
/// axial = a(L), load = int a dx, spin = int x a dx.
using Matrix = std::vector<std::vector<double>>;
struct ModalIntegrals {
  std::vector<double> mean, moment;
  Matrix mass, bending, axial, spin, load;
};
/// With the frame's origin at x = c = modes.origin() (0 but for anchored
/// modes and Tisserand's frame) the body coordinate is s = x - c, and moment,
/// spin and load are taken about it: moment = int s phi, load = int a_c,
/// spin = int s a_c with a_c(x) = int_c^x phi' phi'^T (signed: a point on
/// either side moves towards c). In Tisserand's frame a_c - abar replaces
/// a_c: load is zero, and spin loses abar int s dx (zero about the centre).
ModalIntegrals modal_integrals(const BeamModes& modes);

/// a_c(x) = int_c^x phi_i' phi_j' dx (c = modes.origin()), minus its mean in
/// Tisserand's frame: the foreshortening of the point x per unit eta_i eta_j
/// (the axial shortening is -1/2 eta^T a_c(x) eta).
Matrix axial_up_to(const BeamModes& modes, double x);

/// int_0^L phi_i phi_j dx between two mode sets of the same length (the
/// two bending planes of one beam).
Matrix cross_mass(const BeamModes& a, const BeamModes& b);

}  // namespace mbgc::flex
