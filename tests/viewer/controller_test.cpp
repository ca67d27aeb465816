// Mouse gestures: a press on the puppet grabs the point under it and the point then follows the
// mouse in the plane facing the camera; elsewhere the mouse moves the camera.
#include "puppet/viewer/controller.h"

#include <gtest/gtest.h>

namespace puppet::viewer {
namespace {

struct Fixture {
  Session session{SessionConfig{}};
  OrbitCamera camera;
  Controller controller{camera, session};

  Fixture() {
    camera.yaw = -M_PI / 2;  // looking along +y, the puppet's right side towards the eye
    camera.pitch = 0.0;
    camera.frame({-0.3, -0.3, 0.0}, {0.3, 0.3, 1.8});
  }
  Vector2d pixel_of(const Vector3d& p) const {
    Vector2d pixel;
    EXPECT_TRUE(camera.project(p, &pixel));
    return pixel;
  }
};

TEST(Controller, PressOnThePuppetGrabsThePointUnderTheMouse) {
  Fixture f;
  const int forearm = f.session.model().find_segment("r_forearm");
  const Vector2d pixel = f.pixel_of(f.session.run(0).bodies[forearm].x);
  f.controller.press(Button::kLeft, pixel, false);
  ASSERT_TRUE(f.session.grabbing());
  EXPECT_EQ(f.session.grabbed_segment(), forearm);
  // held where it was hit: on the forearm's surface nearest the eye, under the mouse
  const Vector3d held = f.session.grab_target();
  Vector2d held_pixel = f.pixel_of(held);
  EXPECT_LE((held_pixel - pixel).norm(), 1e-6);
  const BodyState& arm = f.session.run(0).bodies[forearm];
  const Shape& shape = f.session.model().segments[forearm].shapes[0];
  EXPECT_NEAR(signed_distance(shape, arm.q.conjugate() * (held - arm.x)), 0.0, 1e-9);
  EXPECT_LT((held - f.camera.eye()).norm(), (arm.x - f.camera.eye()).norm());

  // the target follows the mouse at the grabbed point's depth, in the plane facing the camera
  f.controller.move(pixel + Vector2d(50, -20));
  const Vector3d moved = f.session.grab_target();
  EXPECT_NEAR((moved - held).dot(f.camera.forward()), 0.0, 1e-9);
  const double depth = (held - f.camera.eye()).dot(f.camera.forward());
  const double m = f.camera.metres_per_pixel(depth);
  EXPECT_NEAR((moved - held).dot(f.camera.right()), 50 * m, 1e-9);
  EXPECT_NEAR((moved - held).dot(f.camera.up()), 20 * m, 1e-9);
  EXPECT_EQ(f.camera.yaw, -M_PI / 2);  // the camera stays

  f.controller.toggle_shake();
  EXPECT_TRUE(f.session.shaking());
  f.controller.release(Button::kLeft);
  EXPECT_FALSE(f.session.grabbing());
}

TEST(Controller, ElsewhereTheMouseOrbitsPansAndZooms) {
  Fixture f;
  // left press on empty sky: orbit, nothing grabbed
  f.controller.press(Button::kLeft, {5, 5}, false);
  f.controller.move({25, 5});
  EXPECT_FALSE(f.session.grabbing());
  EXPECT_NE(f.camera.yaw, -M_PI / 2);
  // a second button during a gesture is ignored; the release of the first ends it
  f.controller.press(Button::kRight, {25, 5}, false);
  f.controller.release(Button::kLeft);
  const double yaw = f.camera.yaw;
  f.controller.move({100, 5});
  EXPECT_EQ(f.camera.yaw, yaw);

  // shift+drag pans, even over the puppet
  const Vector3d target = f.camera.target;
  const int forearm = f.session.model().find_segment("r_forearm");
  const Vector2d on_arm = f.pixel_of(f.session.run(0).bodies[forearm].x);
  f.controller.press(Button::kLeft, on_arm, true);
  f.controller.move(on_arm + Vector2d(10, 0));
  f.controller.release(Button::kLeft);
  EXPECT_FALSE(f.session.grabbing());
  EXPECT_FALSE(f.camera.target.isApprox(target));

  const double distance = f.camera.distance;
  f.controller.scroll(2);
  EXPECT_NEAR(f.camera.distance, distance * 0.81, 1e-12);
}

}  // namespace
}  // namespace puppet::viewer
