// What the mouse and keys mean: the one place a gesture turns into a camera move or a grab, used
// by the window and by scripted runs alike, and tested without a window.
//
//   left-drag on the puppet   grab the point under the mouse; it follows the mouse in the plane
//                             facing the camera; release lets go
//   left-drag elsewhere, right-drag   orbit
//   middle-drag, shift+drag   pan
//   wheel                     zoom
#pragma once

#include <optional>

#include "puppet/viewer/camera.h"
#include "puppet/viewer/picking.h"
#include "puppet/viewer/session.h"

namespace puppet::viewer {

enum class Button { kLeft, kRight, kMiddle };

class Controller {
 public:
  Controller(OrbitCamera& camera, Session& session) : camera_(camera), session_(session) {}

  void press(Button button, const Vector2d& pixel, bool shift);
  void move(const Vector2d& pixel);
  void release(Button button);
  void scroll(double steps) { camera_.zoom(steps); }
  // the grabbed point oscillates along the camera's right axis, or stops
  void toggle_shake();
  // a gesture holds the view (a grab's drag plane, an orbit, a pan): the camera keeps still
  bool holding() const { return gesture_ != Gesture::kNone; }

 private:
  enum class Gesture { kNone, kGrab, kOrbit, kPan };

  OrbitCamera& camera_;
  Session& session_;
  Gesture gesture_ = Gesture::kNone;
  std::optional<Button> held_;
  Vector2d last_{0, 0};
  DragPlane plane_;
};

}  // namespace puppet::viewer
