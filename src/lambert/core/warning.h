#pragma once
// The one place the library reports a problem it recovered from (a damaged cache file, a cache
// that could not be written, faces a loader dropped): "lambert: warning: <what>" on stderr, or
// wherever a program that embeds lambert sends them instead.
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace lambert {

// Reports one warning line (without the prefix or a newline). Thread-safe.
void warning(const std::string& message);

// Sends every later warning to sink instead of stderr (an empty function restores stderr);
// returns the previous sink. For programs with their own log, and for tests.
using WarningSink = std::function<void(const std::string& message)>;
WarningSink setWarningSink(WarningSink sink);

// Keeps every warning reported while it lives, and restores the previous sink when it goes.
// With Forward::yes each warning still reaches that previous sink (stderr by default) as well:
// the CLI keeps them for its --json output while a person still sees them as they come.
class WarningCapture {
 public:
  // no: kept only; yes: each also reaches the previous sink; onceEach: each distinct message
  // reaches it once (loads that read one file through several others: two OBJs sharing an MTL).
  enum class Forward { no, yes, onceEach };
  explicit WarningCapture(Forward forward = Forward::no);
  ~WarningCapture();
  WarningCapture(const WarningCapture&) = delete;
  WarningCapture& operator=(const WarningCapture&) = delete;

  std::vector<std::string> messages() const;
  // How many of them contain `part`.
  int count(const std::string& part) const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
  std::set<std::string> forwarded_;
  WarningSink previous_;
};

}  // namespace lambert
