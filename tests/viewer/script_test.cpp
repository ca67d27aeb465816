// The scripted mouse of headless runs, played without a window: the drag script grabs the hand
// and carries it by the scripted offset on screen.
#include "puppet/viewer/script.h"

#include <gtest/gtest.h>

namespace puppet::viewer {
namespace {

TEST(Script, Names) {
  EXPECT_EQ(parse_script("drag"), Script::kDrag);
  EXPECT_EQ(parse_script("shake"), Script::kShake);
  EXPECT_EQ(parse_script("hang"), Script::kHang);
  EXPECT_FALSE(parse_script("wave"));
}

// the scripts' drag checks the point is at the mouse: a pin holds it there
SessionConfig with_pin() {
  SessionConfig c;
  c.grab_pin = true;
  return c;
}

struct Played {
  Session session{with_pin()};
  OrbitCamera camera;
  Controller controller{camera, session};
  ScriptPlayer player;

  Played(Script script, int frames) : player(script) {
    camera.frame({-0.3, -0.3, 0.0}, {0.3, 0.3, 1.8});
    for (int frame = 0; frame < frames; ++frame) {
      player.before_frame(frame, controller, camera, session);
      session.advance(1.0 / 60.0, 100);
    }
  }
};

TEST(Script, DragCarriesTheHandByTheScriptedOffset) {
  Played played(Script::kDrag, 150);
  const Session& session = played.session;
  ASSERT_TRUE(session.grabbing());
  ASSERT_EQ(session.grabbed_segment(), session.model().find_segment("r_forearm"));
  // the grabbed point is where the mouse is: pressed pixel + offset
  const Pin& pin = session.pins()[session.grab_index()];
  const BodyState& b = session.run(0).bodies[pin.segment];
  Vector2d pixel;
  ASSERT_TRUE(played.camera.project(b.x + b.q * pin.local_point, &pixel));
  const Vector2d expected =
      *played.player.press_pixel() + ScriptPlayer::offset_at(150, played.camera);
  EXPECT_LE((pixel - expected).norm(), 3.0) << pixel.transpose() << " vs " << expected.transpose();
  EXPECT_FALSE(session.run(0).diverged);
}

TEST(Script, ShakeShakesAndHangDoesNothing) {
  Played shake(Script::kShake, 40);
  EXPECT_TRUE(shake.session.shaking());
  Played hang(Script::kHang, 40);
  EXPECT_FALSE(hang.session.grabbing());
  EXPECT_FALSE(hang.player.press_pixel());
}

}  // namespace
}  // namespace puppet::viewer
