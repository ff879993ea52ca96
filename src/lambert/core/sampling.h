#pragma once
// Low-discrepancy points in the unit square: the (0,2)-sequence of van der Corput (base 2) and the
// second Sobol' dimension, randomised by an XOR scramble (Kollig & Keller, "Efficient
// Multidimensional Sampling", 2002). Every power-of-two prefix is a (0,m,2)-net: one point in each
// of the N elementary rectangles of every shape, which plain per-axis stratification (N-rooks)
// does not give. The scramble keeps that property and makes estimates unbiased.
#include <cstdint>

namespace lambert {

inline std::uint32_t vanDerCorput(std::uint32_t index, std::uint32_t scramble) {
  index = (index << 16) | (index >> 16);
  index = ((index & 0x00ff00ffu) << 8) | ((index & 0xff00ff00u) >> 8);
  index = ((index & 0x0f0f0f0fu) << 4) | ((index & 0xf0f0f0f0u) >> 4);
  index = ((index & 0x33333333u) << 2) | ((index & 0xccccccccu) >> 2);
  index = ((index & 0x55555555u) << 1) | ((index & 0xaaaaaaaau) >> 1);
  return index ^ scramble;
}

inline std::uint32_t sobolSecondDimension(std::uint32_t index, std::uint32_t scramble) {
  for (std::uint32_t v = 1u << 31; index; index >>= 1, v ^= v >> 1)
    if (index & 1u) scramble ^= v;
  return scramble;
}

struct UnitSquarePoint {
  double u, v;
};

// Point `index` of the scrambled (0,2)-sequence, in [0,1)².
inline UnitSquarePoint scrambledZeroTwo(std::uint32_t index, std::uint32_t scrambleU, std::uint32_t scrambleV) {
  return {vanDerCorput(index, scrambleU) * 0x1p-32, sobolSecondDimension(index, scrambleV) * 0x1p-32};
}

}  // namespace lambert
