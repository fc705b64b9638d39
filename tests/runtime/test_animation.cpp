// --animate: the bodies' motion as binary glTF, read back with tinygltf and
// checked against the poses the model gave (a hand-written model whose
// bodies move in closed form).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <random>
#include <set>

#include "animation.hpp"
#include "mbgrt/features.hpp"
#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

/// One state, the clock s = t (also the one output), run for 1 s with a row
/// every 0.25 s: the models below only pose their bodies by it.
class Clock : public TestModel {
 public:
  Clock() {
    settings.t_end_s = 1.0;
    settings.interval_s = 0.25;
  }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "clock"; }
  std::vector<std::string> output_names() const override { return {"s"}; }
  void initial(double, double* y, double*) override { y[0] = 0; }
  void derivative(double, const double*, double* dy) override { dy[0] = 1; }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }
};

/// Body `wheel` runs round the unit circle in the x-y plane and turns about z
/// by the angle it has run, s = t; body `strip` stays at [0, 0, 1], turned
/// 90 degrees about x, its two modes at q = (sin t, t). One state: the clock.
class Carousel : public Clock {
 public:
  const char* name() const override { return "carousel"; }
  std::size_t body_count() const override { return 2; }
  BodyVisual body_visual(std::size_t i) const override {
    BodyVisual v;
    if (i == 0) {
      v.name = "wheel";
      v.shape = BodyVisual::Shape::cylinder;
      v.size[0] = 0.3, v.size[1] = 0.1;
      return v;
    }
    v.name = "strip";
    v.shape = BodyVisual::Shape::mesh;
    v.vertices = {0, 0, 0, 1, 0, 0, 1, 0.1, 0};
    v.triangles = {0, 1, 2};
    v.mode_shapes = {{0, 0, 0, 0, 0, 0.1, 0, 0, 0.1}, {0, 0, 0, 0, 0, 0.2, 0, 0, 0.3}};
    return v;
  }
  void body_poses(double, const double* y, const double*, double* out) override {
    const double s = y[0], c = std::cos(s), n = std::sin(s);
    const double wheel[12] = {c, n, 0, c, -n, 0, n, c, 0, 0, 0, 1};
    const double strip[12] = {0, 0, 1, 1, 0, 0, 0, 0, -1, 0, 1, 0};  // Rx(90 degrees)
    std::copy(wheel, wheel + 12, out);
    std::copy(strip, strip + 12, out + 12);
    out[24] = std::sin(s), out[25] = s;
  }
};

std::vector<float> floats(const tinygltf::Model& m, int accessor) {
  const tinygltf::Accessor& a = m.accessors.at(static_cast<std::size_t>(accessor));
  const tinygltf::BufferView& v = m.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  const int components = a.type == TINYGLTF_TYPE_VEC3 ? 3 : a.type == TINYGLTF_TYPE_VEC4 ? 4 : 1;
  std::vector<float> out(a.count * static_cast<std::size_t>(components));
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  std::memcpy(out.data(), m.buffers.at(0).data.data() + v.byteOffset + a.byteOffset, out.size() * sizeof(float));
  return out;
}

TEST(Animation, KeyframesAreThePosesAtTheRows) {
  const std::string glb = temp_path("run") + ".glb";
  Carousel model;
  use_gltf_animation();
  RunResult r = run(model, {"--animate", glb, "--solver", "rk4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "2 bodies in 5 frames to " + glb));

  tinygltf::Model m;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&m, &error, &warning, glb)) << error;
  EXPECT_EQ(warning, "");
  ASSERT_EQ(m.nodes.size(), 3u);  // the z-up root, then the bodies
  EXPECT_EQ(m.nodes[1].name, "wheel");
  EXPECT_EQ(m.nodes[2].name, "strip");
  EXPECT_EQ(m.nodes[0].children, (std::vector<int>{1, 2}));
  ASSERT_EQ(m.nodes[0].rotation.size(), 4u);
  EXPECT_NEAR(m.nodes[0].rotation[0], -std::sqrt(0.5), 1e-15);  // -90 degrees about x
  EXPECT_EQ(m.meshes.at(static_cast<std::size_t>(m.nodes[2].mesh)).primitives.at(0).targets.size(), 2u);

  ASSERT_EQ(m.animations.size(), 1u);
  const tinygltf::Animation& a = m.animations[0];
  ASSERT_EQ(a.channels.size(), 5u);  // translation and rotation of both, the strip's weights
  for (const tinygltf::AnimationChannel& c : a.channels) {
    const tinygltf::AnimationSampler& sampler = a.samplers.at(static_cast<std::size_t>(c.sampler));
    const std::vector<float> times = floats(m, sampler.input), values = floats(m, sampler.output);
    ASSERT_EQ(times.size(), 5u);
    for (std::size_t k = 0; k < times.size(); ++k) {
      const double t = 0.25 * static_cast<double>(k);
      EXPECT_NEAR(times[k], t, 1e-7);
      if (c.target_node == 1 && c.target_path == "translation") {
        EXPECT_NEAR(values[3 * k], std::cos(t), 1e-6);
        EXPECT_NEAR(values[3 * k + 1], std::sin(t), 1e-6);
        EXPECT_NEAR(values[3 * k + 2], 0.0, 1e-7);
      } else if (c.target_node == 1 && c.target_path == "rotation") {  // about z by t: [0, 0, sin(t/2), cos(t/2)]
        EXPECT_NEAR(values[4 * k + 2], std::sin(t / 2), 1e-6);
        EXPECT_NEAR(values[4 * k + 3], std::cos(t / 2), 1e-6);
      } else if (c.target_node == 2 && c.target_path == "rotation") {  // about x by 90 degrees
        EXPECT_NEAR(values[4 * k], std::sqrt(0.5), 1e-6);
        EXPECT_NEAR(values[4 * k + 3], std::sqrt(0.5), 1e-6);
      } else if (c.target_node == 2 && c.target_path == "weights") {
        EXPECT_NEAR(values[2 * k], std::sin(t), 1e-6);
        EXPECT_NEAR(values[2 * k + 1], t, 1e-6);
      } else {
        EXPECT_EQ(c.target_node, 2);
        EXPECT_EQ(c.target_path, "translation");
        EXPECT_NEAR(values[3 * k + 2], 1.0, 1e-7);
      }
    }
  }
  std::filesystem::remove(glb);
}

/// Body `cart` (a 0.2 m cube) slides along x from 0 to 10 m over the run; body
/// `post` stands at x = 100, touching nothing. Surfaces: `floor`, a plane on
/// the ground under the cart; `pad`, a plane on the cart (its pose); `road`,
/// a profile with a 0.5 m step between x = 2 and 3.
class Sled : public Clock {
 public:
  const char* name() const override { return "sled"; }
  std::size_t body_count() const override { return 5; }
  BodyVisual body_visual(std::size_t i) const override {
    BodyVisual v;
    v.size[0] = v.size[1] = v.size[2] = 0.2;
    v.name = std::vector<std::string>{"cart", "post", "floor", "pad", "road"}[i];
    if (i < 2) return v;
    v.surface = true;
    v.covers = {0};
    v.shape = i == 4 ? BodyVisual::Shape::road : BodyVisual::Shape::plane;
    if (i == 4) v.profile = {2, 0, 3, 0.5};
    return v;
  }
  void body_poses(double, const double* y, const double*, double* out) override {
    const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double origins[5][3] = {{10 * y[0], 0, 0}, {100, 0, 0}, {0, 0, 0}, {10 * y[0], 0, 0}, {0, 0, 0}};
    for (int b = 0; b < 5; ++b) {
      std::copy(origins[b], origins[b] + 3, out + 12 * b);
      std::copy(identity, identity + 9, out + 12 * b + 3);
    }
  }
};

TEST(Animation, SurfacesAreMarkedAndCoverTheirBodiesRun) {
  const std::string glb = temp_path("surfaces") + ".glb";
  Sled model;
  use_gltf_animation();
  RunResult r = run(model, {"--animate", glb, "--solver", "rk4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "2 bodies in 5 frames to " + glb)) << r.err;  // the surfaces are not counted

  tinygltf::Model m;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&m, &error, &warning, glb)) << error;
  ASSERT_EQ(m.nodes.size(), 6u);
  auto surface_of = [&](int node) {
    const tinygltf::Value& extras = m.nodes[static_cast<std::size_t>(node)].extras;
    return extras.Has("surface") ? extras.Get("surface").Get<std::string>() : std::string("(none)");
  };
  EXPECT_EQ(surface_of(1), "(none)");
  EXPECT_EQ(surface_of(2), "(none)");
  EXPECT_EQ(surface_of(3), "plane");
  EXPECT_EQ(surface_of(4), "plane");
  EXPECT_EQ(surface_of(5), "road");
  // fixed surfaces have no channels, the pad moves with the cart
  std::set<int> animated;
  for (const tinygltf::AnimationChannel& c : m.animations.at(0).channels) animated.insert(c.target_node);
  EXPECT_EQ(animated, (std::set<int>{1, 2, 4}));
  // The floor covers the cart's run (the cube's corners reach sqrt(3) 0.1 m
  // from its centre) and half its largest extent more on each side; the post,
  // touching nothing, is not covered.
  const double reach = std::sqrt(3.0) * 0.1, margin = 0.5 * (10 + 2 * reach);
  const tinygltf::Accessor& floor = m.accessors.at(static_cast<std::size_t>(
      m.meshes.at(static_cast<std::size_t>(m.nodes[3].mesh)).primitives.at(0).attributes.at("POSITION")));
  EXPECT_NEAR(floor.minValues.at(0), -reach - margin, 1e-5);
  EXPECT_NEAR(floor.maxValues.at(0), 10 + reach + margin, 1e-5);
  EXPECT_NEAR(floor.minValues.at(1), -reach - margin, 1e-5);
  EXPECT_NEAR(floor.maxValues.at(1), reach + margin, 1e-5);
  EXPECT_NEAR(floor.maxValues.at(2), 0.0, 1e-7);
  // The pad, in the cart's frame over the run: the run seen from the cart.
  const tinygltf::Accessor& pad = m.accessors.at(static_cast<std::size_t>(
      m.meshes.at(static_cast<std::size_t>(m.nodes[4].mesh)).primitives.at(0).attributes.at("POSITION")));
  EXPECT_NEAR(pad.minValues.at(0), -10 - reach - margin, 1e-5);
  EXPECT_NEAR(pad.maxValues.at(0), 10 + reach + margin, 1e-5);
  // The road: the profile's points inside, its step to 0.5 m, flat beyond.
  const tinygltf::Primitive& road = m.meshes.at(static_cast<std::size_t>(m.nodes[5].mesh)).primitives.at(0);
  const std::vector<float> p = floats(m, road.attributes.at("POSITION"));
  bool at_2 = false, at_3 = false;
  for (std::size_t k = 0; k < p.size(); k += 3) {
    at_2 = at_2 || (std::abs(p[k] - 2) < 1e-6 && std::abs(p[k + 2]) < 1e-7);
    at_3 = at_3 || (std::abs(p[k] - 3) < 1e-6 && std::abs(p[k + 2] - 0.5) < 1e-7);
    if (p[k] > 3 + 1e-6) {
      EXPECT_NEAR(p[k + 2], 0.5, 1e-7);
    }
    if (p[k] < 2 - 1e-6) {
      EXPECT_NEAR(p[k + 2], 0.0, 1e-7);
    }
  }
  EXPECT_TRUE(at_2 && at_3);
  const tinygltf::Accessor& extent = m.accessors.at(static_cast<std::size_t>(road.attributes.at("POSITION")));
  EXPECT_NEAR(extent.minValues.at(0), -reach - margin, 1e-5);
  EXPECT_NEAR(extent.maxValues.at(0), 10 + reach + margin, 1e-5);
  std::filesystem::remove(glb);
}

TEST(Animation, QuaternionOfEveryBranchOfShepperd) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 2000; ++trial) {
    double q[4] = {g(rng), g(rng), g(rng), g(rng)};  // x, y, z, w
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& c : q) c /= n;
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                         2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    const std::array<double, 4> back = detail::quaternion_of(R);
    const double sign = back[0] * x + back[1] * y + back[2] * z + back[3] * w > 0 ? 1 : -1;  // q and -q: one rotation
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(sign * back[static_cast<std::size_t>(k)], q[k], 1e-12) << trial;
  }
}

TEST(Animation, ModelWithoutBodiesIsAnError) {
  use_gltf_animation();
  Decay m;
  RunResult r = run(m, {"--animate", temp_path("none") + ".glb"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "describes no bodies to draw"));
}

TEST(Animation, NotWithASweepOrALinearisation) {
  use_gltf_animation();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--animate", "a.glb", "--sweep", "k=1:2:2"}, {"--animate", "a.glb", "--linearize-at", "1"}}) {
    Decay m;
    RunResult r = run(m, args);
    EXPECT_EQ(r.status, 2) << args[2];
    EXPECT_TRUE(Contains(r.err, "--animate")) << args[2];
  }
}

// The glTF writer is an optional part (mbgrt/features.hpp): a program that
// never called use_gltf_animation() says so, and writes no file.
TEST(Animation, AProgramWithoutTheWriterSaysSo) {
  detail::animation_factory() = nullptr;
  const std::string glb = temp_path("without") + ".glb";
  Carousel model;
  RunResult r = run(model, {"--animate", glb, "--solver", "rk4"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "built without the glTF writer")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(glb));
}

}  // namespace
}  // namespace mbgrt::test
