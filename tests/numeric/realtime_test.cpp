// realtime_test.cpp — a generated model class (mbgc_add_model) in a
// fixed-step loop, as a real-time application runs it: after construction and
// the initial state, no step may allocate from the heap (issue 17, point 5).
// Every operator new of the program is counted; the count must not move
// while the loop runs. Three models: a bond graph (the single-track
// vehicle), rigid bodies in joint coordinates (the 3-D double pendulum) and
// reduced FE bodies with rigid ones in joint coordinates (reduced_joints).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

#include "realtime_double_pendulum_3d.hpp"
#include "realtime_reduced_joints.hpp"
#include "realtime_single_track.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};
void* allocate(std::size_t n) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* allocate_aligned(std::size_t n, std::align_val_t a) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t align = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(align, (std::max<std::size_t>(n, 1) + align - 1) / align * align)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, std::align_val_t a) { return allocate_aligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return allocate_aligned(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace {

/// One classical Runge–Kutta step of h from (t, y), in buffers the caller owns.
struct Rk4Step {
  explicit Rk4Step(std::size_t n) : k1(n), k2(n), k3(n), k4(n), tmp(n) {}
  void operator()(mbgrt::Model& model, double& t, double h, std::vector<double>& y) {
    const std::size_t n = y.size();
    model.derivative(t, y.data(), k1.data());
    for (std::size_t i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
    model.derivative(t + 0.5 * h, tmp.data(), k2.data());
    for (std::size_t i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k2[i];
    model.derivative(t + 0.5 * h, tmp.data(), k3.data());
    for (std::size_t i = 0; i < n; ++i) tmp[i] = y[i] + h * k3[i];
    model.derivative(t + h, tmp.data(), k4.data());
    for (std::size_t i = 0; i < n; ++i) y[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    t += h;
  }
  std::vector<double> k1, k2, k3, k4, tmp;
};

/// `steps` classical Runge–Kutta steps of `h` with the outputs read after
/// each, every buffer allocated before the loop; returns the allocations the
/// loop made.
long fixed_step_allocations(mbgrt::Model& model, double h, int steps) {
  const std::size_t n = model.size();
  std::vector<double> y(n), yp(n), out(model.output_names().size());
  Rk4Step step(n);
  model.initial(0.0, y.data(), yp.data());
  double t = 0;
  allocations = 0;
  counting = true;
  for (int s = 0; s < steps; ++s) {
    step(model, t, h, y);
    model.outputs(t, y.data(), yp.data(), out.data());
  }
  counting = false;
  for (std::size_t i = 0; i < n; ++i) EXPECT_TRUE(std::isfinite(y[i])) << model.variable_name(i);
  return allocations.load();
}

TEST(RealTime, TheCountingAllocatorCountsAllocations) {
  // the check must be able to fail: a loop that allocates is seen
  allocations = 0;
  counting = true;
  std::vector<double>* v = new std::vector<double>(10);
  counting = false;
  delete v;
  EXPECT_EQ(allocations.load(), 2);  // the vector object and its buffer
}

TEST(RealTime, ABondGraphModelStepsWithoutAllocating) {
  single_track::single_track_model model;
  EXPECT_EQ(fixed_step_allocations(model, 1e-3, 2000), 0);
}

TEST(RealTime, RigidBodiesInJointCoordinatesStepWithoutAllocating) {
  double_pendulum_3d::double_pendulum_3d_model model;
  EXPECT_EQ(fixed_step_allocations(model, 1e-3, 2000), 0);
}

TEST(RealTime, ReducedFEBodiesInJointCoordinatesStepWithoutAllocating) {
  reduced_joints::reduced_joints_model model;
  EXPECT_EQ(fixed_step_allocations(model, 1e-4, 2000), 0);
}

}  // namespace

namespace {

/// The generated model's partial evaluations against its whole derivative,
/// at the start and after 500 RK4 steps of h: position_rates() gives the
/// position entries of derivative(), and derivative_and_power() the
/// derivative and power() both, to rounding (each method shares its
/// subexpressions its own way).
void expect_partial_evaluations_agree(mbgrt::Model& model, double h) {
  const std::size_t n = model.size();
  std::vector<double> y(n), yp(n), f(n), g(n);
  Rk4Step step(n);
  model.initial(0.0, y.data(), yp.data());
  double t = 0;
  for (int check = 0; check < 2; ++check) {
    model.derivative(t, y.data(), f.data());
    std::vector<double> rates(n, 7.0);  // (the velocities' entries must be left as they are)
    ASSERT_TRUE(model.has_position_rates());
    model.position_rates(t, y.data(), rates.data());
    for (std::size_t i = 0; i < n; ++i) {
      if (model.unknown_role(i) == mbgrt::UnknownRole::position)
        EXPECT_NEAR(rates[i], f[i], 1e-12 * std::max(1.0, std::abs(f[i]))) << model.variable_name(i) << " at t = " << t;
      else
        EXPECT_EQ(rates[i], 7.0) << model.variable_name(i);
    }
    if (model.has_energy_balance()) {
      double fused[2], separate[2];
      model.derivative_and_power(t, y.data(), g.data(), fused);
      model.power(t, y.data(), nullptr, separate);
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(g[i], f[i]) << model.variable_name(i);
      for (int j = 0; j < 2; ++j) EXPECT_NEAR(fused[j], separate[j], 1e-12 * std::max(1.0, std::abs(separate[j])));
    }
    for (int s = 0; s < 500; ++s) step(model, t, h, y);
  }
}

TEST(GeneratedModel, PositionRatesAndTheFusedPowersAgreeWithTheWholeDerivative) {
  single_track::single_track_model bond_graph;
  expect_partial_evaluations_agree(bond_graph, 1e-3);
  double_pendulum_3d::double_pendulum_3d_model rigid;
  expect_partial_evaluations_agree(rigid, 1e-3);
  reduced_joints::reduced_joints_model flexible;
  expect_partial_evaluations_agree(flexible, 1e-4);
}

}  // namespace
