#include "puppet/viewer/controller.h"

namespace puppet::viewer {

void Controller::press(Button button, const Vector2d& pixel, bool shift) {
  if (held_) return;  // one gesture at a time
  held_ = button;
  last_ = pixel;
  if (shift || button == Button::kMiddle) {
    gesture_ = Gesture::kPan;
    return;
  }
  if (button == Button::kLeft) {
    const Hit hit = pick(session_.model(), session_.run(0).bodies, camera_.ray(pixel));
    if (hit.segment >= 0) {
      // the point stays under the mouse: it moves in the plane through it facing the camera
      plane_ = facing_plane(camera_, hit.world_point);
      session_.grab(hit.segment, hit.local_point, hit.world_point);
      gesture_ = Gesture::kGrab;
      return;
    }
  }
  gesture_ = Gesture::kOrbit;
}

void Controller::move(const Vector2d& pixel) {
  const Vector2d delta = pixel - last_;
  last_ = pixel;
  switch (gesture_) {
    case Gesture::kGrab:
      if (const auto target = plane_.intersect(camera_.ray(pixel))) session_.move_grab(*target);
      break;
    case Gesture::kOrbit:
      camera_.orbit(delta);
      break;
    case Gesture::kPan:
      camera_.pan(delta);
      break;
    case Gesture::kNone:
      break;
  }
}

void Controller::release(Button button) {
  if (!held_ || *held_ != button) return;
  if (gesture_ == Gesture::kGrab) session_.release();
  gesture_ = Gesture::kNone;
  held_.reset();
}

void Controller::toggle_shake() { session_.set_shake(!session_.shaking(), camera_.right()); }

}  // namespace puppet::viewer
