#include "flex/beam_modes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace mbgc::flex {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct SupportsInfo {
  Supports supports;
  const char* name;
};
constexpr SupportsInfo kSupports[] = {{Supports::ClampedFree, "clamped_free"},
                                      {Supports::PinnedPinned, "pinned_pinned"},
                                      {Supports::ClampedPinned, "clamped_pinned"},
                                      {Supports::FreeFree, "free_free"}};

/// The characteristic equation, divided by cosh(B) so it stays O(1), and the
/// centre of the bracket holding its i-th root (1-based).
double characteristic(Supports s, double B) {
  switch (s) {
    case Supports::ClampedFree: return std::cos(B) + 1 / std::cosh(B);           // cos B cosh B = -1
    case Supports::ClampedPinned: return std::cos(B) * std::tanh(B) - std::sin(B);  // tan B = tanh B
    case Supports::FreeFree: return std::cos(B) - 1 / std::cosh(B);              // cos B cosh B = 1
    case Supports::PinnedPinned: return std::sin(B);
  }
  return 0;
}
double root_guess(Supports s, int i) {
  switch (s) {
    case Supports::ClampedFree: return (2 * i - 1) * kPi / 2;
    case Supports::ClampedPinned: return (4 * i + 1) * kPi / 4;
    case Supports::FreeFree: return (2 * i + 1) * kPi / 2;
    case Supports::PinnedPinned: return i * kPi;
  }
  return 0;
}

/// Bisection to the last bit: the roots are simple and isolated within +-0.6.
double root(Supports s, int i) {
  if (s == Supports::PinnedPinned) return i * kPi;
  double a = root_guess(s, i) - 0.6, b = root_guess(s, i) + 0.6;
  double fa = characteristic(s, a);
  if (fa * characteristic(s, b) > 0) throw std::logic_error("beam_modes: root not bracketed");
  for (int k = 0; k < 200 && b - a > 0; ++k) {
    double m = 0.5 * (a + b);
    if (m <= a || m >= b) break;
    double fm = characteristic(s, m);
    if ((fm < 0) == (fa < 0)) a = m, fa = fm;
    else b = m;
  }
  return 0.5 * (a + b);
}

/// Gauss–Legendre nodes and weights on [-1, 1], n = 20, by Newton on P_n.
struct GaussLegendre {
  static constexpr int n = 20;
  std::array<double, n> x{}, w{};
  GaussLegendre() {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= n; ++k) {
          double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[static_cast<std::size_t>(i)] = z;
      w[static_cast<std::size_t>(i)] = 2 / ((1 - z * z) * dp * dp);
    }
  }
};

}  // namespace

const char* supports_name(Supports s) {
  for (const auto& info : kSupports)
    if (info.supports == s) return info.name;
  return "?";
}

bool supports_from_name(const std::string& name, Supports* out) {
  for (const auto& info : kSupports)
    if (name == info.name) {
      *out = info.supports;
      return true;
    }
  return false;
}

BeamModes::BeamModes(Supports supports, double length_m, int count) : supports_(supports), length_(length_m) {
  for (int i = 1; i <= count; ++i) {
    const double B = root(supports, i);
    beta_L_.push_back(B);
    // sigma and 1 - sigma; the latter from its numerator written with e^-B,
    // since sigma -> 1 and the hyperbolic terms would cancel.
    const double eB = std::exp(-B), s = std::sin(B), c = std::cos(B);
    double sigma = 0, one_minus = 0;
    switch (supports) {
      case Supports::ClampedFree:  // sigma = (cosh B + cos B) / (sinh B + sin B)
        sigma = (std::cosh(B) + c) / (std::sinh(B) + s);
        one_minus = (-eB + s - c) / (std::sinh(B) + s);
        break;
      case Supports::ClampedPinned:
      case Supports::FreeFree:  // sigma = (cosh B - cos B) / (sinh B - sin B)
        sigma = (std::cosh(B) - c) / (std::sinh(B) - s);
        one_minus = (-eB - s + c) / (std::sinh(B) - s);
        break;
      case Supports::PinnedPinned: break;
    }
    sigma_.push_back(sigma);
    one_minus_sigma_.push_back(one_minus);
  }
}

BeamModes BeamModes::anchored_at(double c) const {
  BeamModes m = *this;
  m.anchored_ = true;
  m.anchor_ = c;
  m.origin_ = c;
  return m;
}

BeamModes BeamModes::in_tisserand_frame() const {
  BeamModes m = *this;
  m.origin_ = length_ / 2;
  m.mean_free_shortening_ = true;
  return m;
}

double BeamModes::shape(int i, double x, int derivative) const {
  const double raw = plain_shape(i, x, derivative);
  if (!anchored_) return raw;
  const double c = anchor_;
  if (derivative == 0) return raw - plain_shape(i, c, 0) - plain_shape(i, c, 1) * (x - c);
  if (derivative == 1) return raw - plain_shape(i, c, 1);
  return raw;
}

double BeamModes::plain_shape(int i, double x, int derivative) const {
  const std::size_t k = static_cast<std::size_t>(i);
  const double b = beta(i), bx = b * x, scale = std::pow(b, derivative);
  const double shift = derivative * kPi / 2;  // d^k/dx^k cos(bx) = b^k cos(bx + k pi/2)
  if (supports_ == Supports::PinnedPinned) return std::sqrt(2.0) * scale * std::sin(bx + shift);
  // cosh(bx) - sigma sinh(bx) = ((1 - sigma) e^{bx} + (1 + sigma) e^{-bx}) / 2, its k-th
  // derivative b^k ((1 - sigma) e^{bx} + (-1)^k (1 + sigma) e^{-bx}) / 2.
  const double sign = derivative % 2 == 0 ? 1.0 : -1.0;
  const double hyperbolic = 0.5 * (one_minus_sigma_[k] * std::exp(bx) + sign * (1 + sigma_[k]) * std::exp(-bx));
  const double sigma = sigma_[k], cs = std::cos(bx + shift), sn = std::sin(bx + shift);
  // clamped-free, clamped-pinned: cosh - cos - sigma (sinh - sin); free-free: cosh + cos - sigma (sinh + sin)
  const double trig = supports_ == Supports::FreeFree ? cs - sigma * sn : -cs + sigma * sn;
  return scale * (hyperbolic + trig);
}

double integrate(double length_m, const std::function<double(double)>& f, int panels) {
  static const GaussLegendre gl;
  const double h = length_m / panels;
  double sum = 0;
  for (int p = 0; p < panels; ++p) {
    const double mid = (p + 0.5) * h;
    double panel = 0;
    for (int k = 0; k < GaussLegendre::n; ++k)
      panel += gl.w[static_cast<std::size_t>(k)] * f(mid + 0.5 * h * gl.x[static_cast<std::size_t>(k)]);
    sum += 0.5 * h * panel;
  }
  return sum;
}

namespace {

Matrix square_integrals(const BeamModes& modes, const std::function<double(int, int, double)>& f) {
  const auto n = static_cast<std::size_t>(modes.count());
  Matrix out(n, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i; j < n; ++j)
      out[i][j] = out[j][i] = integrate(modes.length(), [&](double x) { return f(static_cast<int>(i), static_cast<int>(j), x); });
  return out;
}

/// int a_c dx, written as a single integral of phi' phi'^T with the weight
/// (by parts) L - x on the far side of c and -x on the near one.
Matrix shortening_integral(const BeamModes& modes) {
  const double c = modes.origin(), L = modes.length();
  return square_integrals(modes, [&](int i, int j, double x) {
    return (x >= c ? L - x : -x) * modes.shape(i, x, 1) * modes.shape(j, x, 1);
  });
}

/// abar = (1/L) int a_c dx, what Tisserand's frame subtracts from a_c.
Matrix shortening_mean(const BeamModes& modes) {
  Matrix m = shortening_integral(modes);
  for (auto& row : m)
    for (double& x : row) x /= modes.length();
  return m;
}

}  // namespace

ModalIntegrals modal_integrals(const BeamModes& modes) {
  const int n = modes.count();
  const double L = modes.length(), c = modes.origin();
  ModalIntegrals m;
  for (int i = 0; i < n; ++i) {
    m.mean.push_back(integrate(L, [&](double x) { return modes.shape(i, x); }));
    m.moment.push_back(integrate(L, [&](double x) { return (x - c) * modes.shape(i, x); }));
  }
  m.mass = square_integrals(modes, [&](int i, int j, double x) { return modes.shape(i, x) * modes.shape(j, x); });
  m.bending = square_integrals(modes, [&](int i, int j, double x) { return modes.shape(i, x, 2) * modes.shape(j, x, 2); });
  m.axial = square_integrals(modes, [&](int i, int j, double x) { return modes.shape(i, x, 1) * modes.shape(j, x, 1); });
  // int s a_c dx as a single integral (by parts); for c = 0 the weight is (L^2 - x^2) / 2.
  auto spin_weight = [&](double x) {
    return x >= c ? 0.5 * ((L - c) * (L - c) - (x - c) * (x - c)) : 0.5 * (c * c - (x - c) * (x - c));
  };
  m.spin = square_integrals(modes, [&](int i, int j, double x) { return spin_weight(x) * modes.shape(i, x, 1) * modes.shape(j, x, 1); });
  m.load = shortening_integral(modes);
  if (modes.mean_free_shortening()) {
    // a_c - abar: its integral vanishes by construction, and int s (a_c - abar) dx loses abar int s dx
    const double s_integral = L * L / 2 - c * L;
    const std::size_t k = static_cast<std::size_t>(n);
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = 0; j < k; ++j) {
        m.spin[i][j] -= m.load[i][j] / L * s_integral;
        m.load[i][j] = 0;
      }
  }
  return m;
}

Matrix axial_up_to(const BeamModes& modes, double x) {
  const auto n = static_cast<std::size_t>(modes.count());
  Matrix out(n, std::vector<double>(n, 0.0));
  if (modes.mean_free_shortening()) {
    out = shortening_mean(modes);
    for (auto& row : out)
      for (double& v : row) v = -v;
  }
  const double c = modes.origin();
  if (x == c) return out;
  const double lo = std::min(c, x), sign = x > c ? 1.0 : -1.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i; j < n; ++j) {
      const double a = sign * integrate(std::abs(x - c), [&](double s) {
        return modes.shape(static_cast<int>(i), lo + s, 1) * modes.shape(static_cast<int>(j), lo + s, 1);
      });
      out[i][j] += a;
      if (j != i) out[j][i] += a;
    }
  return out;
}

Matrix cross_mass(const BeamModes& a, const BeamModes& b) {
  Matrix out(static_cast<std::size_t>(a.count()), std::vector<double>(static_cast<std::size_t>(b.count())));
  for (int i = 0; i < a.count(); ++i)
    for (int j = 0; j < b.count(); ++j)
      out[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          integrate(a.length(), [&](double x) { return a.shape(i, x) * b.shape(j, x); });
  return out;
}

}  // namespace mbgc::flex
