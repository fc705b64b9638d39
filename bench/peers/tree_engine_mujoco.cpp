// MuJoCo: a 3-D model of tree_spec.hpp as MJCF (nested bodies, each with its
// frame at its joint point; a ball joint, or two hinges at the same point for
// a universal joint: MuJoCo applies a body's joints in order, each about its
// axis turned by the ones before, as R(axis1, alpha) R(axis2, beta)); explicit
// inertials, no geometry, contacts off. The ball joints' initial quaternions
// are written into qpos after mj_resetData. Integrated by MuJoCo's own RK4
// (integrator="RK4", mj_step), which advances the quaternions on the
// rotation group with its own update (mj_integratePos).
#include <mujoco/mujoco.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "tree_engines.hpp"

namespace bench::tree {
namespace {

void write_vec(std::ostream& x, const Eigen::Vector3d& v) { x << v.x() << ' ' << v.y() << ' ' << v.z(); }

void write_body(std::ostream& x, const TreeSpec& t, const std::vector<std::vector<int>>& children, int i, int depth) {
  const BodySpec& b = t.bodies[i];
  const std::string pad(2 * depth + 4, ' ');
  x << pad << "<body name=\"b" << i << "\" pos=\"";
  write_vec(x, b.at);
  x << "\">\n";
  if (b.joint == JointType::ball) {
    x << pad << "  <joint name=\"j" << i << "\" type=\"ball\" pos=\"0 0 0\"/>\n";
  } else {
    x << pad << "  <joint name=\"j" << i << "a\" type=\"hinge\" pos=\"0 0 0\" axis=\"";
    write_vec(x, b.axis1);
    x << "\"/>\n" << pad << "  <joint name=\"j" << i << "b\" type=\"hinge\" pos=\"0 0 0\" axis=\"";
    write_vec(x, b.axis2);
    x << "\"/>\n";
  }
  x << pad << "  <inertial pos=\"";
  write_vec(x, b.com);
  x << "\" mass=\"" << b.mass << "\" diaginertia=\"";
  write_vec(x, b.inertia);
  x << "\"/>\n";
  for (int c : children[i]) write_body(x, t, children, c, depth + 1);
  x << pad << "</body>\n";
}

std::string tree_mjcf(const TreeSpec& t) {
  std::vector<std::vector<int>> children(t.bodies.size());
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco model=\"tree\">\n"
    << "  <option gravity=\"";
  write_vec(x, t.gravity);
  x << "\" integrator=\"RK4\" timestep=\"0.001\">\n"
    << "    <flag contact=\"disable\"/>\n  </option>\n  <worldbody>\n";
  for (std::size_t i = 0; i < t.bodies.size(); ++i)
    if (t.bodies[i].parent >= 0) children[t.bodies[i].parent].push_back(static_cast<int>(i));
  for (std::size_t i = 0; i < t.bodies.size(); ++i)
    if (t.bodies[i].parent < 0) write_body(x, t, children, static_cast<int>(i), 0);
  x << "  </worldbody>\n</mujoco>\n";
  return x.str();
}

struct Sim {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  std::vector<int> ball_qpos;           // per body: qpos address of its ball joint, or -1
  std::vector<Eigen::Quaterniond> rot0;  // per body
  std::vector<int> body_id;             // per body: MuJoCo's body id (MuJoCo numbers depth first)
  ~Sim() {
    if (data) mj_deleteData(data);
    if (model) mj_deleteModel(model);
  }
};

void ignore_warning(const char*) {}

}  // namespace

Engine mujoco_engine(const TreeSpec& spec) {
  mju_user_warning = ignore_warning;
  char path[] = "/tmp/mbgc_bench_tree_XXXXXX.xml";
  const int fd = mkstemps(path, 4);
  if (fd < 0) throw std::runtime_error("mujoco_engine: cannot create a temporary MJCF file");
  close(fd);
  std::ofstream(path) << tree_mjcf(spec);
  auto sim = std::make_shared<Sim>();
  char error[1000] = "";
  sim->model = mj_loadXML(path, nullptr, error, sizeof error);
  std::remove(path);
  if (!sim->model) throw std::runtime_error(std::string("MuJoCo could not load the ") + spec.name + ": " + error);
  sim->data = mj_makeData(sim->model);
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
    const std::string b = "b" + std::to_string(i), j = "j" + std::to_string(i);
    sim->body_id.push_back(mj_name2id(sim->model, mjOBJ_BODY, b.c_str()));
    const bool ball = spec.bodies[i].joint == JointType::ball;
    sim->ball_qpos.push_back(ball ? sim->model->jnt_qposadr[mj_name2id(sim->model, mjOBJ_JOINT, j.c_str())] : -1);
    sim->rot0.push_back(spec.bodies[i].rot0);
  }
  return {"MuJoCo " + std::to_string(mj_version() / 100) + "." + std::to_string(mj_version() / 10 % 10) + "." +
              std::to_string(mj_version() % 10),
          [sim](double h, long steps) {
            mjModel* m = sim->model;
            mjData* d = sim->data;
            m->opt.timestep = h;
            mj_resetData(m, d);
            for (std::size_t i = 0; i < sim->ball_qpos.size(); ++i) {
              if (sim->ball_qpos[i] < 0) continue;
              mjtNum* q = d->qpos + sim->ball_qpos[i];
              q[0] = sim->rot0[i].w(), q[1] = sim->rot0[i].x(), q[2] = sim->rot0[i].y(), q[3] = sim->rot0[i].z();
            }
            for (long s = 0; s < steps; ++s) mj_step(m, d);
            mj_kinematics(m, d);  // the positions of the final state (mj_step leaves those of the one before)
            std::vector<double> out;
            out.reserve(3 * sim->body_id.size());
            for (int id : sim->body_id) out.insert(out.end(), d->xipos + 3 * id, d->xipos + 3 * id + 3);
            return out;
          }};
}

}  // namespace bench::tree
