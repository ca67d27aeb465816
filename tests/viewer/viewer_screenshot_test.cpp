// The viewer binary, headless under xvfb-run: its screenshots show the puppet, a scripted drag
// carries the grabbed hand across the screen by the script's offset, the ghost is drawn, and bad
// input exits with status 2 before a window opens or a file is written.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

// the viewer's defaults: a 1280 × 720 window whose right 356 pixels are the panel, and the drag
// script's offset, 12 % of the scene's width and height, up and to the right
constexpr int kWidth = 1280, kHeight = 720;
constexpr int kSceneWidth = 1280 - 356;
constexpr double kScriptDx = 0.12 * kSceneWidth, kScriptDy = -0.12 * kHeight;

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / "puppet_viewer_test";
  fs::create_directories(dir);
  return dir;
}

int viewer(const std::string& arguments, bool display = true) {
  const std::string command =
      std::string(display ? "xvfb-run -a -s '-screen 0 1280x720x24' " : "") + VIEWER_BINARY + " " +
      arguments + " >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

Image load(const fs::path& path) {
  Image image;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 3);
  if (data != nullptr) {
    image.rgb.assign(data, data + static_cast<size_t>(image.width) * image.height * 3);
    stbi_image_free(data);
  }
  return image;
}

// pixels of the scene (left of the panel) whose hue lies in [low, high] degrees, saturated and
// not dark: the lit surfaces of one colour, whatever the shading
struct Region {
  int count = 0;
  double x = 0.0, y = 0.0;  // centroid
};

Region hue_region(const Image& image, double low, double high) {
  Region r;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < kSceneWidth; ++x) {
      const unsigned char* p = &image.rgb[(static_cast<size_t>(y) * image.width + x) * 3];
      const double red = p[0] / 255.0, green = p[1] / 255.0, blue = p[2] / 255.0;
      const double max = std::max({red, green, blue}), min = std::min({red, green, blue});
      if (max < 0.12 || max - min < 0.3 * max) continue;
      double hue = 0.0;
      const double c = max - min;
      if (max == red) {
        hue = 60.0 * std::fmod((green - blue) / c + 6.0, 6.0);
      } else if (max == green) {
        hue = 60.0 * ((blue - red) / c + 2.0);
      } else {
        hue = 60.0 * ((red - green) / c + 4.0);
      }
      if (hue < low || hue > high) continue;
      ++r.count;
      r.x += x;
      r.y += y;
    }
  }
  if (r.count > 0) {
    r.x /= r.count;
    r.y /= r.count;
  }
  return r;
}

Region wood(const Image& image) { return hue_region(image, 15.0, 45.0); }
Region grabbed(const Image& image) { return hue_region(image, 290.0, 330.0); }
Region ghost(const Image& image) { return hue_region(image, 200.0, 230.0); }

TEST(ViewerScreenshot, AScriptedDragCarriesTheHand) {
  const fs::path before = scratch() / "drag_start.png", after = scratch() / "drag_end.png";
  fs::remove(before);
  fs::remove(after);
  // frame 5 presses on the hand; by frame 90 the mouse has moved and the hand followed
  ASSERT_EQ(viewer("--frames 6 --script drag --screenshot " + before.string()), 0);
  ASSERT_EQ(viewer("--frames 90 --script drag --screenshot " + after.string()), 0);
  const Image a = load(before), b = load(after);
  ASSERT_EQ(a.width, kWidth);
  ASSERT_EQ(a.height, kHeight);
  ASSERT_EQ(b.width, kWidth);

  // the puppet is there: thousands of wood-coloured pixels, the held forearm among them
  EXPECT_GT(wood(a).count, 5000);
  EXPECT_GT(wood(b).count, 5000);
  const Region hand_a = grabbed(a), hand_b = grabbed(b);
  ASSERT_GT(hand_a.count, 100);
  ASSERT_GT(hand_b.count, 100);
  // and it moved with the mouse: the script's offset, give or take the forearm turning about
  // the held point
  const double dx = hand_b.x - hand_a.x, dy = hand_b.y - hand_a.y;
  const double moved = std::hypot(dx, dy), scripted = std::hypot(kScriptDx, kScriptDy);
  EXPECT_GT(moved, 0.6 * scripted) << dx << ", " << dy;
  EXPECT_LT(moved, 1.4 * scripted) << dx << ", " << dy;
  EXPECT_GT((dx * kScriptDx + dy * kScriptDy) / (moved * scripted), 0.9) << dx << ", " << dy;
}

TEST(ViewerScreenshot, TheGhostIsDrawnBesideTheSolver) {
  const fs::path path = scratch() / "ghost.png";
  fs::remove(path);
  ASSERT_EQ(
      viewer("--frames 30 --script shake --ghost bullet-multibody --screenshot " + path.string()),
      0);
  const Image image = load(path);
  EXPECT_GT(wood(image).count, 5000);
  EXPECT_GT(ghost(image).count, 500);
  // without a ghost there is no ghost colour in the scene
  ASSERT_EQ(viewer("--frames 2 --screenshot " + path.string()), 0);
  EXPECT_LT(ghost(load(path)).count, 50);
}

TEST(ViewerScreenshot, BadInputExitsTwoAndWritesNothing) {
  const fs::path path = scratch() / "never.png";
  fs::remove(path);
  for (const std::string arguments :
       {"--dt 0", "--dt nan", "--frames -1", "--script wave", "--solver physx", "--ghost havok",
        "--rule fastest", "--model /nonexistent/model.json", "--scenario float", "--width 10",
        "--msaa 17", "--anchor head", "--frames 2 --bogus", "--dt 1e-300", "--dt 1/3/4",
        "--model /dev/zero", "--model chain:150 --solver mujoco"}) {
    EXPECT_EQ(viewer(arguments + " --frames 2 --screenshot " + path.string(), false), 2)
        << arguments;
  }
  EXPECT_EQ(viewer("--screenshot " + path.string(), false), 2);  // needs --frames
  EXPECT_EQ(viewer("--frames 2 --screenshot /nonexistent/dir/out.png", false), 2);
  EXPECT_FALSE(fs::exists(path));
  // a link planted at the screenshot's name is never written through
  const fs::path victim = scratch() / "victim.txt";
  const fs::path link = scratch() / "linked.png";
  fs::remove(link);
  std::ofstream(victim) << "victim";
  fs::create_symlink(victim, link);
  EXPECT_EQ(viewer("--frames 2 --screenshot " + link.string(), false), 2);
  std::ifstream in(victim);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), {}), "victim");
  fs::remove(link);
}

}  // namespace
