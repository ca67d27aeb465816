#include "puppet/compare/start.h"

#include <cmath>
#include <queue>
#include <stdexcept>

#include "puppet/compare/number.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/rotation.h"
#include "puppet/model/text.h"

namespace puppet::compare {
namespace {

// SplitMix64 (Steele, Lea & Flood 2014): one 64-bit state, the same numbers everywhere; the
// standard library's distributions are not (their algorithms are the implementation's)
class Stream {
 public:
  Stream(uint64_t seed, int64_t index) : state_(mix(seed ^ mix(static_cast<uint64_t>(index)))) {}
  uint64_t next() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return mix(state_);
  }
  // uniform in [0, 1): the top 53 bits
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double low, double high) { return low + (high - low) * uniform(); }
  // uniform in the unit ball, by rejection from the cube (on average 1.9 draws of three)
  Vector3d in_ball() {
    for (;;) {
      const double x = uniform(-1, 1), y = uniform(-1, 1), z = uniform(-1, 1);
      const Vector3d p(x, y, z);
      if (p.squaredNorm() <= 1.0 && p.squaredNorm() > 1e-12) return p;
    }
  }

 private:
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

}  // namespace

StartInputs random_start(const Model& model, uint64_t seed, int64_t index) {
  Stream rng(seed, index);
  StartInputs s;
  s.seed = seed;
  s.index = index;
  s.tilt_deg = rng.uniform(-kStartTiltDeg, kStartTiltDeg);
  s.hz = rng.uniform(kStartHzLow, kStartHzHigh);
  s.phase = rng.uniform(0.0, 2.0 * M_PI);
  s.grab_direction = rng.in_ball().normalized();
  const double margin = (1.0 - kStartLimitFraction) / 2.0;
  for (const Joint& joint : model.joints) {
    Quaterniond q = Quaterniond::Identity();
    Vector3d w{0, 0, 0};
    double offset = 0.0;
    switch (joint.type) {
      case JointType::kBall: {
        if (joint.ball_limit == BallLimit::kEulerBox) {
          // each angle within the middle part of its range, as a hinge's
          Vector3d angles;
          for (int k = 0; k < 3; ++k) {
            angles[k] = joint.box_lower[k] + (joint.box_upper[k] - joint.box_lower[k]) *
                                                 rng.uniform(margin, 1.0 - margin);
          }
          q = euler_rotation(joint.box_order, angles);
          w = kStartJointSpeed * rng.in_ball();
          break;
        }
        const double direction = rng.uniform(0.0, 2.0 * M_PI);
        const double radius = kStartLimitFraction * std::sqrt(rng.uniform());
        const double twist = rng.uniform(-kStartLimitFraction, kStartLimitFraction) * joint.twist;
        const Vector3d swing(radius * joint.swing_x * std::cos(direction),
                             radius * joint.swing_y * std::sin(direction), 0.0);
        q = quat_exp(swing) * quat_exp(Vector3d(0, 0, twist));
        w = kStartJointSpeed * rng.in_ball();
        break;
      }
      case JointType::kHinge: {
        const double angle =
            joint.lower + (joint.upper - joint.lower) * rng.uniform(margin, 1.0 - margin);
        q = quat_exp(angle * joint.hinge_axis);
        w = rng.uniform(-kStartJointSpeed, kStartJointSpeed) * joint.hinge_axis;
        break;
      }
      case JointType::kSlide:
        if (std::isfinite(joint.lower)) {
          offset = joint.lower + (joint.upper - joint.lower) * rng.uniform(margin, 1.0 - margin);
        }
        w = rng.uniform(-kStartSlideSpeed, kStartSlideSpeed) * joint.hinge_axis;
        break;
      case JointType::kFixed:
        break;
    }
    // inside the limits by construction; the clamp makes sure of it whatever their form
    s.joint_rotation.push_back(clamp_to_limits(joint, q).normalized());
    s.joint_velocity.push_back(w);
    s.joint_offset.push_back(offset);
  }
  return s;
}

double StartInputs::joint_angle_rms_deg() const {
  double sum = 0.0;
  for (const Quaterniond& q : joint_rotation) sum += quat_log(q).squaredNorm();
  return joint_rotation.empty() ? 0.0 : std::sqrt(sum / joint_rotation.size()) * 180.0 / M_PI;
}

double StartInputs::joint_speed_rms() const {
  double sum = 0.0;
  for (const Vector3d& w : joint_velocity) sum += w.squaredNorm();
  return joint_velocity.empty() ? 0.0 : std::sqrt(sum / joint_velocity.size());
}

std::vector<BodyState> posed_start(const Model& model, const StartInputs& start, int anchor) {
  if (static_cast<int>(start.joint_rotation.size()) != model.joint_count() ||
      static_cast<int>(start.joint_velocity.size()) != model.joint_count() ||
      static_cast<int>(start.joint_offset.size()) != model.joint_count()) {
    throw std::invalid_argument("a start drawn for another model");
  }
  std::vector<BodyState> bodies = rest_pose(model);
  // breadth-first from the anchor over the joints, both ways
  std::vector<std::vector<int>> at(model.segment_count());
  for (int j = 0; j < model.joint_count(); ++j) {
    at[model.joints[j].parent].push_back(j);
    at[model.joints[j].child].push_back(j);
  }
  std::vector<bool> placed(model.segment_count(), false);
  std::queue<int> open;
  placed[anchor] = true;
  open.push(anchor);
  while (!open.empty()) {
    const int a = open.front();
    open.pop();
    for (int j : at[a]) {
      const Joint& joint = model.joints[j];
      const bool down = joint.parent == a;  // walked in the model's direction
      const int b = down ? joint.child : joint.parent;
      if (placed[b]) continue;
      const BodyState& from = bodies[a];
      BodyState& to = bodies[b];
      const Quaterniond& q_rel = start.joint_rotation[j];
      // a box of hinges at different points carries the parent's point along its angles
      const Vector3d on_parent = parent_anchor(joint, q_rel);
      const Vector3d& local_a = down ? on_parent : joint.anchor_in_child;
      const Vector3d& local_b = down ? joint.anchor_in_child : on_parent;
      Quaterniond parent_frame;  // the joint's frame as the parent carries it, world
      if (down) {
        // q_rel = (q_p F_p)⁻¹ (q_c F_c)  ⇒  q_c = q_p F_p q_rel F_c⁻¹
        parent_frame = from.q * joint.frame_in_parent;
        to.q = (parent_frame * q_rel * joint.frame_in_child.conjugate()).normalized();
      } else {
        // q_p = q_c F_c q_rel⁻¹ F_p⁻¹
        to.q =
            (from.q * joint.frame_in_child * q_rel.conjugate() * joint.frame_in_parent.conjugate())
                .normalized();
        parent_frame = to.q * joint.frame_in_parent;
      }
      if (joint.type == JointType::kSlide) {
        // the child's point is the parent's moved along the slide, at the slide's rate; neither
        // turns against the other
        const double sign = down ? 1.0 : -1.0;
        const Vector3d direction = parent_frame * joint.hinge_axis;
        const Vector3d point = from.x + from.q * local_a + sign * start.joint_offset[j] * direction;
        to.x = point - to.q * local_b;
        to.w = from.w;
        to.v = from.v + from.w.cross(to.x - from.x) +
               sign * Vector3d(parent_frame * start.joint_velocity[j]);
        placed[b] = true;
        open.push(b);
        continue;
      }
      const Vector3d point = from.x + from.q * local_a;
      to.x = point - to.q * local_b;
      // ω_c = ω_p + ω_rel, the joint point moving alike on both sides
      const Vector3d relative = parent_frame * start.joint_velocity[j];
      to.w = down ? Vector3d(from.w + relative) : Vector3d(from.w - relative);
      to.v = from.v + from.w.cross(point - from.x) - to.w.cross(point - to.x);
      placed[b] = true;
      open.push(b);
    }
  }
  return bodies;
}

void parse_start(const std::string& text, uint64_t* seed, int64_t* index) {
  const size_t colon = text.find(':');
  uint64_t s = 0, k = 0;
  if (colon == std::string::npos || !parse_whole(text.substr(0, colon), &s) ||
      !parse_whole(text.substr(colon + 1), &k)) {
    throw std::invalid_argument("expected SEED:INDEX in plain decimal digits, got " + shown(text));
  }
  *seed = s;
  *index = static_cast<int64_t>(k);
}

}  // namespace puppet::compare
