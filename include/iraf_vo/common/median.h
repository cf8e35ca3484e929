// The median of a sample, as the stages and tools report it. ROS-free.
#pragma once

#include <algorithm>

namespace iraf_vo {

/// The element at index n / 2 of the sorted values (the upper one of the middle two when n is even); 0 when empty.
/// Takes a copy (a std::vector or std::deque of numbers) that it reorders.
template <class Values>
double median(Values v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace iraf_vo
