// Scripted mouse for headless runs (`viewer --frames N --script ...`): what a person would do,
// played through the same Controller, frame by frame, so a screenshot shows real interaction.
//
//   hang    nothing: the scenario alone
//   drag    at frame 5 press on the hand (the grab point of scenario `drag`), then over one second
//           move the mouse up and to the right by kDragOffset (a fraction of the window), and hold
//   shake   as drag, and from frame 20 shake the grabbed point
#pragma once

#include <optional>
#include <string_view>

#include "puppet/viewer/controller.h"

namespace puppet::viewer {

enum class Script { kHang, kDrag, kShake };

std::optional<Script> parse_script(std::string_view name);

class ScriptPlayer {
 public:
  static constexpr int kPressFrame = 5;
  static constexpr int kMoveFrames = 60;
  static constexpr int kShakeFrame = 20;
  // of the window's width and height; y grows downwards
  static inline const Vector2d kDragOffset{0.12, -0.12};

  explicit ScriptPlayer(Script script) : script_(script) {}

  // the mouse of this frame, before the frame is stepped and drawn
  void before_frame(int frame, Controller& controller, const OrbitCamera& camera,
                    const Session& session);
  // where the mouse pressed; nullopt before it did
  const std::optional<Vector2d>& press_pixel() const { return press_; }
  // the mouse's offset from where it pressed, at a frame (pixels)
  static Vector2d offset_at(int frame, const OrbitCamera& camera);

 private:
  Script script_;
  std::optional<Vector2d> press_;
};

}  // namespace puppet::viewer
