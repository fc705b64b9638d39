// Simbody: a 3-D model of tree_spec.hpp as Ball mobilizers (quaternion q,
// angular-velocity u) and Universal mobilizers (about F's x, then the turned
// y: the mobilizer frames F on the parent and M on the child are the joint
// point with axes [axis1, axis2, axis1 x axis2], so the child turns by
// R(axis1, alpha) R(axis2, beta)); the same RK4 loop as the hand-written
// model around realize(Stage::Acceleration), over Simbody's own state
// [q; u] with its qdot (the quaternions are integrated as 4-vectors, as in
// the hand-written model and mbgc).
#include <Simbody.h>

#include <memory>
#include <string>

#include "tree_engines.hpp"

namespace bench::tree {
namespace {

struct Sim {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  std::vector<SimTK::MobilizedBody> bodies;
  std::vector<SimTK::Vec3> com;
  SimTK::State state, initial;
};

SimTK::Vec3 vec(const Eigen::Vector3d& v) { return SimTK::Vec3(v.x(), v.y(), v.z()); }

}  // namespace

Engine simbody_engine(const TreeSpec& spec) {
  using namespace SimTK;
  auto sim = std::make_shared<Sim>();
  Force::Gravity(sim->forces, sim->matter, UnitVec3(vec(spec.gravity)), spec.gravity.norm());  // the subsystem owns it
  for (const BodySpec& b : spec.bodies) {
    const Vec3 com = vec(b.com);
    const Inertia about_com(vec(b.inertia));
    Body::Rigid body(MassProperties(b.mass, com, about_com.shiftFromMassCenter(com, b.mass)));
    MobilizedBody& parent = b.parent < 0 ? sim->matter.updGround() : sim->bodies[b.parent];
    if (b.joint == JointType::ball) {
      MobilizedBody::Ball ball(parent, Transform(vec(b.at)), body, Transform());
      const Quaternion q(b.rot0.w(), b.rot0.x(), b.rot0.y(), b.rot0.z());
      ball.setDefaultRotation(Rotation(q));
      sim->bodies.push_back(ball);
    } else {
      const Eigen::Vector3d z = b.axis1.cross(b.axis2);
      Mat33 axes;
      for (int r = 0; r < 3; ++r) axes(r, 0) = b.axis1[r], axes(r, 1) = b.axis2[r], axes(r, 2) = z[r];
      const Rotation F(axes, true);  // columns: the frame's x, y, z in body axes (orthonormal)
      sim->bodies.push_back(MobilizedBody::Universal(parent, Transform(F, vec(b.at)), body, Transform(F, Vec3(0))));
    }
    sim->com.push_back(com);
  }
  sim->initial = sim->system.realizeTopology();
  sim->state = sim->initial;
  int major = 0, minor = 0, build = 0;
  SimTK_version_simbody(&major, &minor, &build);
  return {"Simbody " + std::to_string(major) + "." + std::to_string(minor), [sim](double h, long steps) {
            State& s = sim->state;
            s = sim->initial;
            const int nq = s.getNQ(), nu = s.getNU();
            std::vector<double> y(nq + nu);
            for (int i = 0; i < nq; ++i) y[i] = s.getQ()[i];
            for (int i = 0; i < nu; ++i) y[nq + i] = s.getU()[i];
            rk4(
                [&](double t, const double* x, double* xdot) {
                  s.setTime(t);
                  Vector& q = s.updQ();
                  Vector& u = s.updU();
                  for (int i = 0; i < nq; ++i) q[i] = x[i];
                  for (int i = 0; i < nu; ++i) u[i] = x[nq + i];
                  sim->system.realize(s, Stage::Acceleration);
                  const Vector& qdot = s.getQDot();
                  const Vector& udot = s.getUDot();
                  for (int i = 0; i < nq; ++i) xdot[i] = qdot[i];
                  for (int i = 0; i < nu; ++i) xdot[nq + i] = udot[i];
                },
                y, h, steps);
            Vector& q = s.updQ();
            for (int i = 0; i < nq; ++i) q[i] = y[i];
            sim->system.realize(s, Stage::Position);
            std::vector<double> out;
            for (std::size_t i = 0; i < sim->bodies.size(); ++i) {
              const Vec3 p = sim->bodies[i].findStationLocationInGround(s, sim->com[i]);
              out.insert(out.end(), {p[0], p[1], p[2]});
            }
            return out;
          }};
}

}  // namespace bench::tree
