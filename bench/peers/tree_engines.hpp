// tree_engines.hpp — the engines of tree_peers: each simulates one 3-D model
// of tree_spec.hpp (the binary tree or the spherical chain) for `steps` steps
// of h from its initial pose at rest and returns the rods' centres of mass,
// world axes, [x1, y1, z1, x2, ...] at t = steps h (steps = 0: the initial
// pose, which tree_peers compares between engines).
#pragma once
#include <memory>
#include <vector>

#include "engine.hpp"
#include "rk4.hpp"
#include "tree_spec.hpp"

namespace bench::tree {

Engine aba_engine(const TreeSpec& spec);      // tree_aba.hpp, by hand, under rk4.hpp
Engine mujoco_engine(const TreeSpec& spec);   // MuJoCo's own RK4 (ball joints; two hinges for a universal joint)
Engine simbody_engine(const TreeSpec& spec);  // Ball and Universal mobilizers, realize(Acceleration) under rk4.hpp
Engine dart_engine(const TreeSpec& spec);     // BallJoint and UniversalJoint, computeForwardDynamics() under rk4.hpp

// The model classes mbgc generates (--constraints coordinates) from
// binary_tree.mbg (N = 31) and spherical_chain.mbg (N = 32), one translation
// unit each; their outputs are the centres of mass, in the order above.
Engine mbgc_binary_tree_31();
Engine mbgc_spherical_chain_32();

template <class Model>
Engine engine_for_generated_tree() {
  auto model = std::make_shared<Model>();
  const std::size_t n_out = model->output_names().size();
  return {"mbgc", [model, n_out](double h, long steps) {
            std::vector<double> y(model->size());
            model->initial(0.0, y.data(), nullptr);
            rk4([&](double t, const double* x, double* xdot) { model->derivative(t, x, xdot); }, y, h, steps);
            std::vector<double> out(n_out);
            model->outputs(h * steps, y.data(), nullptr, out.data());
            return out;
          }};
}

}  // namespace bench::tree
