// An enum's names in one table: toString and parse of each enum read the same table. ROS-free.
//   constexpr EnumName<MotionKind> kNames[] = {{MotionKind::kRoom, "room"}, ...};
//   const char* toString(MotionKind m) { return nameOf(kNames, m); }
//   bool parseMotionKind(const std::string& s, MotionKind* m) { return parseName(kNames, s, m); }
#pragma once

#include <cstddef>
#include <string>

namespace iraf_vo {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The name of `value`, or `fallback` when the table has none.
template <class E, size_t N>
const char* nameOf(const EnumName<E> (&names)[N], E value, const char* fallback = "?") {
  for (const EnumName<E>& n : names)
    if (n.value == value) return n.name;
  return fallback;
}

/// Sets *value to the entry named exactly `text`; false (and *value unchanged) when no entry is.
template <class E, size_t N>
bool parseName(const EnumName<E> (&names)[N], const std::string& text, E* value) {
  for (const EnumName<E>& n : names)
    if (text == n.name) {
      *value = n.value;
      return true;
    }
  return false;
}

}  // namespace iraf_vo
