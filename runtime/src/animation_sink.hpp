// animation_sink.hpp — what the core asks of `--animate`: record the bodies'
// poses at every output row, write them at the end. The writer itself (glTF,
// animation.cpp) is an optional part (mbgrt/features.hpp): the core reaches
// it through the factory a program installs with mbgrt::use_gltf_animation(),
// so a simulator of a model with no bodies never links tinygltf.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "mbgrt/model.hpp"

namespace mbgrt::detail {

class AnimationSink {
 public:
  virtual ~AnimationSink() = default;
  /// Bodies to draw: none for a bond graph (the run then says so and writes nothing).
  virtual std::size_t bodies() const = 0;
  /// The poses at one output row.
  virtual void record(double t, const double* y, const double* yp) = 0;
  virtual std::size_t frames() const = 0;
  /// Writes the file; throws std::runtime_error if it cannot.
  virtual void write(const std::string& path) const = 0;
};

using AnimationFactory = std::unique_ptr<AnimationSink> (*)(Model&);

/// The installed writer's factory; null until use_gltf_animation(). (A
/// function-local static of an inline function: one object in the program,
/// and the optional library needs no symbol of the core's to set it.)
inline AnimationFactory& animation_factory() {
  static AnimationFactory factory = nullptr;
  return factory;
}

}  // namespace mbgrt::detail
