#include <memory>

#include "tree_aba.hpp"
#include "tree_engines.hpp"

namespace bench::tree {

Engine aba_engine(const TreeSpec& spec) {
  auto aba = std::make_shared<TreeAba>(spec);
  return {"hand-written O(N)", [aba](double h, long steps) {
            std::vector<double> y = aba->initial_state();
            rk4([&](double, const double* x, double* xdot) { aba->derivative(x, xdot); }, y, h, steps);
            return aba->com_positions(y.data());
          }};
}

}  // namespace bench::tree
