// drawing_test.cpp — what a generated model says about its bodies for
// --animate (tests/golden/good/drawn_bodies.mbg in library form): the shapes
// its `shape` settings give and the defaults, and poses that agree with the
// quantities the model computes another way (a point's position output, a
// body's position output, the joint that holds the wheel to the link's tip).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drawing_drawn_bodies.hpp"

namespace {

using Shape = mbgrt::BodyVisual::Shape;

struct Pose {
  double p[3];
  double R[9];
};

class DrawnBodies : public ::testing::Test {
 protected:
  /// A consistent start moved away along every unknown (the poses are functions of y alone).
  void SetUp() override {
    n = m.size();
    y.assign(n, 0), yp.assign(n, 0);
    m.initial(0.0, y.data(), yp.data());
    for (std::size_t i = 0; i < n; ++i) y[i] += 0.05 * std::sin(1.0 + 3.0 * static_cast<double>(i));
    poses.assign(12 * m.body_count(), 0);
    m.body_poses(0.0, y.data(), yp.data(), poses.data());
    outputs.assign(m.output_names().size(), 0);
    m.outputs(0.0, y.data(), yp.data(), outputs.data());
  }
  Pose pose(std::size_t body) const {
    Pose q{};
    for (int k = 0; k < 3; ++k) q.p[k] = poses[12 * body + k];
    for (int k = 0; k < 9; ++k) q.R[k] = poses[12 * body + 3 + k];
    return q;
  }
  double output(const std::string& name) const {
    const auto names = m.output_names();
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return outputs[i];
    ADD_FAILURE() << "no output " << name;
    return NAN;
  }
  drawn_bodies::drawn_bodies_model m;
  std::size_t n = 0;
  std::vector<double> y, yp, poses, outputs;
};

TEST_F(DrawnBodies, EveryBodyIsDrawnWithItsShapeOrADefault) {
  ASSERT_EQ(m.body_count(), 5u);
  const auto link = m.body_visual(0), wheel = m.body_visual(1), ball = m.body_visual(2), tetra = m.body_visual(3),
             plain = m.body_visual(4);
  EXPECT_EQ(link.name, "link");
  EXPECT_EQ(link.shape, Shape::box);
  EXPECT_DOUBLE_EQ(link.size[0], 0.5);
  EXPECT_DOUBLE_EQ(link.size[1], 0.04);
  EXPECT_DOUBLE_EQ(link.size[2], 0.02);
  EXPECT_EQ(wheel.shape, Shape::cylinder);
  EXPECT_DOUBLE_EQ(wheel.size[0], 0.1);
  EXPECT_DOUBLE_EQ(wheel.size[1], 0.03);
  EXPECT_EQ(ball.shape, Shape::sphere);  // a particle
  EXPECT_GT(ball.size[0], 0);
  EXPECT_EQ(tetra.shape, Shape::mesh);
  EXPECT_EQ(tetra.vertices.size(), 12u);   // the OBJ file's 4 vertices
  EXPECT_EQ(tetra.triangles.size(), 12u);  // and 4 faces
  EXPECT_DOUBLE_EQ(tetra.vertices[9 + 2], 0.106);
  // no shape: the box around its points [-0.2, 0, 0] and [0.2, 0.05, 0] and its centre of mass
  EXPECT_EQ(plain.shape, Shape::box);
  EXPECT_DOUBLE_EQ(plain.size[0], 0.4);
  EXPECT_DOUBLE_EQ(plain.size[1], 0.05);
  EXPECT_DOUBLE_EQ(plain.size[2], 0.05 * 0.4);  // at least 5 % of the largest edge thick
  EXPECT_DOUBLE_EQ(plain.centre[1], 0.025);
  // distinct colours
  EXPECT_NE(link.colour[0], wheel.colour[0]);
}

TEST_F(DrawnBodies, RotationsAreRotations) {
  for (std::size_t b = 0; b < m.body_count(); ++b) {
    const Pose q = pose(b);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += q.R[3 * k + i] * q.R[3 * k + j];
        EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12) << "body " << b;
      }
    const double det = q.R[0] * (q.R[4] * q.R[8] - q.R[5] * q.R[7]) - q.R[1] * (q.R[3] * q.R[8] - q.R[5] * q.R[6]) +
                       q.R[2] * (q.R[3] * q.R[7] - q.R[4] * q.R[6]);
    EXPECT_NEAR(det, 1.0, 1e-12) << "body " << b;
  }
}

TEST_F(DrawnBodies, PosesAgreeWithTheModelsOwnQuantities) {
  // the link's pose is its centre of mass, [0.25, 0, 0] in its frame from the base; the tip is [0.5, 0, 0]
  const Pose link = pose(0);
  const double tip_x = link.p[0] + link.R[0] * 0.25;
  EXPECT_NEAR(tip_x, output("x"), 1e-12);
  EXPECT_NEAR(pose(2).p[2], output("ball_z"), 1e-12);
  // the wheel's centre of mass is its hub, held at the link's tip (joint coordinates: exactly)
  const Pose wheel = pose(1);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(wheel.p[k], link.p[k] + link.R[3 * k] * 0.25, 1e-12) << "axis " << k;
  // and it turns with the link about the link's z axis: the two z axes stay parallel
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(wheel.R[3 * k + 2], link.R[3 * k + 2], 1e-12);
}

}  // namespace
