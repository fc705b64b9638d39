#include <memory>

#include "chain_recursive.hpp"
#include "engine.hpp"
#include "rk4.hpp"

namespace bench {

Engine recursive_engine(int n) {
  auto chain = std::make_shared<ChainRecursive>(n, kLength_m, kMass_kg, kGravity_m_per_s2);
  return {"hand-written O(N)", [chain, n](double h, long steps) {
            std::vector<double> y(2 * n, 0.0);
            for (int i = 0; i < n; ++i) y[i] = kStartAngle_rad;
            rk4([&](double, const double* x, double* xdot) { chain->derivative(x, xdot); }, y, h, steps);
            return std::vector<double>(y.begin(), y.begin() + n);
          }};
}

}  // namespace bench
