#include "puppet/viewer/script.h"

#include <algorithm>

namespace puppet::viewer {

std::optional<Script> parse_script(std::string_view name) {
  if (name == "hang") return Script::kHang;
  if (name == "drag") return Script::kDrag;
  if (name == "shake") return Script::kShake;
  return std::nullopt;
}

Vector2d ScriptPlayer::offset_at(int frame, const OrbitCamera& camera) {
  const double u = std::clamp(static_cast<double>(frame - kPressFrame) / kMoveFrames, 0.0, 1.0);
  const double s = u * u * (3.0 - 2.0 * u);
  return s * Vector2d(kDragOffset.x() * camera.width, kDragOffset.y() * camera.height);
}

void ScriptPlayer::before_frame(int frame, Controller& controller, const OrbitCamera& camera,
                                const Session& session) {
  if (script_ == Script::kHang || frame < kPressFrame) return;
  if (frame == kPressFrame) {
    // the hand: scenario drag's grab point, drawn a little towards the segment's centre so that
    // the ray meets its surface rather than grazing its outline
    const Model& model = session.model();
    const Pin hand = compare::make_scenario("drag", model).pins.back().pin;
    const BodyState& body = session.run(0).bodies[hand.segment];
    Vector2d pixel;
    if (!camera.project(body.x + body.q * (0.7 * hand.local_point), &pixel)) return;
    press_ = pixel;
    controller.press(Button::kLeft, pixel, false);
    return;
  }
  if (!press_) return;
  controller.move(*press_ + offset_at(frame, camera));
  if (script_ == Script::kShake && frame == kShakeFrame) controller.toggle_shake();
}

}  // namespace puppet::viewer
