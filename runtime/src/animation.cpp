#include "animation.hpp"

#include "mbgrt/features.hpp"

#include <fmt/format.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace mbgrt::detail {

namespace {

/// A triangle mesh in body axes with per-vertex normals.
struct Mesh {
  std::vector<float> positions, normals;
  std::vector<unsigned> indices;
  void vertex(double x, double y, double z, double nx, double ny, double nz) {
    positions.insert(positions.end(), {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
    normals.insert(normals.end(), {static_cast<float>(nx), static_cast<float>(ny), static_cast<float>(nz)});
  }
  unsigned count() const { return static_cast<unsigned>(positions.size() / 3); }
};

Mesh box(const BodyVisual& v) {
  Mesh m;
  const double h[3] = {v.size[0] / 2, v.size[1] / 2, v.size[2] / 2};
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {  // the face whose normal is side * e_axis
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const unsigned first = m.count();
      for (int k = 0; k < 4; ++k) {
        double p[3], n[3] = {0, 0, 0};
        p[axis] = side * h[axis];
        p[u] = (k == 1 || k == 2 ? 1 : -1) * h[u];
        p[w] = (k >= 2 ? 1 : -1) * h[w];
        n[axis] = side;
        m.vertex(v.centre[0] + p[0], v.centre[1] + p[1], v.centre[2] + p[2], n[0], n[1], n[2]);
      }
      // counter-clockwise seen from outside
      if (side > 0) m.indices.insert(m.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
      else m.indices.insert(m.indices.end(), {first, first + 2, first + 1, first, first + 3, first + 2});
    }
  return m;
}

constexpr int kSegments = 24;

Mesh cylinder(const BodyVisual& v) {  // along body z
  Mesh m;
  const double r = v.size[0], half = v.size[1] / 2;
  const double* c = v.centre;
  for (int k = 0; k <= kSegments; ++k) {  // the side, a seam at k = 0 and kSegments
    const double a = 2 * std::numbers::pi * k / kSegments, x = std::cos(a), y = std::sin(a);
    m.vertex(c[0] + r * x, c[1] + r * y, c[2] - half, x, y, 0);
    m.vertex(c[0] + r * x, c[1] + r * y, c[2] + half, x, y, 0);
  }
  for (unsigned k = 0; k < kSegments; ++k)
    m.indices.insert(m.indices.end(), {2 * k, 2 * k + 2, 2 * k + 3, 2 * k, 2 * k + 3, 2 * k + 1});
  for (int side : {-1, 1}) {  // the caps: a fan around their centres
    const unsigned centre = m.count();
    m.vertex(c[0], c[1], c[2] + side * half, 0, 0, side);
    for (int k = 0; k < kSegments; ++k) {
      const double a = 2 * std::numbers::pi * k / kSegments;
      m.vertex(c[0] + r * std::cos(a), c[1] + r * std::sin(a), c[2] + side * half, 0, 0, side);
    }
    for (unsigned k = 0; k < kSegments; ++k) {
      const unsigned a = centre + 1 + k, b = centre + 1 + (k + 1) % kSegments;
      if (side > 0) m.indices.insert(m.indices.end(), {centre, a, b});
      else m.indices.insert(m.indices.end(), {centre, b, a});
    }
  }
  return m;
}

Mesh sphere(const BodyVisual& v) {
  Mesh m;
  const double r = v.size[0];
  constexpr int kRings = 12;
  for (int i = 0; i <= kRings; ++i) {
    const double polar = std::numbers::pi * i / kRings;
    for (int k = 0; k <= kSegments; ++k) {
      const double a = 2 * std::numbers::pi * k / kSegments;
      const double x = std::sin(polar) * std::cos(a), y = std::sin(polar) * std::sin(a), z = std::cos(polar);
      m.vertex(v.centre[0] + r * x, v.centre[1] + r * y, v.centre[2] + r * z, x, y, z);
    }
  }
  const unsigned row = kSegments + 1;
  for (unsigned i = 0; i < kRings; ++i)
    for (unsigned k = 0; k < kSegments; ++k) {
      const unsigned a = i * row + k, b = a + row;
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  return m;
}

/// A given surface; normals averaged over the triangles at each vertex.
Mesh surface(const BodyVisual& v) {
  Mesh m;
  const std::size_t n = v.vertices.size() / 3;
  std::vector<double> normal(3 * n, 0.0);
  for (std::size_t t = 0; t + 2 < v.triangles.size(); t += 3) {
    const double* a = &v.vertices[3 * v.triangles[t]];
    const double* b = &v.vertices[3 * v.triangles[t + 1]];
    const double* c = &v.vertices[3 * v.triangles[t + 2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double cr[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) normal[3 * v.triangles[t + static_cast<std::size_t>(k)] + static_cast<std::size_t>(j)] += cr[j];
  }
  for (std::size_t i = 0; i < n; ++i) {
    double* nv = &normal[3 * i];
    const double len = std::sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
    if (len > 0) nv[0] /= len, nv[1] /= len, nv[2] /= len;
    m.vertex(v.vertices[3 * i], v.vertices[3 * i + 1], v.vertices[3 * i + 2], nv[0], nv[1], nv[2]);
  }
  m.indices = v.triangles;
  return m;
}

/// The largest distance of a mesh's vertex from the point its body's pose gives.
double reach(const Mesh& m) {
  double r = 0;
  for (std::size_t i = 0; i + 2 < m.positions.size(); i += 3)
    r = std::max(r, std::sqrt(double(m.positions[i]) * m.positions[i] + double(m.positions[i + 1]) * m.positions[i + 1] +
                              double(m.positions[i + 2]) * m.positions[i + 2]));
  return r;
}

/// An axis-aligned box; lo > hi while empty.
struct Box {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  bool empty() const { return lo[0] > hi[0]; }
  void add(const double* p, double r = 0) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k] - r), hi[k] = std::max(hi[k], p[k] + r);
  }
  double largest() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}); }
};

/// A plane: the rectangle [x0, x1] x [y0, y1] of its x-y plane, normal +z.
Mesh plane_patch(const Box& local) {
  Mesh m;
  for (int k = 0; k < 4; ++k)
    m.vertex(k == 1 || k == 2 ? local.hi[0] : local.lo[0], k >= 2 ? local.hi[1] : local.lo[1], 0, 0, 0, 1);
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

/// A convex polygon of the x-z plane (corners counter-clockwise, x right, z
/// up) extruded over [y0, y1]: its side faces and its two ends.
Mesh prism(const std::vector<double>& corners, double y0, double y1) {
  Mesh m;
  const std::size_t n = corners.size() / 2;
  for (std::size_t i = 0; i < n; ++i) {  // a side face per edge, outward normal (dz, 0, -dx)
    const double ax = corners[2 * i], az = corners[2 * i + 1];
    const double bx = corners[2 * ((i + 1) % n)], bz = corners[2 * ((i + 1) % n) + 1];
    double nx = bz - az, nz = -(bx - ax);
    const double len = std::hypot(nx, nz);
    if (!(len > 0)) continue;
    nx /= len, nz /= len;
    const unsigned first = m.count();
    m.vertex(ax, y0, az, nx, 0, nz), m.vertex(bx, y0, bz, nx, 0, nz), m.vertex(bx, y1, bz, nx, 0, nz), m.vertex(ax, y1, az, nx, 0, nz);
    m.indices.insert(m.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
  }
  for (double y : {y0, y1}) {  // the ends: fans
    const unsigned first = m.count();
    const double ny = y == y0 ? -1 : 1;
    for (std::size_t i = 0; i < n; ++i) m.vertex(corners[2 * i], y, corners[2 * i + 1], 0, ny, 0);
    for (unsigned i = 1; i + 1 < n; ++i) m.indices.insert(m.indices.end(), {first, first + i, first + i + 1});
  }
  return m;
}

/// A road z = h(x) over [x0, x1] x [y0, y1]: h through the profile's points,
/// constant beyond its ends; one flat strip per segment.
Mesh road(const std::vector<double>& profile, const Box& local) {
  const double x0 = local.lo[0], x1 = local.hi[0];
  auto height = [&](double x) {
    if (profile.empty()) return 0.0;
    if (x <= profile[0]) return profile[1];
    for (std::size_t k = 2; k + 1 < profile.size(); k += 2)
      if (x <= profile[k]) return profile[k - 1] + (profile[k + 1] - profile[k - 1]) * (x - profile[k - 2]) / (profile[k] - profile[k - 2]);
    return profile[profile.size() - 1];
  };
  std::vector<double> xs = {x0};
  for (std::size_t k = 0; k + 1 < profile.size(); k += 2)
    if (profile[k] > x0 && profile[k] < x1) xs.push_back(profile[k]);
  xs.push_back(x1);
  Mesh m;
  for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
    const double ha = height(xs[k]), hb = height(xs[k + 1]);
    const double dx = xs[k + 1] - xs[k], dh = hb - ha, len = std::hypot(dx, dh);
    if (!(len > 0)) continue;
    const double nx = -dh / len, nz = dx / len;
    const unsigned first = m.count();
    m.vertex(xs[k], local.lo[1], ha, nx, 0, nz), m.vertex(xs[k + 1], local.lo[1], hb, nx, 0, nz);
    m.vertex(xs[k + 1], local.hi[1], hb, nx, 0, nz), m.vertex(xs[k], local.hi[1], ha, nx, 0, nz);
    m.indices.insert(m.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
  }
  return m;
}

/// Builds the glTF model: buffers, views and accessors appended as data come.
class Writer {
 public:
  int accessor(const std::vector<float>& data, int type, int components, bool with_bounds, int target = 0) {
    const int view = view_of(data.data(), data.size() * sizeof(float), target);
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.count = data.size() / static_cast<std::size_t>(components);
    a.type = type;
    if (with_bounds) {
      a.minValues.assign(static_cast<std::size_t>(components), HUGE_VAL);
      a.maxValues.assign(static_cast<std::size_t>(components), -HUGE_VAL);
      for (std::size_t i = 0; i < data.size(); ++i) {
        const std::size_t k = i % static_cast<std::size_t>(components);
        a.minValues[k] = std::min(a.minValues[k], static_cast<double>(data[i]));
        a.maxValues[k] = std::max(a.maxValues[k], static_cast<double>(data[i]));
      }
    }
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  }
  int indices(const std::vector<unsigned>& data) {
    const int view = view_of(data.data(), data.size() * sizeof(unsigned), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.count = data.size();
    a.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  }
  tinygltf::Model model;

 private:
  int view_of(const void* data, std::size_t bytes, int target) {
    if (model.buffers.empty()) model.buffers.emplace_back();
    std::vector<unsigned char>& buffer = model.buffers[0].data;
    while (buffer.size() % 4) buffer.push_back(0);  // every view 4-byte aligned
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buffer.size();
    v.byteLength = bytes;
    v.target = target;
    buffer.resize(buffer.size() + bytes);
    std::memcpy(buffer.data() + v.byteOffset, data, bytes);
    model.bufferViews.push_back(v);
    return static_cast<int>(model.bufferViews.size() - 1);
  }
};

}  // namespace

std::array<double, 4> quaternion_of(const double* R) {
  const double trace = R[0] + R[4] + R[8];
  std::array<double, 4> q{};  // x, y, z, w
  if (trace >= R[0] && trace >= R[4] && trace >= R[8]) {
    const double s = 2 * std::sqrt(1 + trace);
    q = {(R[7] - R[5]) / s, (R[2] - R[6]) / s, (R[3] - R[1]) / s, s / 4};
  } else if (R[0] >= R[4] && R[0] >= R[8]) {
    const double s = 2 * std::sqrt(1 + R[0] - R[4] - R[8]);
    q = {s / 4, (R[1] + R[3]) / s, (R[2] + R[6]) / s, (R[7] - R[5]) / s};
  } else if (R[4] >= R[8]) {
    const double s = 2 * std::sqrt(1 + R[4] - R[0] - R[8]);
    q = {(R[1] + R[3]) / s, s / 4, (R[5] + R[7]) / s, (R[2] - R[6]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + R[8] - R[0] - R[4]);
    q = {(R[2] + R[6]) / s, (R[5] + R[7]) / s, s / 4, (R[3] - R[1]) / s};
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  return q;
}

AnimationRecorder::AnimationRecorder(Model& model) : model_(model) {
  for (std::size_t i = 0; i < model.body_count(); ++i) {
    visuals_.push_back(model.body_visual(i));
    pose_size_ += 12 + visuals_.back().mode_shapes.size();
  }
  row_.resize(pose_size_);
}

void AnimationRecorder::record(double t, const double* y, const double* yp) {
  if (visuals_.empty()) return;
  model_.body_poses(t, y, yp, row_.data());
  times_.push_back(t);
  poses_.insert(poses_.end(), row_.begin(), row_.end());
}

void AnimationRecorder::write(const std::string& path) const {
  Writer w;
  tinygltf::Model& m = w.model;
  m.asset.version = "2.0";
  m.asset.generator = "mbgrt (mbgc's runtime) --animate";
  tinygltf::Scene scene;
  tinygltf::Node root;
  root.name = "world (z up)";
  root.rotation = {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)};  // -90 degrees about x: the model's z is glTF's y
  m.nodes.push_back(root);
  scene.nodes.push_back(0);

  auto body_mesh = [](const BodyVisual& v) {
    return v.shape == BodyVisual::Shape::box        ? box(v)
           : v.shape == BodyVisual::Shape::cylinder ? cylinder(v)
           : v.shape == BodyVisual::Shape::sphere   ? sphere(v)
                                                    : surface(v);
  };
  // Where the bodies go over the run (world): an unbounded surface covers
  // the box its touching bodies sweep, and half its largest extent more on
  // every side, in its own frame at every row.
  std::vector<double> reaches(visuals_.size(), 0.0);
  for (std::size_t b = 0; b < visuals_.size(); ++b)
    if (!visuals_[b].surface) reaches[b] = reach(body_mesh(visuals_[b]));
  auto swept_by = [&](const std::vector<std::size_t>& covers) {
    Box swept;
    for (std::size_t b = 0; b < visuals_.size(); ++b) {
      if (visuals_[b].surface || (!covers.empty() && std::find(covers.begin(), covers.end(), b) == covers.end())) continue;
      for (std::size_t f = 0; f < times_.size(); ++f) swept.add(&poses_[f * pose_size_ + 12 * b], reaches[b]);
    }
    if (swept.empty()) {
      const double origin[3] = {0, 0, 0};
      swept.add(origin, 0.5);
    }
    return swept;
  };
  /// That box in the frame of entry b's pose (over all rows), with the margin around it.
  auto local_box = [&](std::size_t b) {
    const Box swept = swept_by(visuals_[b].covers);
    const double margin = std::max(0.5 * swept.largest(), 1e-3);
    Box local;
    for (std::size_t f = 0; f < std::max<std::size_t>(times_.size(), 1); ++f) {
      const double* pose = times_.empty() ? nullptr : &poses_[f * pose_size_ + 12 * b];
      for (int corner = 0; corner < 8; ++corner) {
        const double c[3] = {corner & 1 ? swept.hi[0] : swept.lo[0], corner & 2 ? swept.hi[1] : swept.lo[1],
                             corner & 4 ? swept.hi[2] : swept.lo[2]};
        double d[3] = {c[0], c[1], c[2]};
        if (pose) {  // R^T (c - p)
          const double* R = pose + 3;
          const double e[3] = {c[0] - pose[0], c[1] - pose[1], c[2] - pose[2]};
          for (int k = 0; k < 3; ++k) d[k] = R[k] * e[0] + R[3 + k] * e[1] + R[6 + k] * e[2];
        }
        local.add(d, margin);
      }
    }
    return local;
  };
  auto surface_mesh = [&](std::size_t b) {
    BodyVisual v = visuals_[b];
    switch (v.shape) {
      case BodyVisual::Shape::plane: return plane_patch(local_box(b));
      case BodyVisual::Shape::road: return road(v.profile, local_box(b));
      case BodyVisual::Shape::prism: {
        const Box local = local_box(b);
        return prism(v.profile, local.lo[1], local.hi[1]);
      }
      case BodyVisual::Shape::cylinder:
        if (v.size[1] <= 0) {
          const Box local = local_box(b);
          v.size[1] = local.hi[2] - local.lo[2];
          v.centre[0] = v.centre[1] = 0, v.centre[2] = 0.5 * (local.lo[2] + local.hi[2]);
        }
        return cylinder(v);
      default: return body_mesh(v);
    }
  };

  std::vector<float> times(times_.begin(), times_.end());
  const int input = times.empty() ? -1 : w.accessor(times, TINYGLTF_TYPE_SCALAR, 1, true);
  tinygltf::Animation animation;
  animation.name = "run";
  std::size_t offset = 0;  // into a row of poses: this body's pose
  std::size_t modal = 12 * visuals_.size();  // and its modal coordinates
  for (std::size_t b = 0; b < visuals_.size(); ++b) {
    const BodyVisual& v = visuals_[b];
    const Mesh mesh = v.surface ? surface_mesh(b) : body_mesh(v);
    tinygltf::Material material;
    material.name = v.name;
    material.pbrMetallicRoughness.baseColorFactor = {v.colour[0], v.colour[1], v.colour[2], 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 0.8;
    material.doubleSided = true;
    m.materials.push_back(material);
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = w.accessor(mesh.positions, TINYGLTF_TYPE_VEC3, 3, true, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["NORMAL"] = w.accessor(mesh.normals, TINYGLTF_TYPE_VEC3, 3, false, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.indices = w.indices(mesh.indices);
    primitive.material = static_cast<int>(m.materials.size() - 1);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    for (const std::vector<double>& shape : v.mode_shapes) {  // a morph target per mode
      if (shape.size() != mesh.positions.size())
        throw std::runtime_error(fmt::format("--animate: body '{}' has {} vertices but a mode shape of {} numbers",
                                             v.name, mesh.count(), shape.size()));
      std::vector<float> d(shape.begin(), shape.end());
      primitive.targets.push_back({{"POSITION", w.accessor(d, TINYGLTF_TYPE_VEC3, 3, true, TINYGLTF_TARGET_ARRAY_BUFFER)}});
    }
    tinygltf::Mesh gm;
    gm.name = v.name;
    gm.primitives.push_back(primitive);
    gm.weights.assign(v.mode_shapes.size(), 0.0);
    m.meshes.push_back(gm);
    tinygltf::Node node;
    node.name = v.name;
    node.mesh = static_cast<int>(m.meshes.size() - 1);
    // A surface is fixed (the ground's) or moves with a body; it is marked
    // so that viewers can tell it from the bodies (three.js: userData.surface).
    bool fixed = false;
    if (v.surface) {
      static const char* const kNames[] = {"box", "cylinder", "sphere", "mesh", "plane", "prism", "road"};
      tinygltf::Value::Object extras;
      extras["surface"] = tinygltf::Value(std::string(kNames[static_cast<int>(v.shape)]));
      node.extras = tinygltf::Value(extras);
      fixed = true;
      for (std::size_t f = 1; f < times_.size() && fixed; ++f)
        fixed = std::equal(&poses_[f * pose_size_ + offset], &poses_[f * pose_size_ + offset + 12], &poses_[offset]);
      if (fixed && !times_.empty()) {
        node.translation = {poses_[offset], poses_[offset + 1], poses_[offset + 2]};
        const std::array<double, 4> q = quaternion_of(&poses_[offset + 3]);
        node.rotation.assign(q.begin(), q.end());
      }
    }
    m.nodes.push_back(node);
    const int index = static_cast<int>(m.nodes.size() - 1);
    m.nodes[0].children.push_back(index);

    if (input >= 0 && !fixed) {  // keyframes: translation, rotation, and the modal weights
      std::vector<float> translation, rotation, weights;
      for (std::size_t f = 0; f < times_.size(); ++f) {
        const double* pose = &poses_[f * pose_size_ + offset];
        translation.insert(translation.end(), {static_cast<float>(pose[0]), static_cast<float>(pose[1]), static_cast<float>(pose[2])});
        const std::array<double, 4> q = quaternion_of(pose + 3);
        for (double c : q) rotation.push_back(static_cast<float>(c));
        for (std::size_t k = 0; k < v.mode_shapes.size(); ++k)
          weights.push_back(static_cast<float>(poses_[f * pose_size_ + modal + k]));
      }
      auto channel = [&](const std::vector<float>& data, int type, int components, const char* path) {
        tinygltf::AnimationSampler sampler;
        sampler.input = input;
        sampler.output = w.accessor(data, type, components, false);
        sampler.interpolation = "LINEAR";
        animation.samplers.push_back(sampler);
        tinygltf::AnimationChannel c;
        c.sampler = static_cast<int>(animation.samplers.size() - 1);
        c.target_node = index;
        c.target_path = path;
        animation.channels.push_back(c);
      };
      channel(translation, TINYGLTF_TYPE_VEC3, 3, "translation");
      channel(rotation, TINYGLTF_TYPE_VEC4, 4, "rotation");
      if (!v.mode_shapes.empty()) channel(weights, TINYGLTF_TYPE_SCALAR, 1, "weights");
    }
    offset += 12;
    modal += v.mode_shapes.size();
  }
  if (!animation.channels.empty()) m.animations.push_back(animation);
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToFile(&m, path, /*embedImages=*/true, /*embedBuffers=*/true, /*prettyPrint=*/false,
                                 /*writeBinary=*/true))
    throw std::runtime_error(fmt::format("--animate {}: cannot write the file", path));
}

}  // namespace mbgrt::detail

namespace mbgrt {

void use_gltf_animation() {
  detail::animation_factory() = [](Model& model) -> std::unique_ptr<detail::AnimationSink> {
    return std::make_unique<detail::AnimationRecorder>(model);
  };
}

}  // namespace mbgrt
