// A small simulator for the viewer's browser test: a red box and a blue
// sphere moving in closed form, drawn by --animate and written by --out, so
// that a picture of the run can be checked against the CSV. A hand-written
// mbgrt::Model (like tests/runtime's Carousel) until mbgc emits bodies.
//
// One state, the clock s = t. The box `crate` slides along a straight line
// through all three axes and turns about z; the sphere `ball` runs round a
// vertical circle (the x-z plane at y = 0.3). Outputs: both positions.
#include <mbgrt/features.hpp>
#include <mbgrt/model.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace {

class TwoBodies : public mbgrt::Model {
 public:
  const char* name() const override { return "two_bodies"; }
  const char* source_file() const override { return "tests/viewer/two_bodies.cpp"; }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "clock"; }
  std::vector<std::string> output_names() const override {
    return {"crate_x", "crate_y", "crate_z", "ball_x", "ball_y", "ball_z"};
  }
  std::vector<mbgrt::ParameterInfo> parameters() const override { return {}; }
  bool set_parameter(const std::string&, double) override { return false; }
  mbgrt::Settings default_settings() const override {
    mbgrt::Settings s;
    s.t_end_s = 2.0;
    s.interval_s = 0.1;
    s.solver = mbgrt::Solver::rk4;  // the clock's derivative is 1: exact
    return s;
  }
  void initial(double, double* y, double*) override { y[0] = 0; }
  void derivative(double, const double*, double* dy) override { dy[0] = 1; }
  void outputs(double, const double* y, const double*, double* out) override {
    crate(y[0], out);
    ball(y[0], out + 3);
  }

  std::size_t body_count() const override { return 2; }
  mbgrt::BodyVisual body_visual(std::size_t i) const override {
    mbgrt::BodyVisual v;
    if (i == 0) {
      v.name = "crate";
      v.shape = mbgrt::BodyVisual::Shape::box;
      v.size[0] = v.size[1] = v.size[2] = 0.2;
      v.colour[0] = 0.8, v.colour[1] = 0.05, v.colour[2] = 0.05;  // red
    } else {
      v.name = "ball";
      v.shape = mbgrt::BodyVisual::Shape::sphere;
      v.size[0] = 0.1;
      v.colour[0] = 0.05, v.colour[1] = 0.15, v.colour[2] = 0.8;  // blue
    }
    return v;
  }
  void body_poses(double, const double* y, const double*, double* out) override {
    const double s = y[0], c = std::cos(s), n = std::sin(s);
    crate(s, out);
    const double turn[9] = {c, -n, 0, n, c, 0, 0, 0, 1};  // about z by s
    std::copy(turn, turn + 9, out + 3);
    ball(s, out + 12);
    const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::copy(identity, identity + 9, out + 15);
  }

 private:
  static void crate(double s, double* r) {
    r[0] = -0.6 + 0.6 * s, r[1] = -0.3 + 0.3 * s, r[2] = 0.1 + 0.25 * s;
  }
  static void ball(double s, double* r) {
    const double a = std::numbers::pi / 2 * s;
    r[0] = 0.5 * std::cos(a), r[1] = 0.3, r[2] = 0.4 + 0.3 * std::sin(a);
  }
};

}  // namespace

int main(int argc, char** argv) {
  TwoBodies model;
  mbgrt::use_gltf_animation();
  return mbgrt::run_main(model, argc, argv);
}
