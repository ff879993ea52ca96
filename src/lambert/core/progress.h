#pragma once
// A progress line for long work: redrawn in place on a terminal, silent otherwise (pipes, CI,
// --json). Safe to advance from many threads.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace lambert {

class Progress {
 public:
  // total: units of work (0: not known in advance, and the line shows the count done); a line
  // is shown only when enabled and stderr is a terminal.
  Progress(std::string label, std::uint64_t total, bool enabled = true);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::uint64_t units = 1);
  void finish();

  // Whether progress lines go to stderr at all (a terminal, and not switched off).
  static bool terminalAttached();

 private:
  void draw(std::uint64_t done, bool final);

  std::string label_;
  std::uint64_t total_;
  bool shown_;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<std::int64_t> lastDrawMillis_{-1000};
  std::mutex drawMutex_;
  bool finished_ = false;
};

}  // namespace lambert
