#pragma once
// Repeats among unordered pairs of ids (edges, face sides), without a set (implemented in core/skeleton.cpp).
#include <array>
#include <vector>

namespace mesohex {

// Per pair: 1 when no earlier pair joins the same two ids (in either direction), else 0. O(#pairs + n) when every id
// is in [0, n), else a sort.
std::vector<char> first_of_each_pair(const std::vector<std::array<int, 2>>& pairs, int n);

}  // namespace mesohex
