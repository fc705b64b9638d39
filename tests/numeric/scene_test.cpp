// scene_test.cpp — scenes compile only what their outputs need
// (models/scene_parts.mbg: a pendulum, an unrelated DC motor, and a filter
// driven by the pendulum's angle).
//
// The proof that a removed part cannot change the requested outputs is made
// on the whole model: change the removed part's parameters there and the
// outputs stay bit for bit the same (rk4 at a fixed step, so no error control
// couples the parts). The negative control shows the comparison can fail: the
// filter, which the pendulum drives, does change when the pendulum does.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

double max_diff(const SimRun& a, const SimRun& b, const std::string& column) {
  return max_difference(a.csv, b.csv, column);
}

std::uintmax_t generated_size(const std::string& target) {
  return std::filesystem::file_size(std::string(GENERATED_DIR) + "/" + target + ".cpp");
}

}  // namespace

TEST(Scenes, ThePendulumSceneGivesTheWholeModelsAnglesBitForBit) {
  SimRun full = run(SCENE_FULL_SIM, "", "scene_full");
  SimRun scene = run(SCENE_PENDULUM_SIM, "", "scene_pendulum");
  ASSERT_EQ(full.status, 0) << full.log;
  ASSERT_EQ(scene.status, 0) << scene.log;
  ASSERT_EQ(scene.csv.header, (std::vector<std::string>{"t", "angle_rad [rad]", "rate [rad/s]"}));  // units the compiler found
  EXPECT_EQ(max_diff(full, scene, "angle_rad"), 0.0);
  EXPECT_EQ(max_diff(full, scene, "rate"), 0.0);
  EXPECT_GT(full.csv.max_deviation("angle_rad"), 1.0);  // it swings
}

TEST(Scenes, WhatThePendulumSceneRemovedCannotActOnItsOutputs) {
  SimRun base = run(SCENE_FULL_SIM, "", "scene_base");
  // the motor and the filter, both removed by the scene, changed beyond recognition
  SimRun changed = run(SCENE_FULL_SIM, "--set V=200 --set tau=0.01", "scene_changed_removed");
  ASSERT_EQ(base.status, 0) << base.log;
  ASSERT_EQ(changed.status, 0) << changed.log;
  EXPECT_GT(max_diff(base, changed, "omega_flywheel"), 1.0);
  EXPECT_GT(max_diff(base, changed, "filtered"), 0.01);
  EXPECT_EQ(max_diff(base, changed, "angle_rad"), 0.0);
  EXPECT_EQ(max_diff(base, changed, "rate"), 0.0);
  // negative control: the pendulum does act on the filter, so the filter scene keeps it
  SimRun longer = run(SCENE_FULL_SIM, "--set L=2", "scene_changed_kept");
  ASSERT_EQ(longer.status, 0) << longer.log;
  EXPECT_GT(max_diff(base, longer, "filtered"), 0.01);
  SimRun filter = run(SCENE_FILTER_SIM, "--set L=2", "scene_filter");
  ASSERT_EQ(filter.status, 0) << filter.log;
  EXPECT_EQ(max_diff(longer, filter, "filtered"), 0.0);
}

TEST(Scenes, AnAdaptiveSolverAgreesToItsTolerance) {
  // With error control the removed states no longer share the step sizes, so
  // the agreement is to the tolerance, not to the bit.
  const std::string cvode = "--solver cvode --rtol 1e-9 --atol 1e-11";
  SimRun full = run(SCENE_FULL_SIM, cvode, "scene_full_cvode");
  SimRun scene = run(SCENE_PENDULUM_SIM, cvode, "scene_pendulum_cvode");
  ASSERT_EQ(full.status, 0) << full.log;
  ASSERT_EQ(scene.status, 0) << scene.log;
  EXPECT_LT(max_diff(full, scene, "angle_rad"), 1e-6);
}

TEST(Scenes, TheMotorSceneFixesItsSupplyVoltage) {
  // scene motor { outputs = [omega_flywheel]; V = 24 } acts as mbgc --set V=24
  SimRun scene = run(SCENE_MOTOR_SIM, "", "scene_motor");
  SimRun full = run(SCENE_FULL_SIM, "--set V=24", "scene_full_24v");
  ASSERT_EQ(scene.status, 0) << scene.log;
  ASSERT_EQ(full.status, 0) << full.log;
  EXPECT_EQ(max_diff(full, scene, "omega_flywheel"), 0.0);
  EXPECT_GT(scene.csv.max_abs("omega_flywheel"), 10.0);
}

TEST(Scenes, TheGeneratedCodeShrinksWithWhatTheSceneRemoves) {
  const auto full = generated_size("scene_parts"), pendulum = generated_size("scene_parts_pendulum"),
             filter = generated_size("scene_parts_filter"), motor = generated_size("scene_parts_motor");
  std::printf("generated C++: whole model %ju B, pendulum %ju B, filter %ju B, motor %ju B\n", full, pendulum, filter,
              motor);
  // measured: 9.5 kB, 6.3 kB, 7.0 kB, 5.2 kB (the pendulum's geometry is
  // folded into its equations, so it no longer dominates)
  EXPECT_LT(pendulum, filter);  // the filter scene keeps the pendulum too
  EXPECT_LT(filter, full * 9 / 10);
  EXPECT_LT(motor, pendulum);
  // No body, no joint, none of their parameters: not a line of the motor's
  // simulator names them.
  std::ifstream in(std::string(GENERATED_DIR) + "/scene_parts_motor.cpp");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.find("bob"), std::string::npos);
  EXPECT_EQ(text.find("hinge"), std::string::npos);
  EXPECT_EQ(text.find("gravity"), std::string::npos);
}
