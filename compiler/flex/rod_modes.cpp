// flex/rod_modes.cpp — axial and torsion modes (see rod_modes.hpp).
#include "flex/rod_modes.hpp"

#include <cmath>
#include <numbers>

namespace mbgc::flex {

const char* rod_ends_name(RodEnds e) {
  switch (e) {
    case RodEnds::FixedFree: return "fixed_free";
    case RodEnds::FixedFixed: return "fixed_fixed";
    case RodEnds::FreeFree: return "free_free";
  }
  return "?";
}

bool rod_ends_from_name(const std::string& name, RodEnds* out) {
  for (RodEnds e : {RodEnds::FixedFree, RodEnds::FixedFixed, RodEnds::FreeFree})
    if (name == rod_ends_name(e)) {
      *out = e;
      return true;
    }
  return false;
}

RodModes::RodModes(RodEnds ends, double length_m, int count) : ends_(ends), length_(length_m), count_(count) {}

double RodModes::k_L(int i) const {
  const double k = i + 1;  // 1-based mode number
  return ends_ == RodEnds::FixedFree ? (2 * k - 1) * std::numbers::pi / 2 : k * std::numbers::pi;
}

double RodModes::shape(int i, double x, int derivative) const {
  const double k = k_L(i) / length_, a = std::sqrt(2.0);
  const double s = std::sin(k * x), c = std::cos(k * x);
  const bool sine = ends_ != RodEnds::FreeFree;
  switch (derivative) {
    case 0: return a * (sine ? s : c);
    case 1: return a * k * (sine ? c : -s);
    default: return -a * k * k * (sine ? s : c);
  }
}

RodIntegrals rod_integrals(const RodModes& m) {
  const int n = m.count();
  const double L = m.length();
  RodIntegrals r;
  r.mass.assign(static_cast<std::size_t>(n), std::vector<double>(static_cast<std::size_t>(n)));
  r.stiffness = r.mass;
  for (int i = 0; i < n; ++i) {
    r.mean.push_back(integrate(L, [&](double x) { return m.shape(i, x); }));
    r.moment.push_back(integrate(L, [&](double x) { return x * m.shape(i, x); }));
    for (int j = 0; j < n; ++j) {
      r.mass[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = integrate(L, [&](double x) { return m.shape(i, x) * m.shape(j, x); });
      r.stiffness[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          integrate(L, [&](double x) { return m.shape(i, x, 1) * m.shape(j, x, 1); });
    }
  }
  return r;
}

Matrix cross_mass(const RodModes& axial, const BeamModes& bending) {
  Matrix c(static_cast<std::size_t>(axial.count()), std::vector<double>(static_cast<std::size_t>(bending.count())));
  for (int i = 0; i < axial.count(); ++i)
    for (int j = 0; j < bending.count(); ++j)
      c[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          integrate(axial.length(), [&](double x) { return axial.shape(i, x) * bending.shape(j, x); });
  return c;
}

}  // namespace mbgc::flex
