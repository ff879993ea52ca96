#pragma once
// The one way lambert writes output and cache files: to a temporary file beside the target, then
// renamed over it, so a reader never sees a partial file and a failed write leaves the old one.
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>

#include "lambert/core/error.h"

namespace lambert {

// Creates missing parent directories. Errors name the path and what failed; no temporary file is
// left behind either way.
Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes);
// The same for a file made of several parts, written one after another without joining them
// (a large payload between a header and a trailer need not be copied).
Status writeFileAtomically(const std::string& path, std::initializer_list<std::span<const std::uint8_t>> parts);
Status writeFileAtomically(const std::string& path, std::span<const std::span<const std::uint8_t>> parts);

// Removes the temporary files writes in progress have open (for an interrupted process about to
// exit: core/interrupt.h). Their targets keep their old contents.
void removeTemporaryFiles();

}  // namespace lambert
