#include "puppet/compare/truth_cache.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "puppet/compare/output.h"
#include "puppet/model/file.h"

namespace puppet::compare {
namespace {

// the bytes a key is the checksum of: every value in a fixed layout, strings with their length
class KeyBytes {
 public:
  KeyBytes& add(const std::string& text) {
    add(static_cast<int64_t>(text.size()));
    bytes_ += text;
    return *this;
  }
  KeyBytes& add(const char* text) { return add(std::string(text)); }
  KeyBytes& add(double value) { return raw(value); }
  KeyBytes& add(int64_t value) { return raw(value); }
  KeyBytes& add(int value) { return raw(static_cast<int64_t>(value)); }
  KeyBytes& add(bool value) { return raw(static_cast<int64_t>(value)); }
  KeyBytes& add(const Vector3d& v) { return add(v.x()).add(v.y()).add(v.z()); }
  KeyBytes& add(const Quaterniond& q) { return add(q.w()).add(q.x()).add(q.y()).add(q.z()); }
  template <typename Enum>
  requires std::is_enum_v<Enum> KeyBytes& add(Enum value) {
    return add(static_cast<int64_t>(value));
  }
  const std::string& bytes() const { return bytes_; }

 private:
  template <typename T>
  KeyBytes& raw(T value) {
    char buffer[sizeof(T)];
    std::memcpy(buffer, &value, sizeof(T));
    bytes_.append(buffer, sizeof(T));
    return *this;
  }
  std::string bytes_;
};

void add_state(KeyBytes& key, const BodyState& body) {
  key.add(body.x).add(body.q).add(body.v).add(body.w);
}

void add_model(KeyBytes& key, const Model& model) {
  key.add(model.name).add(model.total_mass).add(model.rest_height).add(model.gravity);
  key.add(model.segment_count());
  for (const Segment& s : model.segments) {
    key.add(s.name).add(s.mass).add(s.inertia).add(s.inv_mass).add(s.inv_inertia);
    // a lone shape at the segment's origin adds what one shape always added (keys of such
    // models are unchanged); more shapes, or one placed elsewhere, add their count and places
    for (const Shape& shape : s.shapes) {
      key.add(shape.type).add(shape.radius).add(shape.half_length).add(shape.half_extents);
    }
    if (!lone_shape(s)) {
      key.add(static_cast<int>(s.shapes.size()));
      for (const Shape& shape : s.shapes) key.add(shape.position).add(shape.orientation);
    }
    key.add(s.rest_position).add(s.rest_orientation).add(s.parent_joint).add(s.parent);
  }
  key.add(model.joint_count());
  for (const Joint& j : model.joints) {
    key.add(j.name).add(j.type).add(j.parent).add(j.child);
    key.add(j.anchor_world).add(j.anchor_in_parent).add(j.anchor_in_child);
    key.add(j.frame_in_parent).add(j.frame_in_child).add(j.frame_world);
    key.add(j.ball_limit).add(j.swing_x).add(j.swing_y).add(j.twist);
    for (const int axis : j.box_order.axes) key.add(axis);
    key.add(j.box_lower).add(j.box_upper).add(j.hinge_axis).add(j.lower).add(j.upper);
    key.add(j.twist_half_sin).add(j.twist_half_cos).add(j.lower_half_sin);
    key.add(j.lower_half_cos).add(j.upper_half_sin).add(j.upper_half_cos);
  }
}

void add_scenario(KeyBytes& key, const Scenario& scenario) {
  const Environment& e = scenario.environment;
  key.add(scenario.name).add(scenario.duration);
  key.add(e.gravity).add(e.air_drag).add(e.water).add(e.water_level).add(e.water_density);
  key.add(e.water_drag).add(e.ground).add(e.friction).add(e.tremble);
  key.add(static_cast<int64_t>(e.tremble_seed));
  key.add(static_cast<int64_t>(scenario.initial.size()));
  for (const BodyState& body : scenario.initial) add_state(key, body);
  key.add(static_cast<int64_t>(scenario.pins.size()));
  for (const PinPath& p : scenario.pins) {
    key.add(p.pin.segment).add(p.pin.local_point).add(p.pin.target).add(p.pin.compliance);
    key.add(p.pin.grab.hz).add(p.pin.grab.damping_ratio).add(p.pin.grab.max_force);
    key.add(p.path).add(p.radius).add(p.hz).add(p.phase);
  }
}

void add_options(KeyBytes& key, const SolverOptions& o) {
  key.add(o.procedural.rule)
      .add(o.procedural.iterations)
      .add(o.procedural.substeps)
      .add(o.procedural.derive_velocities)
      .add(o.procedural.start_lever_arms)
      .add(o.procedural.limit_functions)
      .add(o.procedural.limits_before_joints)
      .add(o.procedural.limit_velocity_pass)
      .add(o.procedural.limit_restitution)
      .add(o.procedural.tremble)
      .add(o.procedural.joint_compliance)
      .add(o.procedural.limit_compliance)
      .add(static_cast<int64_t>(o.procedural.tremble_seed));  // time_stages moves nothing
  key.add(o.bullet.iterations).add(o.bullet.erp).add(o.bullet.euler_ball_limits);
  key.add(o.mujoco.integrator).add(o.mujoco.constraint_time_constant);
  key.add(o.ode.stepper).add(o.ode.iterations).add(o.ode.erp).add(o.ode.cfm);
}

// the running program, as its executable's size and modification time (a rebuild changes both)
void add_program(KeyBytes& key) {
  struct stat info {};
  if (stat("/proc/self/exe", &info) == 0) {
    key.add(static_cast<int64_t>(info.st_size)).add(static_cast<int64_t>(info.st_mtim.tv_sec));
    key.add(static_cast<int64_t>(info.st_mtim.tv_nsec)).add(static_cast<int64_t>(info.st_ino));
  } else {
    key.add(static_cast<int64_t>(getpid()));  // unknown program: no two processes share a file
  }
}

// the file: a header line, then the trajectory's doubles as they are in memory
constexpr char kMagic[] = "puppet truth trajectory 1\n";
constexpr int kDoublesPerBody = 13;  // x, q (w, x, y, z), v, w

struct Header {
  char key[16];
  int64_t diverged, samples, bodies;
};

void put(std::string& out, const Vector3d& v) {
  out.append(reinterpret_cast<const char*>(v.data()), 3 * sizeof(double));
}

std::string encode(const std::string& key, const Trajectory& trajectory) {
  std::string out = kMagic;
  Header header{};
  std::memcpy(header.key, key.data(), sizeof header.key);
  header.diverged = trajectory.diverged;
  header.samples = static_cast<int64_t>(trajectory.samples.size());
  header.bodies =
      trajectory.samples.empty() ? 0 : static_cast<int64_t>(trajectory.samples.front().size());
  out.append(reinterpret_cast<const char*>(&header), sizeof header);
  for (const auto& sample : trajectory.samples) {
    for (const BodyState& body : sample) {
      put(out, body.x);
      const double q[4] = {body.q.w(), body.q.x(), body.q.y(), body.q.z()};
      out.append(reinterpret_cast<const char*>(q), sizeof q);
      put(out, body.v);
      put(out, body.w);
    }
  }
  return out;
}

// false when the bytes are not a whole trajectory of this key (every sample the same size)
bool decode(const std::string& bytes, const std::string& key, Trajectory& out) {
  const size_t magic = sizeof kMagic - 1;
  if (bytes.size() < magic + sizeof(Header) || bytes.compare(0, magic, kMagic) != 0) return false;
  Header header{};
  std::memcpy(&header, bytes.data() + magic, sizeof header);
  if (key.compare(0, sizeof header.key, header.key, sizeof header.key) != 0) return false;
  constexpr int64_t kMaxCount = int64_t{1} << 24;
  if (header.samples < 0 || header.bodies < 0 || header.samples > kMaxCount ||
      header.bodies > kMaxCount || (header.diverged != 0 && header.diverged != 1)) {
    return false;
  }
  const size_t doubles = static_cast<size_t>(header.samples * header.bodies) * kDoublesPerBody;
  if (bytes.size() != magic + sizeof header + doubles * sizeof(double)) return false;
  const char* p = bytes.data() + magic + sizeof header;
  auto next = [&p] {
    double value;
    std::memcpy(&value, p, sizeof value);
    p += sizeof value;
    return value;
  };
  out.diverged = header.diverged == 1;
  out.samples.assign(static_cast<size_t>(header.samples),
                     std::vector<BodyState>(static_cast<size_t>(header.bodies)));
  for (auto& sample : out.samples) {
    for (BodyState& body : sample) {
      for (int i = 0; i < 3; ++i) body.x[i] = next();
      const double w = next(), x = next(), y = next(), z = next();
      body.q = Quaterniond(w, x, y, z);
      for (int i = 0; i < 3; ++i) body.v[i] = next();
      for (int i = 0; i < 3; ++i) body.w[i] = next();
      // a trajectory that says it did not diverge holds finite states only: one that does not
      // is not ours (a planted or damaged file), and a miss
      if (!out.diverged && !(body.x.allFinite() && body.q.coeffs().allFinite() &&
                             body.v.allFinite() && body.w.allFinite())) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

std::string truth_key(const Model& model, const Scenario& scenario, const std::string& solver,
                      const SolverOptions& options, double dt, double duration) {
  KeyBytes key;
  key.add(kMagic);
  add_program(key);
  key.add(solver).add(dt).add(duration);
  add_options(key, options);
  add_model(key, model);
  add_scenario(key, scenario);
  return content_checksum(key.bytes());
}

TruthCache::TruthCache(std::string folder) : folder_(std::move(folder)) {
  if (folder_.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(folder_, error);
  if (!std::filesystem::is_directory(folder_)) {
    throw std::runtime_error("'" + folder_ + "' is not a folder and cannot be made one");
  }
}

Trajectory TruthCache::get(const std::string& key,
                           const std::function<Trajectory()>& compute) const {
  if (folder_.empty()) return compute();
  const std::filesystem::path path = std::filesystem::path(folder_) / (key + ".truth");
  // a regular file only (a FIFO or a folder in its place is a miss, never a hang), bounded
  constexpr size_t kMaxFileBytes = size_t{1} << 30;
  std::string bytes, problem;
  Trajectory stored;
  if (read_regular_file(path.string(), kMaxFileBytes, &bytes, &problem) &&
      decode(bytes, key, stored)) {
    return stored;
  }
  Trajectory computed = compute();
  try {
    write_file_atomically(path.string(), encode(key, computed));
  } catch (const std::exception&) {
    // not stored (a full disk, a folder in its place): the next run computes it again
  }
  return computed;
}

}  // namespace puppet::compare
