// The world's joint on the root segment (root_joint.h)
#include "puppet/model/root_joint.h"

#include <cmath>

#include "puppet/model/rotation.h"

namespace puppet {
namespace {

// the rotation from the rest orientation to q, its scalar part made non-negative
Quaterniond turn_from_rest(const Segment& root, const Quaterniond& q) {
  Quaterniond turn = q * root.rest_orientation.conjugate();
  if (turn.w() < 0.0) turn.coeffs() = -turn.coeffs();
  return turn;
}

}  // namespace

int root_hinge_index(RootHold hold) {
  return hold == RootHold::kHinge ? 0 : hold == RootHold::kPlanar ? 2 : -1;
}

int root_slide_count(RootHold hold) {
  return hold == RootHold::kSlide ? 1 : hold == RootHold::kPlanar ? 2 : 0;
}

Vector3d root_held_turn(const Model& model, const Quaterniond& q) {
  const RootJoint& root = model.root;
  const Quaterniond turn = turn_from_rest(model.segments[0], q);
  if (root.hold == RootHold::kWeld || root.hold == RootHold::kSlide) return quat_log(turn);
  const int hinge = root_hinge_index(root.hold);
  if (hinge < 0) return Vector3d::Zero();
  const Vector3d& a = root.axes[static_cast<size_t>(hinge)];
  const Vector3d now = turn * a;
  const Vector3d tilt = a.cross(now);
  const double sine = tilt.norm();
  return sine > 0.0 ? Vector3d(std::atan2(sine, a.dot(now)) / sine * tilt) : Vector3d::Zero();
}

int root_coordinate_count(RootHold hold) {
  return root_slide_count(hold) + (root_hinge_index(hold) >= 0 ? 1 : 0);
}

int root_dofs(RootHold hold) {
  switch (hold) {
    case RootHold::kFree:
      return 6;
    case RootHold::kWeld:
      return 0;
    case RootHold::kHinge:
    case RootHold::kSlide:
      return 1;
    case RootHold::kBall:
    case RootHold::kPlanar:
      return 3;
  }
  return 0;
}

const char* joint_type_name(JointType type) {
  switch (type) {
    case JointType::kBall:
      return "ball";
    case JointType::kHinge:
      return "hinge";
    case JointType::kFixed:
      return "fixed";
    case JointType::kSlide:
      return "slide";
  }
  return "?";
}

const char* root_hold_name(RootHold hold) {
  switch (hold) {
    case RootHold::kFree:
      return "free";
    case RootHold::kWeld:
      return "weld";
    case RootHold::kHinge:
      return "hinge";
    case RootHold::kSlide:
      return "slide";
    case RootHold::kBall:
      return "ball";
    case RootHold::kPlanar:
      return "planar";
  }
  return "";
}

std::string held_root_problem(const Model& model) {
  if (!root_held(model)) return {};
  return std::string("its root is joined to the world (a ") + root_hold_name(model.root.hold) +
         " root), which this engine does not build (mujoco, bullet-multibody, bullet-rigid, ode "
         "and the procedural rules xpbd and tree do)";
}

std::string slide_armature_problem(const Model& model) {
  const RootJoint& root = model.root;
  const int slides = root_slide_count(root.hold);
  for (int k = 0; k < slides; ++k) {
    if (root.passive[static_cast<size_t>(k)].armature != 0.0) {
      return "the armature of the root's slide \"" + root.names[static_cast<size_t>(k)] +
             "\" has no inertia of a segment to stand in for it";
    }
  }
  for (const Joint& joint : model.joints) {
    if (joint.type == JointType::kSlide && joint.passive[0].armature != 0.0) {
      return "the armature of slide \"" + joint.name +
             "\" has no inertia of a segment to stand in for it";
    }
  }
  return {};
}

RootCoordinates root_coordinates(const Model& model, const BodyState& root) {
  const RootJoint& joint = model.root;
  RootCoordinates c;
  const int hinge = root_hinge_index(joint.hold);
  const int slides = root_slide_count(joint.hold);
  c.count = root_coordinate_count(joint.hold);
  const Vector3d arm = root.q * joint.anchor_in_root;
  const Vector3d moved = root.x + arm - joint.anchor_world;
  const Vector3d anchor_velocity = root.v + root.w.cross(arm);
  for (int k = 0; k < slides; ++k) {
    c.value[k] = joint.axes[k].dot(moved);
    c.rate[k] = joint.axes[k].dot(anchor_velocity);
  }
  if (hinge >= 0) {
    const Quaterniond turn = turn_from_rest(model.segments[0], root.q);
    const Vector3d& axis = joint.axes[hinge];
    c.value[hinge] = 2.0 * std::atan2(turn.vec().dot(axis), turn.w());
    c.rate[hinge] = axis.dot(root.w);
  }
  return c;
}

BodyState root_state_at(const Model& model, const RootCoordinates& coordinates) {
  const RootJoint& joint = model.root;
  const Segment& segment = model.segments[0];
  BodyState body;
  body.x = segment.rest_position;
  body.q = segment.rest_orientation;
  const int hinge = root_hinge_index(joint.hold);
  Vector3d anchor_velocity = Vector3d::Zero();
  if (hinge >= 0) {
    const Vector3d& axis = joint.axes[hinge];
    const Quaterniond turn(Eigen::AngleAxisd(coordinates.value[hinge], axis));
    body.q = (turn * segment.rest_orientation).normalized();
    body.x = joint.anchor_world + turn * (segment.rest_position - joint.anchor_world);
    body.w = coordinates.rate[hinge] * axis;
  }
  for (int k = 0; k < root_slide_count(joint.hold); ++k) {
    body.x += coordinates.value[k] * joint.axes[k];
    anchor_velocity += coordinates.rate[k] * joint.axes[k];
  }
  // the anchor moves with the slides alone; the centre also turns about it
  body.v = anchor_velocity - body.w.cross(body.q * joint.anchor_in_root);
  return body;
}

RootGap root_gap(const Model& model, const BodyState& root) {
  const RootJoint& joint = model.root;
  RootGap gap;
  if (joint.hold == RootHold::kFree) return gap;
  Vector3d moved = root.x + root.q * joint.anchor_in_root - joint.anchor_world;
  for (int k = 0; k < root_slide_count(joint.hold); ++k) {
    moved -= joint.axes[k].dot(moved) * joint.axes[k];
  }
  gap.distance = moved.norm();
  gap.angle = root_held_turn(model, root.q).norm();
  return gap;
}

}  // namespace puppet
