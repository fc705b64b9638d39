// engine.hpp — one way of simulating the planar chain: made for N rods, it
// runs 1 s from 0.3 rad at every joint (at rest) in `steps` RK4 steps of h
// and returns the joint angles q_1..q_N at t = 1 s. (tree_engines.hpp makes
// the same kind of Engine for the 3-D models; those return the rods'
// centres of mass.)
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace bench {

struct Engine {
  std::string name;
  std::function<std::vector<double>(double h_s, long steps)> run;
};

constexpr double kLength_m = 0.5, kMass_kg = 1.0, kRadius_m = 0.01, kGravity_m_per_s2 = 9.81, kStartAngle_rad = 0.3;

Engine recursive_engine(int n);  // chain_recursive.hpp, by hand
Engine mbgc_engine(int n);       // the model class mbgc generates from examples/chain/chain.mbg
Engine mujoco_engine(int n);     // MuJoCo's own RK4 (mj_step)
Engine simbody_engine(int n);    // Simbody's realize(Acceleration) under rk4.hpp
Engine dart_engine(int n);       // DART's computeForwardDynamics() under rk4.hpp

}  // namespace bench
