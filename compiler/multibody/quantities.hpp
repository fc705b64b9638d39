// multibody/quantities.hpp — the quantities users may name (`bob.position`,
// `j1.angle`, `c1.gap`), each the expression that defines it, and the names
// of everything the multibody layer generated. In: the Expander defines them
// as it writes the fragments they read (expander.hpp; the bodies' and joints'
// in quantities.cpp). Out: the table user expressions are rewritten against
// (rewrite.hpp) and the units pass reads (units.hpp).
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "multibody/build.hpp"
#include "multibody/symbols.hpp"

namespace mbgc::multibody::detail {

class Quantities {
 public:
  /// Quantity `name` is `value` (a later definition replaces an earlier one).
  void define(const Sym& name, E value) { table_.insert_or_assign(name.str(), std::move(value)); }
  /// The definition of quantity `name`; null if there is no such quantity.
  const E* find(const std::string& name) const {
    auto it = table_.find(name);
    return it == table_.end() ? nullptr : &it->second;
  }
  const E& at(const std::string& name) const { return table_.at(name); }
  /// The quantities of body or joint `owner`, by what follows `owner.`, in name order (what a typo's error offers).
  std::vector<std::string> of(const std::string& owner) const {
    std::vector<std::string> out;
    for (const auto& [q, value] : table_)
      if (q.compare(0, owner.size() + 1, owner + ".") == 0) out.push_back(q.substr(owner.size() + 1));
    return out;
  }

  /// The layer wrote `name` (a parameter, signal, element, junction or named bond).
  void generated(const std::string& name) { generated_.insert(name); }
  bool is_generated(const std::string& name) const { return generated_.count(name) > 0; }

 private:
  std::map<std::string, E> table_;
  std::set<std::string> generated_;
};

}  // namespace mbgc::multibody::detail
