// The viewer's Dear ImGui panel: solver and ghost, scenario and model, the environment, time
// controls, and live plots of each run's max joint gap and µs per step.
#pragma once

#include <string>

#include "puppet/viewer/controller.h"
#include "puppet/viewer/session.h"

namespace puppet::viewer {

constexpr float kPanelWidth = 340.0f;

struct PanelState {
  bool paused = false;
  bool follow = true;  // the camera follows the figure's centre of mass [f]
  bool step_once = false;
  char model_path[512] = {};
  std::string error;  // why the last change was refused
};

// draws the panel at the window's right edge and applies what the user changes to the session
void draw_panel(Session& session, Controller& controller, PanelState& state, float window_width,
                float window_height);

}  // namespace puppet::viewer
