// engine_mbgc.hpp — an Engine around a model class mbgc generated from
// examples/chain/chain.mbg with --constraints coordinates (joint angles and
// rates are the states; M(q) q'' = b is solved in the generated code).
#pragma once
#include <memory>

#include "engine.hpp"
#include "rk4.hpp"

namespace bench {

template <class Model>
Engine engine_for_generated(int n) {
  auto model = std::make_shared<Model>();
  return {"mbgc", [model, n](double h, long steps) {
            std::vector<double> y(model->size());
            model->initial(0.0, y.data(), nullptr);
            rk4([&](double t, const double* x, double* xdot) { model->derivative(t, x, xdot); }, y, h, steps);
            std::vector<double> q(n);
            model->outputs(h * steps, y.data(), nullptr, q.data());
            return q;
          }};
}

// One translation unit per N (engine_mbgc_<N>.cpp): chain_32's generated code is large.
Engine mbgc_engine_2();
Engine mbgc_engine_8();
Engine mbgc_engine_32();
Engine mbgc_engine_100();

}  // namespace bench
