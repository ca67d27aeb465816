// Draws a session with OpenGL 3.3 core: the model's shapes lit from above, the ghost translucent,
// the ground grid, joint markers coloured by their gap, the pins, and the water surface.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "gl.h"
#include "puppet/viewer/camera.h"
#include "puppet/viewer/session.h"

namespace puppet::viewer {

using Eigen::Vector3f;
using Eigen::Vector4f;

// colours shared by the scene and the panel
struct Palette {
  static inline const Vector3f kBackground{0.16f, 0.17f, 0.20f};
  static inline const Vector3f kUnderWater{0.09f, 0.20f, 0.33f};  // the eye below the surface
  static inline const Vector3f kWood{0.86f, 0.60f, 0.34f};        // the solver's puppet
  static inline const Vector3f kGrabbed{0.90f, 0.18f, 0.78f};     // the segment held by the mouse
  static inline const Vector3f kGhost{0.35f, 0.62f, 1.00f};       // the second solver
  static inline const Vector3f kPin{0.30f, 0.95f, 0.95f};
  static constexpr float kGhostAlpha = 0.35f;
};

// green for a closed joint, through yellow at 1 mm, to red from 1 cm (log scale from 0.1 mm)
Vector3f gap_colour(double gap_m);

class Renderer {
 public:
  // needs a current OpenGL 3.3 context; throws std::runtime_error when a shader fails
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // clears the framebuffer and draws the scene into its left `width` × `height` pixels
  void draw(const Session& session, const OrbitCamera& camera, int framebuffer_width,
            int framebuffer_height);
  // the framebuffer as RGB rows, top row first
  static std::vector<std::uint8_t> read_pixels(int width, int height);

 private:
  struct Mesh {
    GLuint vao = 0, vbo = 0;
    GLsizei vertex_count = 0;
  };
  struct LineVertex {
    float x, y, z, r, g, b, a;
  };

  Mesh upload(const std::vector<float>& position_normal);
  void draw_mesh(const Mesh& mesh, const Eigen::Matrix4f& model, const Vector4f& colour);
  void draw_model(const Model& model, std::span<const BodyState> bodies, int grabbed,
                  const Vector3f& colour, float alpha);
  void add_line(const Vector3d& a, const Vector3d& b, const Vector4f& colour);
  void flush_lines(GLenum mode);

  GLuint lit_program_ = 0, line_program_ = 0;
  GLint u_model_ = -1, u_normal_ = -1, u_view_projection_ = -1, u_colour_ = -1, u_light_ = -1,
        u_eye_ = -1, u_line_view_projection_ = -1;
  Mesh sphere_, cylinder_, disc_, cube_, quad_;
  GLuint line_vao_ = 0, line_vbo_ = 0;
  std::vector<LineVertex> lines_;
  Eigen::Matrix4f view_projection_ = Eigen::Matrix4f::Identity();  // of the frame being drawn
};

}  // namespace puppet::viewer
