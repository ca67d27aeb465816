#include "builders.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "puppet/model/text.h"

namespace puppet::compare {
namespace {

// the shapes' extreme point along a world direction, at rest, in the segment frame
Vector3d rest_extreme_point(const Segment& segment, const Vector3d& world_direction) {
  return support_point(segment, segment.rest_orientation.conjugate() * world_direction);
}

double rest_lowest_z(const Segment& segment) {
  return (segment.rest_position +
          segment.rest_orientation * rest_extreme_point(segment, -Vector3d::UnitZ()))
      .z();
}

// the default segment choices (docs/design.md): the pinocchio names, else the root for the pin
// and, for the grab, the hand on the same side by the names published characters give it
// (MuJoCo's and dm_control's humanoids: right_hand, left_hand), else the segment reaching lowest
// at rest
int default_pin_segment(const Model& model) {
  const int head = model.find_segment("head");
  return head >= 0 ? head : 0;
}

int default_grab_segment(const Model& model, std::string_view hand_name) {
  const int hand = model.find_segment(std::string(hand_name));
  if (hand >= 0) return hand;
  // Pinocchio's l_forearm is a left hand, r_forearm a right one
  const bool left = hand_name.starts_with("l_");
  const std::array<const char*, 6> right_names = {"right_hand", "hand_right", "r_hand",
                                                  "hand_r",     "righthand",  "RightHand"};
  const std::array<const char*, 6> left_names = {"left_hand", "hand_left", "l_hand",
                                                 "hand_l",    "lefthand",  "LeftHand"};
  for (const char* name : left ? left_names : right_names) {
    if (const int same_side = model.find_segment(name); same_side >= 0) return same_side;
  }
  int lowest = 0;
  for (int i = 1; i < model.segment_count(); ++i) {
    if (rest_lowest_z(model.segments[i]) < rest_lowest_z(model.segments[lowest]) - 1e-12)
      lowest = i;
  }
  return lowest;
}

Pin choose_point(const Model& model, const std::optional<PointChoice>& choice, int default_segment,
                 const Vector3d& extreme_direction, const char* option) {
  Pin pin;
  pin.segment = default_segment;
  if (choice) {
    pin.segment = model.find_segment(choice->segment);
    if (pin.segment < 0) {
      throw ScenarioError(
          "unknown segment " + shown(choice->segment) + " in model " + shown(model.name), option);
    }
  }
  const Segment& segment = model.segments[pin.segment];
  pin.local_point = choice && choice->local_point ? *choice->local_point
                                                  : rest_extreme_point(segment, extreme_direction);
  return pin;
}

Vector3d world_of(const std::vector<BodyState>& bodies, const Pin& pin) {
  return bodies[pin.segment].x + bodies[pin.segment].q * pin.local_point;
}

}  // namespace

void rotate_about(std::span<BodyState> bodies, const Quaterniond& rotation,
                  const Vector3d& centre) {
  for (BodyState& body : bodies) {
    body.x = centre + rotation * (body.x - centre);
    body.q = (rotation * body.q).normalized();
    body.v = rotation * body.v;
    body.w = rotation * body.w;
  }
}

Vector3d centre_of_mass(const Model& model, const std::vector<BodyState>& bodies) {
  Vector3d com{0, 0, 0};
  for (int i = 0; i < model.segment_count(); ++i) com += model.segments[i].mass * bodies[i].x;
  return com / model.total_mass;
}

HandPath circling_hand(const ScenarioOptions& options, bool grab) {
  constexpr double kCircleRadius = 0.3;  // m
  return {.segment = "r_forearm",
          .path = TargetPath::kCircle,
          .radius = kCircleRadius,
          .hz = options.start ? options.start->hz : options.hz,
          .grab = grab};
}

std::vector<HeldTurn> held_turns(const Model& model) {
  const RootJoint& root = model.root;
  if (root.hold == RootHold::kBall) return {{0, root.anchor_world, std::nullopt}};
  if (root.hold == RootHold::kHinge) return {{0, root.anchor_world, root.axes[0]}};
  if (root.hold == RootHold::kPlanar) return {{0, root.anchor_world, root.axes[2]}};
  std::vector<HeldTurn> turns;
  for (const Joint& joint : model.joints) {
    if (joint.parent != 0 || joint.type == JointType::kFixed || joint.type == JointType::kSlide) {
      continue;
    }
    HeldTurn turn{joint.child, joint.anchor_world, std::nullopt};
    if (joint.type == JointType::kHinge) turn.axis = joint.frame_world * joint.hinge_axis;
    turns.push_back(turn);
  }
  return turns;
}

namespace {

// whether segment s lies in the subtree under `top` (segments come parent before child)
bool in_subtree(const Model& model, int top, int s) {
  while (s > top) s = model.segments[s].parent;
  return s == top;
}

}  // namespace

void turn_subtree(const Model& model, int top, const Quaterniond& rotation, const Vector3d& centre,
                  std::vector<BodyState>& bodies) {
  for (int s = 0; s < model.segment_count(); ++s) {
    if (in_subtree(model, top, s)) rotate_about({&bodies[s], 1}, rotation, centre);
  }
}

void spin_subtree(const Model& model, int top, const Vector3d& omega, const Vector3d& centre,
                  std::vector<BodyState>& bodies) {
  for (int s = 0; s < model.segment_count(); ++s) {
    if (!in_subtree(model, top, s)) continue;
    bodies[s].w += omega;
    bodies[s].v += omega.cross(bodies[s].x - centre);
  }
}

Scenario held_figure(const Model& model, const ScenarioOptions& options, bool head,
                     const std::optional<HandPath>& hand) {
  Scenario s;
  s.environment.gravity = model.gravity;
  s.root_held = root_held(model);
  // the world's hold stands where the head's pin would (a pin the user names still holds)
  if (s.root_held && !options.pin) head = false;
  const std::optional<StartInputs>& start = options.start;
  // the pins, chosen on the rest pose
  Pin head_pin, hand_pin;
  if (head) {
    head_pin =
        choose_point(model, options.pin, default_pin_segment(model), Vector3d::UnitZ(), "pin");
  }
  if (hand) {
    hand_pin = choose_point(model, options.grab, default_grab_segment(model, hand->segment),
                            -Vector3d::UnitZ(), "grab");
    if (start && !(options.grab && options.grab->local_point)) {
      hand_pin.local_point = support_point(model.segments[hand_pin.segment], start->grab_direction);
    }
  }
  // a random start poses the figure from the segment held first (it stays at rest, so a held
  // point starts still), else from the root
  const int anchor = head ? head_pin.segment : hand ? hand_pin.segment : 0;
  s.initial = start ? posed_start(model, *start, anchor) : rest_pose(model);

  if (s.root_held && !head) {
    // the tilt as far as the world's hold lets the figure turn: about the root's hinge (its ball
    // about world x), else each of the root's children about its joint
    const double tilt = (start ? start->tilt_deg : options.tilt_deg) * M_PI / 180.0;
    for (const HeldTurn& turn : held_turns(model)) {
      const Vector3d axis = turn.axis.value_or(Vector3d::UnitX());
      turn_subtree(model, turn.top, Quaterniond(Eigen::AngleAxisd(tilt, axis)), turn.centre,
                   s.initial);
    }
  }
  if (head) {
    // a marionette: the pin point fixed, the figure tilted about world x through it
    const Vector3d pivot = world_of(s.initial, head_pin);
    // (a figure the world holds is not tilted about the pin: that would break the hold)
    const double tilt_deg = s.root_held ? 0.0 : start ? start->tilt_deg : options.tilt_deg;
    rotate_about(s.initial,
                 Quaterniond(Eigen::AngleAxisd(tilt_deg * M_PI / 180.0, Vector3d::UnitX())), pivot);
    PinPath fixed;
    fixed.pin = head_pin;
    fixed.pin.target = pivot;
    s.pins.push_back(fixed);
  }
  if (hand) {
    PinPath grab;
    grab.pin = hand_pin;
    grab.pin.target = world_of(s.initial, hand_pin);
    if (hand->grab) {
      grab.pin.grab = grab_spring(model, options.grab_spring);
    } else {
      grab.pin.compliance = options.grab_compliance;
    }
    grab.path = hand->path;
    grab.radius = hand->radius;
    grab.hz = hand->hz;
    if (start) grab.phase = start->phase;
    s.pins.push_back(grab);
  }
  return s;
}

Scenario figure_on_ground(const Model& model, const ScenarioOptions& options, double tilt_deg,
                          double height) {
  if (root_held(model)) {
    throw ScenarioError(std::string("the model's root is joined to the world (a ") +
                        root_hold_name(model.root.hold) +
                        " root): a scene on the ground drops a free figure");
  }
  Scenario s = held_figure(model, options, /*head=*/false, std::nullopt);
  s.duration = 3.0;
  s.environment.air_drag = 0.05;
  s.environment.ground = true;
  s.environment.friction = 0.8;
  rotate_about(s.initial,
               Quaterniond(Eigen::AngleAxisd(tilt_deg * M_PI / 180.0, Vector3d::UnitX())),
               centre_of_mass(model, s.initial));
  double lowest = INFINITY;
  for (int i = 0; i < model.segment_count(); ++i) {
    double low = 0.0, high = 0.0;
    vertical_extent(model.segments[i], s.initial[i].q, s.initial[i].x, &low, &high);
    lowest = std::min(lowest, low);
  }
  for (BodyState& body : s.initial) body.x.z() += height - lowest;
  return s;
}

}  // namespace puppet::compare
