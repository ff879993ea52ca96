#pragma once
// What the two cache targets share. A cache file (core/cache_file.h) ends in an XXH64 of
// everything before it, which a mutation almost never keeps right, so a target fed only the bytes
// as they are would test little beyond the checksum. Each input is therefore read twice: as it
// is (the header checks and the checksum's rejection), and with its last 8 bytes replaced by the
// right checksum (everything the reader checks after it: sizes against counts, the payload).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lambert/core/cache_file.h"

namespace lambert::fuzz {

// The input with a valid checksum in place of its last 8 bytes; empty when it is too short to
// hold a header and a checksum.
inline std::vector<std::uint8_t> withValidChecksum(const std::uint8_t* data, std::size_t size) {
  if (size < cachefile::kHeaderBytes + cachefile::kChecksumBytes) return {};
  std::vector<std::uint8_t> fixed(data, data + size);
  const std::size_t body = size - cachefile::kChecksumBytes;
  cachefile::Xxh64 hash;
  hash.update(fixed.data(), body);
  cachefile::storeLe64(fixed.data() + body, hash.digest());
  return fixed;
}

// The header's key (offset 16) and count (offset 24), or 0 for an input too short to hold them:
// the targets pass them as the expected values, so an input is not refused for a stale key alone.
inline std::uint64_t headerKey(const std::uint8_t* data, std::size_t size) {
  return size >= cachefile::kHeaderBytes ? cachefile::loadLe64(data + 16) : 0;
}
inline std::uint64_t headerCount(const std::uint8_t* data, std::size_t size) {
  return size >= cachefile::kHeaderBytes ? cachefile::loadLe64(data + 24) : 0;
}

// Reads the input with `load` as it is, then with a valid checksum (see above).
template <class Load>
void loadAsIsAndWithValidChecksum(const std::uint8_t* data, std::size_t size, Load load) {
  load(data, size);
  const std::vector<std::uint8_t> fixed = withValidChecksum(data, size);
  if (!fixed.empty()) load(fixed.data(), fixed.size());
}

}  // namespace lambert::fuzz
