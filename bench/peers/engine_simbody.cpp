// Simbody: the chain as Pin mobilizers (each about the common z axis), the
// same RK4 loop as the hand-written model around realize(Stage::Acceleration)
// (Simbody's O(N) articulated-body algorithm).
#include <Simbody.h>

#include <memory>
#include <string>

#include "engine.hpp"
#include "rk4.hpp"

namespace bench {
namespace {

struct Sim {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity{forces, matter, -SimTK::YAxis, kGravity_m_per_s2};
  SimTK::State state;
};

}  // namespace

Engine simbody_engine(int n) {
  using namespace SimTK;
  auto sim = std::make_shared<Sim>();
  const Vec3 centre(0, -kLength_m / 2, 0);
  const Inertia about_centre(kMass_kg * kLength_m * kLength_m / 12, kMass_kg * kRadius_m * kRadius_m / 2,
                             kMass_kg * kLength_m * kLength_m / 12);
  Body::Rigid rod(MassProperties(kMass_kg, centre, about_centre.shiftFromMassCenter(centre, kMass_kg)));
  MobilizedBody parent = sim->matter.Ground();
  for (int i = 1; i <= n; ++i)
    parent = MobilizedBody::Pin(parent, Transform(Vec3(0, i == 1 ? 0.0 : -kLength_m, 0)), rod, Transform());
  sim->state = sim->system.realizeTopology();
  int major = 0, minor = 0, build = 0;
  SimTK_version_simbody(&major, &minor, &build);
  return {"Simbody " + std::to_string(major) + "." + std::to_string(minor), [sim, n](double h, long steps) {
            State& s = sim->state;
            std::vector<double> y(2 * n, 0.0);
            for (int i = 0; i < n; ++i) y[i] = kStartAngle_rad;
            rk4(
                [&](double t, const double* x, double* xdot) {
                  s.setTime(t);
                  Vector& q = s.updQ();
                  Vector& u = s.updU();
                  for (int i = 0; i < n; ++i) q[i] = x[i], u[i] = x[n + i];
                  sim->system.realize(s, Stage::Acceleration);
                  const Vector& qdot = s.getQDot();
                  const Vector& udot = s.getUDot();
                  for (int i = 0; i < n; ++i) xdot[i] = qdot[i], xdot[n + i] = udot[i];
                },
                y, h, steps);
            return std::vector<double>(y.begin(), y.begin() + n);
          }};
}

}  // namespace bench
