#include "error_weights.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mbgrt::detail {

ErrorWeights::ErrorWeights(const Model& model, double rtol, double atol) : rtol_(rtol) {
  const std::size_t n = model.size();
  atol_.resize(n);
  group_.resize(n);
  norm_.resize(n);
  peak_.assign(n, 0.0);
  floored_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double nominal = model.nominal(i);
    atol_[i] = atol * (std::isfinite(nominal) && nominal > 0.0 ? nominal : 1.0);
    const std::size_t g = model.unknown_group(i);
    group_[i] = g < i && group_[g] == g ? g : i;  // a group is named by its first member
  }
}

bool ErrorWeights::operator()(const double* y, double* w) const {
  const std::size_t n = atol_.size();
  for (std::size_t i = 0; i < n; ++i) norm_[i] = 0.0;
  for (std::size_t i = 0; i < n; ++i) norm_[group_[i]] += y[i] * y[i];
  for (std::size_t i = 0; i < n; ++i)
    if (group_[i] == i) {
      norm_[i] = std::sqrt(norm_[i]);
      if (norm_[i] > peak_[i]) peak_[i] = norm_[i];  // (a NaN is left out)
    }
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  for (std::size_t i = 0; i < n; ++i) {
    // a component is measured against its own size, but never against less
    // than a tenth of its vector's
    const double relative = scale_ * rtol_ * std::max(std::abs(y[i]), 0.1 * norm_[group_[i]]);
    const double absolute = scale_ * atol_[i];
    const double floor = floor_on_ ? kRoundingFloor * u * peak_[group_[i]] : 0.0;
    if (floor > absolute && floor > relative) floored_[i] = 1;
    const double tol = relative + std::max(absolute, floor);
    if (!(tol > 0.0)) return false;
    w[i] = 1.0 / tol;
  }
  return true;
}

std::vector<std::size_t> ErrorWeights::floored() const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < floored_.size(); ++i)
    if (floored_[i]) out.push_back(i);
  return out;
}

}  // namespace mbgrt::detail
