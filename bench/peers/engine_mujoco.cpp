// MuJoCo: the chain as MJCF (nested bodies with hinge joints about z and
// explicit inertials, no geometry, contacts off), integrated by MuJoCo's own
// RK4 (option integrator="RK4", mj_step). MuJoCo's XML parser (TinyXML-2)
// refuses elements nested more than 100 deep, so a chain of more than 90
// rods is written as URDF instead (flat links and joints, read by the same
// mj_loadXML into the same kind of model: hinges about z at the same points,
// the same inertials), with gravity, the integrator and contacts set on the
// loaded model; at N = 32 the two give the same angles to rounding.
#include <mujoco/mujoco.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "engine.hpp"

namespace bench {
namespace {

std::string chain_mjcf(int n) {
  const double i_bend = kMass_kg * kLength_m * kLength_m / 12, i_spin = kMass_kg * kRadius_m * kRadius_m / 2;
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco model=\"chain\">\n"
    << "  <option gravity=\"0 " << -kGravity_m_per_s2 << " 0\" integrator=\"RK4\" timestep=\"0.001\">\n"
    << "    <flag contact=\"disable\"/>\n  </option>\n  <worldbody>\n";
  for (int i = 1; i <= n; ++i) {
    x << std::string(2 * i + 2, ' ') << "<body name=\"rod" << i << "\" pos=\"0 " << (i == 1 ? 0.0 : -kLength_m)
      << " 0\">\n"
      << std::string(2 * i + 4, ' ') << "<joint name=\"j" << i << "\" type=\"hinge\" axis=\"0 0 1\" pos=\"0 0 0\"/>\n"
      << std::string(2 * i + 4, ' ') << "<inertial pos=\"0 " << -kLength_m / 2 << " 0\" mass=\"" << kMass_kg
      << "\" diaginertia=\"" << i_bend << ' ' << i_spin << ' ' << i_bend << "\"/>\n";
  }
  for (int i = n; i >= 1; --i) x << std::string(2 * i + 2, ' ') << "</body>\n";
  x << "  </worldbody>\n</mujoco>\n";
  return x.str();
}

/// The same chain as URDF: link `world`, links rod1..rodN with their inertials,
/// continuous (unlimited hinge) joints about z.
std::string chain_urdf(int n) {
  const double i_bend = kMass_kg * kLength_m * kLength_m / 12, i_spin = kMass_kg * kRadius_m * kRadius_m / 2;
  std::ostringstream x;
  x.precision(17);
  x << "<robot name=\"chain\">\n"
    << "  <mujoco><compiler discardvisual=\"false\" fusestatic=\"false\"/></mujoco>\n"
    << "  <link name=\"world\"/>\n";
  for (int i = 1; i <= n; ++i) {
    x << "  <link name=\"rod" << i << "\">\n"
      << "    <inertial><origin xyz=\"0 " << -kLength_m / 2 << " 0\" rpy=\"0 0 0\"/><mass value=\"" << kMass_kg
      << "\"/><inertia ixx=\"" << i_bend << "\" iyy=\"" << i_spin << "\" izz=\"" << i_bend
      << "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>\n"
      << "  </link>\n"
      << "  <joint name=\"j" << i << "\" type=\"continuous\"><parent link=\""
      << (i == 1 ? std::string("world") : "rod" + std::to_string(i - 1))
      << "\"/><child link=\"rod" << i << "\"/><origin xyz=\"0 " << (i == 1 ? 0.0 : -kLength_m)
      << " 0\" rpy=\"0 0 0\"/><axis xyz=\"0 0 1\"/></joint>\n";
  }
  x << "</robot>\n";
  return x.str();
}

struct Sim {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  ~Sim() {
    if (data) mj_deleteData(data);
    if (model) mj_deleteModel(model);
  }
};

}  // namespace

/// MuJoCo warns (and writes MUJOCO_LOG.TXT into the working directory) when
/// a step too large for the chain blows up; the step search expects that.
void ignore_warning(const char*) {}

Engine mujoco_engine(int n) {
  mju_user_warning = ignore_warning;
  char path[] = "/tmp/mbgc_bench_chain_XXXXXX.xml";
  const int fd = mkstemps(path, 4);
  if (fd < 0) throw std::runtime_error("mujoco_engine: cannot create a temporary MJCF file");
  close(fd);
  const bool urdf = n > 90;  // (MJCF nests a body per rod: at most 100 elements deep)
  std::ofstream(path) << (urdf ? chain_urdf(n) : chain_mjcf(n));
  auto sim = std::make_shared<Sim>();
  char error[1000] = "";
  sim->model = mj_loadXML(path, nullptr, error, sizeof error);
  std::remove(path);
  if (!sim->model) throw std::runtime_error(std::string("MuJoCo could not load the chain: ") + error);
  if (urdf) {
    sim->model->opt.gravity[0] = 0, sim->model->opt.gravity[1] = -kGravity_m_per_s2, sim->model->opt.gravity[2] = 0;
    sim->model->opt.integrator = mjINT_RK4;
    sim->model->opt.disableflags |= mjDSBL_CONTACT;
  }
  sim->data = mj_makeData(sim->model);
  return {"MuJoCo " + std::to_string(mj_version() / 100) + "." + std::to_string(mj_version() / 10 % 10) + "." +
              std::to_string(mj_version() % 10),
          [sim, n](double h, long steps) {
            sim->model->opt.timestep = h;
            mj_resetData(sim->model, sim->data);
            for (int i = 0; i < n; ++i) sim->data->qpos[i] = kStartAngle_rad;
            for (long s = 0; s < steps; ++s) mj_step(sim->model, sim->data);
            return std::vector<double>(sim->data->qpos, sim->data->qpos + n);
          }};
}

}  // namespace bench
