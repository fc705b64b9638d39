// codegen/drawings.hpp — the generated model's drawn bodies (ir/drawing.hpp)
// for --animate: how many, what each looks like (body_visual, constant data
// in body axes) and, written by the emitter like the outputs, where each is
// (body_poses, a section of equations).
#pragma once

#include "codegen/cpp.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// body_count(), body_visual(i) and `poses` (the body_poses section the
/// emitter wrote); nothing when the model draws no body.
void add_drawing_methods(CppClass& c, const ir::ReducedSystem& s, CppFunction poses);

}  // namespace mbgc::codegen
