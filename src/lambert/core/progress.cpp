#include "lambert/core/progress.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace lambert {
namespace {

std::int64_t nowMillis() {
  using namespace std::chrono;
  return duration_cast<milliseconds>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

bool Progress::terminalAttached() { return isatty(STDERR_FILENO) != 0; }

Progress::Progress(std::string label, std::uint64_t total, bool enabled)
    : label_(std::move(label)), total_(total), shown_(enabled && terminalAttached()) {}

Progress::~Progress() { finish(); }

void Progress::advance(std::uint64_t units) {
  std::uint64_t done = done_.fetch_add(units, std::memory_order_relaxed) + units;
  if (!shown_) return;
  std::int64_t now = nowMillis();
  std::int64_t last = lastDrawMillis_.load(std::memory_order_relaxed);
  // Redraw at most ten times a second, and let only one thread do it.
  if (now - last < 100 || !lastDrawMillis_.compare_exchange_strong(last, now)) return;
  draw(done, false);
}

void Progress::finish() {
  if (!shown_ || finished_) return;
  finished_ = true;
  draw(done_.load(), true);
}

void Progress::draw(std::uint64_t done, bool final) {
  std::lock_guard<std::mutex> lock(drawMutex_);
  if (total_ == 0) {  // open-ended work: the count so far
    std::fprintf(stderr, "\r%-14s %llu%s", label_.c_str(), static_cast<unsigned long long>(done), final ? "\n" : "");
    std::fflush(stderr);
    return;
  }
  double fraction = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  if (fraction > 1) fraction = 1;
  constexpr int kWidth = 30;
  int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "\r%-14s [%s] %5.1f%%%s", label_.c_str(), bar.c_str(), 100 * fraction,
               final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace lambert
