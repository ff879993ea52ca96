#pragma once
// The one way lambert writes output and cache files: to a temporary file beside the target, then
// renamed over it, so a reader never sees a partial file and a failed write leaves the old one.
#include <cstdint>
#include <span>
#include <string>

#include "lambert/core/error.h"

namespace lambert {

// Creates missing parent directories. Errors name the path and what failed; no temporary file is
// left behind either way.
Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes);

}  // namespace lambert
