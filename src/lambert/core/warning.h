#pragma once
// The one place the library reports a problem it recovered from (a damaged cache file, a cache
// that could not be written): "lambert: warning: <what>" on stderr, or wherever a program that
// embeds lambert sends them instead.
#include <functional>
#include <string>

namespace lambert {

// Reports one warning line (without the prefix or a newline). Thread-safe.
void warning(const std::string& message);

// Sends every later warning to sink instead of stderr (an empty function restores stderr);
// returns the previous sink. For programs with their own log, and for tests.
using WarningSink = std::function<void(const std::string& message)>;
WarningSink setWarningSink(WarningSink sink);

}  // namespace lambert
