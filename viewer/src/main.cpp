// viewer: grab the puppet with the mouse and drag or shake it, in one solver or two side by side.
//
//   viewer [--model M] [--scenario S] [--solver S] [--rule R] [--ghost S] [--dt DT] ...
//   viewer --frames N --screenshot out.png [--script drag|shake|hang]   (headless, under xvfb-run)
//
// Bad input exits with status 2 and one line naming the flag or file; no window opens and nothing
// is written. A window that cannot open (no display) exits with status 1.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <stb_image_write.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "panel.h"
#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/text.h"
#include "puppet/viewer/script.h"
#include "renderer.h"

#ifdef __SANITIZE_ADDRESS__
// The OpenGL driver (Mesa) leaks at exit from inside modules it has already unloaded, where no
// suppression can name it. The viewer's own logic is leak-checked in the unit tests; here ASan's
// other checks and UBSan stay on.
extern "C" const char* __lsan_default_options() { return "detect_leaks=0"; }
#endif

namespace {

using namespace puppet;
using namespace puppet::viewer;

constexpr int kBadInput = 2;
constexpr int kNoWindow = 1;
constexpr double kFrameSeconds = 1.0 / 60.0;  // a headless frame's simulated time
constexpr double kMaxLagSeconds = 0.1;        // interactive: never fall further behind

// the controller holds references into the app: it is built in place and never moved
struct App {
  explicit App(const SessionConfig& config) : session(config) {}
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  Session session;
  OrbitCamera camera;
  Controller controller{camera, session};
  PanelState panel;
  const Model* framed = nullptr;  // the model the camera last framed
  bool input = true;              // false while a script or a headless run holds the mouse
};

// the model's box at rest, from each shape's extreme points along the world axes
void frame_model(App& app) {
  const Model& model = app.session.model();
  Vector3d low = Vector3d::Constant(1e300), high = Vector3d::Constant(-1e300);
  for (int s = 0; s < model.segment_count(); ++s) {
    const Segment& segment = model.segments[s];
    const BodyState& b = app.session.run(0).bodies[s];
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {-1.0, 1.0}) {
        const Vector3d d = sign * Vector3d::Unit(axis);
        const Vector3d p = b.x + b.q * support_point(segment, b.q.conjugate() * d);
        low = low.cwiseMin(p);
        high = high.cwiseMax(p);
      }
    }
  }
  app.camera.frame(low, high);
  app.framed = &model;
}

App& app_of(GLFWwindow* window) { return *static_cast<App*>(glfwGetWindowUserPointer(window)); }

Vector2d cursor(GLFWwindow* window) {
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window, &x, &y);
  return {x, y};
}

void on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
  App& app = app_of(window);
  if (!app.input) return;
  const Button b = button == GLFW_MOUSE_BUTTON_LEFT    ? Button::kLeft
                   : button == GLFW_MOUSE_BUTTON_RIGHT ? Button::kRight
                                                       : Button::kMiddle;
  if (action == GLFW_PRESS) {
    if (ImGui::GetIO().WantCaptureMouse) return;
    app.controller.press(b, cursor(window), (mods & GLFW_MOD_SHIFT) != 0);
  } else if (action == GLFW_RELEASE) {
    app.controller.release(b);
  }
}

void on_cursor(GLFWwindow* window, double x, double y) {
  App& app = app_of(window);
  if (app.input) app.controller.move({x, y});
}

void on_scroll(GLFWwindow* window, double /*x*/, double y) {
  App& app = app_of(window);
  if (app.input && !ImGui::GetIO().WantCaptureMouse) app.controller.scroll(y);
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  App& app = app_of(window);
  if (!app.input || action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  switch (key) {
    case GLFW_KEY_SPACE:
      app.panel.paused = !app.panel.paused;
      break;
    case GLFW_KEY_N:
      app.panel.step_once = true;
      break;
    case GLFW_KEY_R:
      app.session.reset();
      break;
    case GLFW_KEY_S:
      app.controller.toggle_shake();
      break;
    case GLFW_KEY_F:
      app.panel.follow = !app.panel.follow;
      break;
    case GLFW_KEY_ESCAPE:
      glfwSetWindowShouldClose(window, GLFW_TRUE);
      break;
    default:
      break;
  }
}

// encoded in memory, then written to a new name of its own and renamed (output.h): never half a
// file, and never through a link planted at the name or beside it
bool write_png(const std::string& path, int width, int height) {
  const std::vector<std::uint8_t> pixels = Renderer::read_pixels(width, height);
  std::string bytes;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<size_t>(size));
  };
  if (stbi_write_png_to_func(append, &bytes, width, height, 3, pixels.data(), width * 3) == 0) {
    return false;
  }
  try {
    compare::write_file_atomically(path, bytes);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

void on_glfw_error(int /*code*/, const char* description) {
  std::cerr << "viewer: " << description << '\n';
}

int run(App& app, int frames, const std::string& screenshot, std::optional<Script> script,
        int width, int height, int samples) {
  glfwSetErrorCallback(on_glfw_error);
  if (glfwInit() != GLFW_TRUE) {
    std::cerr << "viewer: cannot open a window (no display? run it under xvfb-run)\n";
    return kNoWindow;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, samples);
  GLFWwindow* window = glfwCreateWindow(width, height, "puppet viewer", nullptr, nullptr);
  if (window == nullptr) {
    std::cerr << "viewer: cannot create an OpenGL 3.3 window\n";
    glfwTerminate();
    return kNoWindow;
  }
  glfwMakeContextCurrent(window);
  const bool headless = frames > 0;
  app.input = !headless && !script;
  glfwSwapInterval(headless ? 0 : 1);
  glfwSetWindowUserPointer(window, &app);
  // ours first: Dear ImGui's callbacks chain to them
  glfwSetMouseButtonCallback(window, on_mouse_button);
  glfwSetCursorPosCallback(window, on_cursor);
  glfwSetScrollCallback(window, on_scroll);
  glfwSetKeyCallback(window, on_key);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330");

  int status = 0;
  {
    Renderer renderer;
    std::optional<ScriptPlayer> player;
    if (script) player.emplace(*script);
    double last = glfwGetTime();
    for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
      glfwPollEvents();
      // the scene fills the window left of the panel
      int window_width = 0, fb_width = 0, fb_height = 0;
      glfwGetWindowSize(window, &window_width, &app.camera.height);
      glfwGetFramebufferSize(window, &fb_width, &fb_height);
      app.camera.width = std::max(64, window_width - static_cast<int>(kPanelWidth) - 16);
      const int fb_scene_width = app.camera.width * fb_width / std::max(window_width, 1);
      if (app.framed != &app.session.model()) frame_model(app);
      if (player) player->before_frame(frame, app.controller, app.camera, app.session);

      // stepping: a headless frame is exactly 1/60 s; a live one follows the clock
      const double now = glfwGetTime();
      const double elapsed = std::min(now - last, kMaxLagSeconds);
      last = now;
      const int max_steps = static_cast<int>(std::ceil(kMaxLagSeconds / app.session.config().dt));
      if (headless) {
        app.session.advance(kFrameSeconds, 1 << 20);
      } else if (!app.panel.paused) {
        app.session.advance(elapsed, max_steps);
      }
      if (app.panel.step_once) {
        app.session.step();
        app.panel.step_once = false;
      }
      // the camera follows the first run's centre of mass, but not while a gesture holds the view
      if (app.panel.follow && !app.controller.holding()) {
        const double seconds = headless ? kFrameSeconds : elapsed;
        app.camera.follow(compare::centre_of_mass(app.session.model(), app.session.run(0).bodies),
                          seconds);
      }

      renderer.draw(app.session, app.camera, fb_scene_width, fb_height);
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      draw_panel(app.session, app.controller, app.panel, static_cast<float>(window_width),
                 static_cast<float>(app.camera.height));
      ImGui::Render();
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

      if (headless && frame + 1 == frames) {
        if (!screenshot.empty() && !write_png(screenshot, fb_width, fb_height)) {
          std::cerr << "viewer: --screenshot: cannot write " << screenshot << '\n';
          status = kBadInput;
        }
        break;
      }
      glfwSwapBuffers(window);
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"viewer: grab the puppet with the mouse, drag or shake it, solvers side by side"};
  SessionConfig config;
  std::string dt_text = "1/240", script_name, screenshot;
  int frames = 0, width = 1280, height = 720, samples = 4;
  app.add_option("--model", config.model, "pinocchio, a model file or chain:N")
      ->capture_default_str();
  // the names from the catalogues (scenario.h, engines.h), as the testbed's
  auto listed = [](const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
  };
  app.add_option("--scenario", config.scenario, listed(compare::scenario_names()))
      ->capture_default_str();
  app.add_option("--solver", config.solver, listed(compare::solver_names()))->capture_default_str();
  // the rule's name is read here, at the edge; the session holds a procedural::Rule
  std::vector<std::string> rule_names;
  for (const procedural::Rule rule : procedural::kAllRules) {
    rule_names.emplace_back(procedural::rule_name(rule));
  }
  std::string rule_text(procedural::rule_name(config.options.procedural.rule));
  app.add_option("--rule", rule_text,
                 "the procedural solver's adjust rule (default xpbd, the rule the verdict picks)")
      ->check(CLI::IsMember(rule_names))
      ->capture_default_str();
  app.add_option("--ghost", config.ghost, "a second solver, drawn as a translucent ghost");
  app.add_option("--anchor", config.anchor,
                 "the pin the procedural pass starts from while a point is held: auto, grab or "
                 "scenario")
      ->capture_default_str();
  app.add_option("--dt", dt_text, "time step (s); fractions such as 1/240 are accepted")
      ->capture_default_str();
  app.add_option("--substeps", config.options.procedural.substeps,
                 compare::procedural_substeps_help());
  app.add_option("--start", config.start,
                 "SEED:INDEX: a random start of testbed robustness (its worst.csv lists them)");
  app.add_option("--grab-hz", config.grab_spring.hz,
                 "the mouse's grab: the frequency f of its spring (the grab of drag, shake, "
                 "water and tremble)")
      ->capture_default_str();
  app.add_option("--grab-ratio", config.grab_spring.damping_ratio,
                 "the mouse's grab: its damping ratio")
      ->capture_default_str();
  app.add_option("--grab-cap", config.grab_spring.cap_weights,
                 "the mouse's grab: its force cap in the figure's weights")
      ->capture_default_str();
  app.add_flag("--grab-pin", config.grab_pin,
               "the mouse holds the point with a pin instead (--grab-compliance)");
  app.add_option("--grab-compliance", config.grab_compliance,
                 "with --grab-pin: 0 holds the point (default), C > 0 (m/N) pulls it with a "
                 "spring of stiffness 1/C")
      ->capture_default_str();
  app.add_option("--frames", frames, "headless: run this many frames of 1/60 s, then exit");
  app.add_option("--screenshot", screenshot, "headless: write the last frame to this PNG");
  app.add_option("--script", script_name, "a scripted mouse: drag, shake or hang");
  app.add_option("--width", width, "window width (pixels)")->capture_default_str();
  app.add_option("--height", height, "window height (pixels)")->capture_default_str();
  app.add_option("--msaa", samples, "multisample anti-aliasing: samples per pixel, 0 for none")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << one_line(std::string("viewer: ") + e.what(), 400) << '\n';
    return kBadInput;
  }
  config.options.procedural.rule = *procedural::parse_rule(rule_text);  // --rule checked it

  auto bad = [](const std::string& message) {
    std::cerr << one_line("viewer: " + message, 400) << '\n';
    return kBadInput;
  };
  // the testbed's range: a smaller step would take longer than a frame forever
  if (!compare::parse_finite(dt_text, &config.dt) || !(config.dt >= 1e-5 && config.dt <= 0.1)) {
    return bad("--dt: expected a step from 1e-5 to 0.1 s, got " + shown(dt_text));
  }
  if (frames < 0) return bad("--frames: must be ≥ 0");
  if (!screenshot.empty() && frames == 0) return bad("--screenshot: needs --frames N");
  if (width < 64 || height < 64 || width > 8192 || height > 8192) {
    return bad("--width/--height: must lie between 64 and 8192 pixels");
  }
  if (samples < 0 || samples > 16) return bad("--msaa: must lie between 0 and 16");
  std::optional<Script> script;
  if (!script_name.empty()) {
    script = parse_script(script_name);
    if (!script) return bad("--script: expected drag, shake or hang, got " + shown(script_name));
  }
  if (!screenshot.empty()) {
    if (std::string problem = compare::output_file_problem(screenshot); !problem.empty()) {
      return bad("--screenshot: " + shown(screenshot) + " " + problem);
    }
  }
  std::optional<App> state;
  try {
    state.emplace(config);
  } catch (const compare::ScenarioError& e) {
    // the session names the option; the command line adds its flag
    return bad(compare::with_flag(e));
  } catch (const std::exception& e) {
    return bad(e.what());
  }
  std::snprintf(state->panel.model_path, sizeof(state->panel.model_path), "%s",
                config.model.c_str());
  try {
    return run(*state, frames, screenshot, script, width, height, samples);
  } catch (const std::exception& e) {
    std::cerr << "viewer: " << e.what() << '\n';
    return kNoWindow;
  }
}
