#pragma once
// Disjoint sets over 0 … n − 1 (union–find with path halving): the regions of a scene's pieces
// (scene/regions.h), the enclosures of closed two-sided objects (geometry/enclosures.h).
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace lambert {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  // Joins the sets of a and b; the lowest member names the set.
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace lambert
