/// \file
/// The joint between the world and a model's root segment (RootJoint, model.h): its coordinates
/// read from a pose, the pose at given coordinates, and how far a pose strays from what the joint
/// allows (the hold's gap, which the metrics add to the joints').
#pragma once

#include <array>
#include <string>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet {

/// a root joint's coordinates and their rates, one per degree of freedom in the order of its axes
/// (a hinge's angle in rad, a slide's distance in m); `count` of them (none for free, weld, ball)
struct RootCoordinates {
  int count = 0;
  std::array<double, 3> value{0, 0, 0};
  std::array<double, 3> rate{0, 0, 0};
};

/// where the root joint's degrees of freedom lie among its axes: the first `root_slide_count` are
/// slides, `root_hinge_index` is the hinge's (-1: none)
int root_slide_count(RootHold hold);
int root_hinge_index(RootHold hold);
/// how many coordinates the hold has along its axes (RootCoordinates::count): its slides and its
/// hinge; none for a free, welded or ball root
int root_coordinate_count(RootHold hold);

/// the turn (world rotation vector) by which orientation q strays from what the hold allows: a
/// weld's or a slide's whole turn from rest; a hinge's (a planar root's) the tilt of its axis from
/// its rest direction to where q has it; nothing for a free or a ball root. Its norm is the gap's
/// angle; turning the root by minus it about the anchor closes it
Vector3d root_held_turn(const Model& model, const Quaterniond& q);

/// the coordinates of the root's pose and velocity (an angle is read within ±π); a pose off the
/// joint reads as its nearest on it, along the free directions
RootCoordinates root_coordinates(const Model& model, const BodyState& root);

/// the root's pose and velocity at the given coordinates of its joint (free, weld and ball: its
/// rest pose, at rest)
BodyState root_state_at(const Model& model, const RootCoordinates& coordinates);

/// how far the root's pose strays from what its joint allows: the held point's distance from
/// where the joint lets it be (m) and the held directions' turn (rad); zero for a free root
struct RootGap {
  double distance = 0.0;
  double angle = 0.0;
};
RootGap root_gap(const Model& model, const BodyState& root);

/// whether the root is joined to the world
inline bool root_held(const Model& model) { return model.root.hold != RootHold::kFree; }

/// an engine's refusal of a model whose root the world holds, in one line, when the engine does
/// not build that joint (empty for a free root)
std::string held_root_problem(const Model& model);
/// the refusal of a slide's armature by an engine in maximal coordinates (empty when there is
/// none): no inertia of a segment stands in for a rotor's inertia along a translation
std::string slide_armature_problem(const Model& model);

}  // namespace puppet
