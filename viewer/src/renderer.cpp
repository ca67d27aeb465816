#include "renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "puppet/model/euler_box.h"

namespace puppet::viewer {
namespace {

using Eigen::Affine3f;
using Eigen::Matrix3f;
using Eigen::Matrix4f;

constexpr char kLitVertex[] = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat3 u_normal;
uniform mat4 u_view_projection;
out vec3 v_normal;
out vec3 v_world;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal * a_normal;
  gl_Position = u_view_projection * world;
})";

// a hemisphere ambient (sky above, floor below), one sun, a little specular
constexpr char kLitFragment[] = R"(#version 330 core
in vec3 v_normal;
in vec3 v_world;
uniform vec4 u_colour;
uniform vec3 u_light;
uniform vec3 u_eye;
out vec4 frag;
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float sun = max(dot(n, u_light), 0.0);
  float sky = 0.5 + 0.5 * n.z;
  vec3 h = normalize(u_light + normalize(u_eye - v_world));
  float specular = 0.18 * pow(max(dot(n, h), 0.0), 48.0);
  frag = vec4(u_colour.rgb * (0.22 + 0.28 * sky + 0.62 * sun) + vec3(specular), u_colour.a);
})";

constexpr char kLineVertex[] = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_colour;
uniform mat4 u_view_projection;
out vec4 v_colour;
void main() {
  v_colour = a_colour;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
})";

constexpr char kLineFragment[] = R"(#version 330 core
in vec4 v_colour;
out vec4 frag;
void main() { frag = v_colour; })";

GLuint compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    throw std::runtime_error(std::string("shader: ") + log);
  }
  return shader;
}

GLuint link(const char* vertex, const char* fragment) {
  const GLuint program = glCreateProgram();
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex), fs = compile(GL_FRAGMENT_SHADER, fragment);
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetProgramInfoLog(program, sizeof(log), nullptr, log);
    throw std::runtime_error(std::string("shader program: ") + log);
  }
  return program;
}

// triangles as (position, normal) pairs
void vertex(std::vector<float>& out, const Vector3f& p, const Vector3f& n) {
  out.insert(out.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
}

// the unit sphere
std::vector<float> sphere_triangles(int slices, int stacks) {
  std::vector<float> out;
  auto at = [&](int i, int j) {
    const double theta = M_PI * i / stacks, phi = 2.0 * M_PI * j / slices;
    return Vector3f(static_cast<float>(std::sin(theta) * std::cos(phi)),
                    static_cast<float>(std::sin(theta) * std::sin(phi)),
                    static_cast<float>(std::cos(theta)));
  };
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      const Vector3f a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      for (const Vector3f& p : {a, b, c, a, c, d}) vertex(out, p, p);
    }
  }
  return out;
}

// the side of the cylinder of radius 1 from z = −1 to 1
std::vector<float> cylinder_triangles(int slices) {
  std::vector<float> out;
  for (int j = 0; j < slices; ++j) {
    const double p0 = 2.0 * M_PI * j / slices, p1 = 2.0 * M_PI * (j + 1) / slices;
    const Vector3f n0(static_cast<float>(std::cos(p0)), static_cast<float>(std::sin(p0)), 0.0f);
    const Vector3f n1(static_cast<float>(std::cos(p1)), static_cast<float>(std::sin(p1)), 0.0f);
    const Vector3f lo(0, 0, -1), hi(0, 0, 1);
    vertex(out, n0 + lo, n0);
    vertex(out, n1 + lo, n1);
    vertex(out, n1 + hi, n1);
    vertex(out, n0 + lo, n0);
    vertex(out, n1 + hi, n1);
    vertex(out, n0 + hi, n0);
  }
  return out;
}

// the unit disc at z = 0, facing +z (scaled by −1 in z it faces down)
std::vector<float> disc_triangles(int slices) {
  std::vector<float> out;
  const Vector3f n(0, 0, 1);
  for (int j = 0; j < slices; ++j) {
    const double p0 = 2.0 * M_PI * j / slices, p1 = 2.0 * M_PI * (j + 1) / slices;
    vertex(out, Vector3f::Zero(), n);
    vertex(out, Vector3f(static_cast<float>(std::cos(p0)), static_cast<float>(std::sin(p0)), 0), n);
    vertex(out, Vector3f(static_cast<float>(std::cos(p1)), static_cast<float>(std::sin(p1)), 0), n);
  }
  return out;
}

// the cube [−1, 1]³ with a normal per face
std::vector<float> cube_triangles() {
  std::vector<float> out;
  for (int axis = 0; axis < 3; ++axis) {
    for (const float sign : {-1.0f, 1.0f}) {
      Vector3f n = Vector3f::Zero();
      n[axis] = sign;
      const Vector3f u = Vector3f::Unit((axis + 1) % 3), v = Vector3f::Unit((axis + 2) % 3);
      // counter-clockwise seen from outside
      const Vector3f a = n - u - v, b = n + u - v, c = n + u + v, d = n - u + v;
      if (sign > 0) {
        for (const Vector3f& p : {a, b, c, a, c, d}) vertex(out, p, n);
      } else {
        for (const Vector3f& p : {a, c, b, a, d, c}) vertex(out, p, n);
      }
    }
  }
  return out;
}

// the square [−1, 1]² at z = 0, facing up
std::vector<float> quad_triangles() {
  std::vector<float> out;
  const Vector3f n(0, 0, 1);
  for (const Vector3f& p : {Vector3f(-1, -1, 0), Vector3f(1, -1, 0), Vector3f(1, 1, 0),
                            Vector3f(-1, -1, 0), Vector3f(1, 1, 0), Vector3f(-1, 1, 0)}) {
    vertex(out, p, n);
  }
  return out;
}

Matrix4f pose(const BodyState& body) {
  Affine3f t = Affine3f::Identity();
  t.translate(body.x.cast<float>());
  t.rotate(body.q.cast<float>());
  return t.matrix();
}

Matrix4f translation_scale(const Vector3f& at, const Vector3f& scale) {
  Affine3f t = Affine3f::Identity();
  t.translate(at);
  t.scale(scale);
  return t.matrix();
}

Vector4f with_alpha(const Vector3f& c, float a) { return {c.x(), c.y(), c.z(), a}; }

}  // namespace

Vector3f gap_colour(double gap_m) {
  const Vector3f green(0.25f, 0.85f, 0.30f), yellow(0.95f, 0.85f, 0.20f), red(0.95f, 0.20f, 0.15f);
  // 0 at 0.1 mm, 1 at 1 mm, 2 at 1 cm
  const double u = std::clamp(std::log10(std::max(gap_m, 1e-12) / 1e-4), 0.0, 2.0);
  if (u <= 1.0) return green + static_cast<float>(u) * (yellow - green);
  return yellow + static_cast<float>(u - 1.0) * (red - yellow);
}

Renderer::Renderer() {
  lit_program_ = link(kLitVertex, kLitFragment);
  line_program_ = link(kLineVertex, kLineFragment);
  u_model_ = glGetUniformLocation(lit_program_, "u_model");
  u_normal_ = glGetUniformLocation(lit_program_, "u_normal");
  u_view_projection_ = glGetUniformLocation(lit_program_, "u_view_projection");
  u_colour_ = glGetUniformLocation(lit_program_, "u_colour");
  u_light_ = glGetUniformLocation(lit_program_, "u_light");
  u_eye_ = glGetUniformLocation(lit_program_, "u_eye");
  u_line_view_projection_ = glGetUniformLocation(line_program_, "u_view_projection");
  sphere_ = upload(sphere_triangles(32, 16));
  cylinder_ = upload(cylinder_triangles(32));
  disc_ = upload(disc_triangles(32));
  cube_ = upload(cube_triangles());
  quad_ = upload(quad_triangles());

  glGenVertexArrays(1, &line_vao_);
  glGenBuffers(1, &line_vbo_);
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
}

Renderer::~Renderer() {
  for (Mesh* mesh : {&sphere_, &cylinder_, &cube_, &quad_}) {
    glDeleteBuffers(1, &mesh->vbo);
    glDeleteVertexArrays(1, &mesh->vao);
  }
  glDeleteBuffers(1, &line_vbo_);
  glDeleteVertexArrays(1, &line_vao_);
  glDeleteProgram(lit_program_);
  glDeleteProgram(line_program_);
}

Renderer::Mesh Renderer::upload(const std::vector<float>& position_normal) {
  Mesh mesh;
  mesh.vertex_count = static_cast<GLsizei>(position_normal.size() / 6);
  glGenVertexArrays(1, &mesh.vao);
  glGenBuffers(1, &mesh.vbo);
  glBindVertexArray(mesh.vao);
  glBindBuffer(GL_ARRAY_BUFFER, mesh.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(position_normal.size() * sizeof(float)),
               position_normal.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  return mesh;
}

void Renderer::draw_mesh(const Mesh& mesh, const Matrix4f& model, const Vector4f& colour) {
  const Matrix3f normal = model.topLeftCorner<3, 3>().inverse().transpose();
  glUniformMatrix4fv(u_model_, 1, GL_FALSE, model.data());
  glUniformMatrix3fv(u_normal_, 1, GL_FALSE, normal.data());
  glUniform4fv(u_colour_, 1, colour.data());
  glBindVertexArray(mesh.vao);
  glDrawArrays(GL_TRIANGLES, 0, mesh.vertex_count);
}

void Renderer::draw_model(const Model& model, std::span<const BodyState> bodies, int grabbed,
                          const Vector3f& colour, float alpha) {
  for (int s = 0; s < model.segment_count(); ++s) {
    const Vector4f c = with_alpha(s == grabbed ? Palette::kGrabbed : colour, alpha);
    for (const Shape& shape : model.segments[s].shapes) {
      // the shape's own frame: the segment's, then the shape's place in it
      Affine3f placed = Affine3f::Identity();
      placed.translate(shape.position.cast<float>());
      placed.rotate(shape.orientation.cast<float>());
      const Matrix4f frame = pose(bodies[s]) * placed.matrix();
      const float r = static_cast<float>(shape.radius);
      switch (shape.type) {
        case ShapeType::kSphere:
          draw_mesh(sphere_, frame * translation_scale(Vector3f::Zero(), Vector3f::Constant(r)), c);
          break;
        case ShapeType::kCapsule: {
          const float h = static_cast<float>(shape.half_length);
          draw_mesh(cylinder_, frame * translation_scale(Vector3f::Zero(), Vector3f(r, r, h)), c);
          draw_mesh(sphere_, frame * translation_scale(Vector3f(0, 0, h), Vector3f::Constant(r)),
                    c);
          draw_mesh(sphere_, frame * translation_scale(Vector3f(0, 0, -h), Vector3f::Constant(r)),
                    c);
          break;
        }
        case ShapeType::kBox:
          draw_mesh(cube_,
                    frame * translation_scale(Vector3f::Zero(), shape.half_extents.cast<float>()),
                    c);
          break;
        case ShapeType::kCylinder: {
          const float h = static_cast<float>(shape.half_length);
          draw_mesh(cylinder_, frame * translation_scale(Vector3f::Zero(), Vector3f(r, r, h)), c);
          draw_mesh(disc_, frame * translation_scale(Vector3f(0, 0, h), Vector3f(r, r, 1)), c);
          draw_mesh(disc_, frame * translation_scale(Vector3f(0, 0, -h), Vector3f(r, r, -1)), c);
          break;
        }
        case ShapeType::kEllipsoid:
          draw_mesh(sphere_,
                    frame * translation_scale(Vector3f::Zero(), shape.half_extents.cast<float>()),
                    c);
          break;
      }
    }
  }
}

void Renderer::add_line(const Vector3d& a, const Vector3d& b, const Vector4f& c) {
  for (const Vector3d& p : {a, b}) {
    lines_.push_back({static_cast<float>(p.x()), static_cast<float>(p.y()),
                      static_cast<float>(p.z()), c.x(), c.y(), c.z(), c.w()});
  }
}

void Renderer::flush_lines(GLenum mode) {
  if (lines_.empty()) return;
  glUseProgram(line_program_);
  glUniformMatrix4fv(u_line_view_projection_, 1, GL_FALSE, view_projection_.data());
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines_.size() * sizeof(LineVertex)),
               lines_.data(), GL_STREAM_DRAW);
  glDrawArrays(mode, 0, static_cast<GLsizei>(lines_.size()));
  lines_.clear();
}

void Renderer::draw(const Session& session, const OrbitCamera& camera, int framebuffer_width,
                    int framebuffer_height) {
  const Model& model = session.model();
  const Environment& environment = session.scenario().environment;
  view_projection_ = (camera.projection() * camera.view()).cast<float>();
  const Matrix4f& view_projection = view_projection_;
  const Vector3f light = Vector3f(0.35f, -0.45f, 1.0f).normalized();
  const Vector3f eye = camera.eye().cast<float>();

  glViewport(0, 0, framebuffer_width, framebuffer_height);
  // below the water surface everything is seen through water
  const bool under_water = environment.water && camera.eye().z() < environment.water_level;
  const Vector3f background = under_water ? Palette::kUnderWater : Palette::kBackground;
  glClearColor(background.x(), background.y(), background.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);

  glUseProgram(lit_program_);
  glUniformMatrix4fv(u_view_projection_, 1, GL_FALSE, view_projection.data());
  glUniform3fv(u_light_, 1, light.data());
  glUniform3fv(u_eye_, 1, eye.data());

  // the ground, a little below z = 0 so the grid stays on top
  constexpr float kFloorHalf = 5.0f;
  if (environment.ground) {
    draw_mesh(quad_, translation_scale({0, 0, -0.002f}, {kFloorHalf, kFloorHalf, 1}),
              {0.30f, 0.31f, 0.33f, 1.0f});
  }
  const Run& solver = session.run(0);
  draw_model(model, solver.bodies, session.grabbed_segment(), Palette::kWood, 1.0f);

  // the grid on z = 0: a line every 0.25 m, brighter every metre
  for (int i = -20; i <= 20; ++i) {
    const double u = 0.25 * i;
    const Vector4f c =
        i % 4 == 0 ? Vector4f(0.46f, 0.47f, 0.50f, 1.0f) : Vector4f(0.30f, 0.31f, 0.34f, 1.0f);
    add_line({u, -kFloorHalf, 0}, {u, kFloorHalf, 0}, c);
    add_line({-kFloorHalf, u, 0}, {kFloorHalf, u, 0}, c);
  }
  // each pin: from the point it holds to its target
  const auto pins = session.pins();
  const auto targets = session.targets();
  for (size_t i = 0; i < pins.size() && i < targets.size(); ++i) {
    const BodyState& b = solver.bodies[pins[i].segment];
    add_line(b.x + b.q * pins[i].local_point, targets[i], with_alpha(Palette::kPin, 1.0f));
  }
  flush_lines(GL_LINES);

  // translucent things last, without writing depth: the ghosts, then the water
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);  // each translucent surface blended once
  glUseProgram(lit_program_);
  for (int r = 1; r < session.run_count(); ++r) {
    draw_model(model, session.run(r).bodies, -1, Palette::kGhost, Palette::kGhostAlpha);
  }
  glDisable(GL_CULL_FACE);
  if (environment.water) {
    draw_mesh(quad_,
              translation_scale({0, 0, static_cast<float>(environment.water_level)},
                                {kFloorHalf, kFloorHalf, 1}),
              {0.20f, 0.45f, 0.85f, 0.30f});
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);

  // markers on top of everything: a joint hides inside its segments
  glDisable(GL_DEPTH_TEST);
  for (int j = 0; j < model.joint_count(); ++j) {
    const Joint& joint = model.joints[j];
    const BodyState &parent = solver.bodies[joint.parent], &child = solver.bodies[joint.child];
    const Vector3d at = parent.x + parent.q * parent_anchor(joint, parent.q, child.q);
    draw_mesh(sphere_, translation_scale(at.cast<float>(), Vector3f::Constant(0.014f)),
              with_alpha(gap_colour(solver.joint_gaps[j]), 1.0f));
  }
  for (size_t i = 0; i < targets.size(); ++i) {
    draw_mesh(sphere_, translation_scale(targets[i].cast<float>(), Vector3f::Constant(0.012f)),
              with_alpha(Palette::kPin, 1.0f));
  }
  glEnable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

std::vector<std::uint8_t> Renderer::read_pixels(int width, int height) {
  std::vector<std::uint8_t> pixels(static_cast<size_t>(width) * height * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // OpenGL's rows start at the bottom
  const size_t row = static_cast<size_t>(width) * 3;
  for (int y = 0; y < height / 2; ++y) {
    std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row,
                     pixels.begin() + (height - 1 - y) * row);
  }
  return pixels;
}

}  // namespace puppet::viewer
