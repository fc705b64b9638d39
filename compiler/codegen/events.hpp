// codegen/events.hpp — the generated model's events (reduce/events): one mode
// per discontinuity, the methods the runtime switches them through, and their
// names in model terms. The zero-crossing functions themselves are a section
// of equations, written by the emitter like the outputs.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <unordered_map>

#include "codegen/cpp.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// How event k's mode is written in expressions: "mode_[k]".
std::string event_mode_name(std::size_t k);

/// Event `ev` in model terms (Model::event_name): "heaviside(t - t_off) (time
/// event), Sf src (events.mbg:15:4)".
std::string event_name(const ir::EventRelation& ev, const ir::Namer& names,
                       const std::function<std::string(const ir::SourceLoc&)>& where);

/// event_count(), event_name(), set_event_mode() and the modes' member array
/// (nothing when the model has no events). An event's name is its step and
/// the element and model line it comes from, `where` writing the line
/// ("heaviside(cap.e - v1), Sf src (events.mbg:15:4)").
void add_event_methods(CppClass& c, const ir::ReducedSystem& s,
                       const std::function<std::string(const ir::SourceLoc&)>& where);

/// How a contact's discrete variables are written: its mode (closed) as its
/// event's mode, its bias and damping as members the runtime sets.
std::unordered_map<int, std::string> contact_member_names(const ir::ReducedSystem& s);

/// contact_count(), contact(c), set_contact_bias(), set_contact_damping(),
/// the members they write, and `speeds` (the contacts' dg/dt, a section of
/// equations the emitter wrote). initial() fills contact_restitution_.
/// `tangents`: the sliding velocities and frictions, when a contact has friction rows.
/// held_state_size/get_held_state/set_held_state (mbgrt::Model): the event
/// modes and the contacts' run-time settings, for a model with either.
void add_held_state_methods(CppClass& c, const ir::ReducedSystem& s);

void add_contact_methods(CppClass& c, const ir::ReducedSystem& s, CppFunction speeds, std::optional<CppFunction> tangents);

}  // namespace mbgc::codegen
