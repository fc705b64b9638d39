// multibody/spanning_tree.hpp — the multibody layer's second pass, over
// the Model the collect pass read (collect.hpp): a spanning tree from
// ground, breadth first (the joint that places each body, Body::placed_by;
// the others close loops), the constraint strategy of every joint left to
// `auto` (joint coordinates where they can move every one of them, else
// multipliers, said in `strategy_report`), and the bodies joint coordinates
// move (Body::by_coordinates). What keeps joint coordinates from a joint
// that asks for them is an error.
#pragma once

#include <string>

#include "ir/diagnostics.hpp"
#include "multibody/model.hpp"

namespace mbgc::multibody::detail {

void plan_tree(Model& m, ir::Diagnostics& diags, std::string* strategy_report);

}  // namespace mbgc::multibody::detail
