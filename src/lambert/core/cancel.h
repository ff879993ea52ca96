#pragma once
// Cooperative cancellation, for a program that embeds the library and takes interrupts itself
// (the Python module, on Ctrl-C; the CLI ends the process instead, core/interrupt.h). The program
// asks; long work stops at its next unit by throwing Cancelled out of the call that runs it:
// every parallelFor chunk (core/parallel.h: link estimates, final gathers, bakes, pictures) and
// every solver sweep or batch of shots checks. Process-wide: one request stops every long call
// running in the process, until it is cleared.
//
// What a cancelled call leaves: nothing it would have returned or cached; objects it was
// changing may be part-way (a solve's hierarchy half refined), so a caller starts that work
// afresh (the Python module makes the engine again before the next solve).
#include <atomic>
#include <stdexcept>

namespace lambert {

class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

namespace detail {
inline std::atomic<bool>& cancelFlag() {
  static std::atomic<bool> flag{false};
  return flag;
}
}  // namespace detail

inline void requestCancel() { detail::cancelFlag().store(true, std::memory_order_relaxed); }
inline void clearCancel() { detail::cancelFlag().store(false, std::memory_order_relaxed); }
inline bool cancelRequested() { return detail::cancelFlag().load(std::memory_order_relaxed); }
// Throws Cancelled where a cancel was requested: call between units of long work.
inline void throwIfCancelled() {
  if (cancelRequested()) throw Cancelled();
}

}  // namespace lambert
