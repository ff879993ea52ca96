#include "viewer/viewer_state.h"

namespace lambert::viewer {

void setPlaying(LightAnimation& animation, bool playing) {
  const double now = steadyClockSeconds();
  animation.seconds = animation.secondsAt(now);
  animation.setAt = now;
  animation.playing = playing;
}

}  // namespace lambert::viewer
