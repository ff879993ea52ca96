#pragma once
// PCG32 (O'Neill 2014), seeded per (seed, stream) so every element's random numbers are the same
// whatever the thread count or the order work is scheduled in.
#include <cstdint>

namespace lambert {

// SplitMix64 finaliser: spreads nearby keys (patch ids) over the whole 64-bit range.
constexpr std::uint64_t mixBits(std::uint64_t v) {
  v ^= v >> 30;
  v *= 0xbf58476d1ce4e5b9ULL;
  v ^= v >> 27;
  v *= 0x94d049bb133111ebULL;
  v ^= v >> 31;
  return v;
}

class Pcg32 {
 public:
  Pcg32(std::uint64_t seed, std::uint64_t stream) : inc_((mixBits(stream) << 1u) | 1u) {
    nextUint();
    state_ += mixBits(seed);
    nextUint();
  }

  std::uint32_t nextUint() {
    std::uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }

  // Uniform in [0, 1).
  double nextDouble() { return nextUint() * 0x1p-32; }

  // Uniform integer in [0, bound).
  std::uint32_t nextBelow(std::uint32_t bound) {
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(nextUint()) * bound) >> 32);
  }

 private:
  std::uint64_t state_ = 0;
  std::uint64_t inc_;
};

}  // namespace lambert
