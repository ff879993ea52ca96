#pragma once
// The interpreter of `lambert view --script` (viewer/script.h parses the file): it runs the
// commands at the start of a frame until one has to wait, and applies each to the viewer's state.
#include <cstddef>
#include <string>

#include "lambert/core/error.h"
#include "lambert/core/timer.h"
#include "viewer/script.h"
#include "viewer/viewer_state.h"

namespace lambert::viewer {

// Plays a Script: commands run at the start of a frame until one has to wait (frames to draw, a
// solution to arrive, a screenshot of this frame).
struct ScriptPlayer {
  enum class Waiting { None, Frames, Solution, Converged, Lightmaps, Probes };

  const Script* script = nullptr;  // null: no script, a user drives
  std::size_t next = 0, current = 0;
  Waiting waiting = Waiting::None;
  int framesLeft = 0;
  double timeout = 0;
  Timer waitTimer;

  bool active() const { return script != nullptr; }
  bool finished() const { return script && next >= script->lines.size() && waiting == Waiting::None; }
  // "file:line" of the command run last, for messages.
  std::string where() const { return script->path + ":" + std::to_string(script->lines.at(current).line); }
};

// Applies one script command; one that waits (frames, a solution) sets the player waiting, and a
// screenshot is taken when this frame is drawn.
Status applyCommand(const ScriptStep& step, ViewerState& state, ScriptPlayer& player, Screenshot& screenshot);

}  // namespace lambert::viewer
