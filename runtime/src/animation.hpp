// animation.hpp — `--animate FILE.glb`: the motion of every body the model
// describes (Model::body_count, body_visual, body_poses) as binary glTF 2.0,
// the open 3-D exchange format, written with tinygltf (Debian
// libtinygltf-dev). One node per body with its shape as a mesh, keyframed at
// the output rows (translation and rotation channels, LINEAR); a flexible
// body's surface carries one morph target per mode, its `weights` channel
// the modal coordinates. The model's world is z up; glTF's is y up: a root
// node turns the scene by -90 degrees about x, the data stay as computed.
// The surfaces the bodies touch (BodyVisual::surface) are nodes too, marked
// extras.surface = their shape; a fixed one has no channels, and the
// unbounded ones are sized to cover their touching bodies' run.
//
// The library mbgrt_gltf (an optional part, mbgrt/features.hpp): the core
// knows only AnimationSink, and mbgrt::use_gltf_animation() installs this
// writer.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "animation_sink.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

class AnimationRecorder final : public AnimationSink {
 public:
  explicit AnimationRecorder(Model& model);
  /// Bodies to draw: none for a bond graph (the run then says so and writes nothing).
  /// The surfaces they touch (BodyVisual::surface) are drawn too, not counted.
  std::size_t bodies() const override {
    return static_cast<std::size_t>(std::count_if(visuals_.begin(), visuals_.end(), [](const BodyVisual& v) { return !v.surface; }));
  }
  /// The poses at one output row.
  void record(double t, const double* y, const double* yp) override;
  std::size_t frames() const override { return times_.size(); }
  /// Writes the file; throws std::runtime_error if it cannot.
  void write(const std::string& path) const override;

 private:
  Model& model_;
  std::vector<BodyVisual> visuals_;
  std::size_t pose_size_ = 0;
  std::vector<double> times_;
  std::vector<double> poses_;  ///< frames x pose_size_
  std::vector<double> row_;
};

/// The unit quaternion [x, y, z, w] (glTF's order) of a rotation matrix
/// (row-major, proper orthogonal), by Shepperd's method (the largest of the
/// four candidates first, so no division by a small number).
std::array<double, 4> quaternion_of(const double* R);

}  // namespace mbgrt::detail
