// One table per choice option: the names a schema lists and the enum values a method parses
// them into, written once (private).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace fairspline::detail {

template <class E>
struct Choice {
  std::string_view name;
  E value;
};

template <class E, std::size_t N>
struct ChoiceTable {
  Choice<E> items[N];

  /// The value named `name`; the registry has already checked the name against names(), so
  /// an unknown one is a programming error and gives the first entry (the default).
  constexpr E parse(std::string_view name) const {
    for (const Choice<E>& c : items) {
      if (c.name == name) return c.value;
    }
    return items[0].value;
  }
  constexpr std::string_view name(E value) const {
    for (const Choice<E>& c : items) {
      if (c.value == value) return c.name;
    }
    return items[0].name;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> v;
    for (const Choice<E>& c : items) v.emplace_back(c.name);
    return v;
  }
};

}  // namespace fairspline::detail
