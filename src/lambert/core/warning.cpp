#include "lambert/core/warning.h"

#include <algorithm>
#include <cstdio>

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

void send(const WarningSink& sink, const std::string& message) {
  if (sink)
    sink(message);
  else
    std::fprintf(stderr, "lambert: warning: %s\n", message.c_str());
}

}  // namespace

void warning(const std::string& message) {
  std::lock_guard<std::mutex> lock(sinkMutex());
  send(currentSink(), message);
}

WarningSink setWarningSink(WarningSink sink) {
  std::lock_guard<std::mutex> lock(sinkMutex());
  WarningSink previous = std::move(currentSink());
  currentSink() = std::move(sink);
  return previous;
}

WarningCapture::WarningCapture(Forward forward) {
  // Swapped under the sink's lock, so a warning from another thread sees either the old sink or
  // this one with previous_ already set.
  std::lock_guard<std::mutex> lock(sinkMutex());
  previous_ = std::move(currentSink());
  currentSink() = [this, forward](const std::string& message) {
    bool first = false;
    {
      std::lock_guard<std::mutex> own(mutex_);
      messages_.push_back(message);
      first = forward == Forward::onceEach && forwarded_.insert(message).second;
    }
    if (forward == Forward::yes || first) send(previous_, message);
  };
}

WarningCapture::~WarningCapture() { setWarningSink(std::move(previous_)); }

std::vector<std::string> WarningCapture::messages() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return messages_;
}

int WarningCapture::count(const std::string& part) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(std::count_if(messages_.begin(), messages_.end(),
                                        [&](const std::string& m) { return m.find(part) != std::string::npos; }));
}

}  // namespace lambert
