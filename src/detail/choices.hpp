// One table per choice option: the names a schema lists and the enum values a method parses
// them into, written once (private).
#pragma once

#include <cstddef>
#include <optional>
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
  /// The value named `name`, if any (for text no schema has checked).
  constexpr std::optional<E> find(std::string_view name) const {
    for (const Choice<E>& c : items) {
      if (c.name == name) return c.value;
    }
    return std::nullopt;
  }
  /// "a, b or c", for messages.
  std::string or_list() const {
    std::string s;
    for (std::size_t i = 0; i < N; ++i) {
      s += i == 0 ? "" : i + 1 == N ? " or " : ", ";
      s += items[i].name;
    }
    return s;
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
