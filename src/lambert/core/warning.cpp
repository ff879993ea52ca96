#include "lambert/core/warning.h"

#include <cstdio>
#include <mutex>

namespace lambert {
namespace {

std::mutex& sinkMutex() {
  static std::mutex mutex;
  return mutex;
}

WarningSink& currentSink() {
  static WarningSink sink;
  return sink;
}

}  // namespace

void warning(const std::string& message) {
  std::lock_guard<std::mutex> lock(sinkMutex());
  if (currentSink())
    currentSink()(message);
  else
    std::fprintf(stderr, "lambert: warning: %s\n", message.c_str());
}

WarningSink setWarningSink(WarningSink sink) {
  std::lock_guard<std::mutex> lock(sinkMutex());
  WarningSink previous = std::move(currentSink());
  currentSink() = std::move(sink);
  return previous;
}

}  // namespace lambert
