// What every model front end (JSON, MJCF) hands to the one builder that validates the tree and
// derives the local quantities, so that both kinds of file are checked alike.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "puppet/model/model.h"

namespace puppet::detail {

// a joint as read: the Joint's own fields (type, limits, anchor_world, frame_world) set, its
// segments still by name, a hinge's axis in world
struct RawJoint {
  Joint joint;
  std::string parent_name, child_name;
  Vector3d hinge_axis_world{0, 0, 0};
  bool hinge_axis_in_frame = false;  // joint.hinge_axis is already in the joint frame
};

// what an error is about, for the front end to name it (with its file, and a line if it has one)
enum class Part { kModel, kSegment, kJoint };
using Locate = std::function<std::string(Part part, int index)>;

// Builds the model from segments (each complete, in any order) and joints: one root, no cycle,
// each segment the child of at most one joint, anchors within 5 cm of both shapes; orders the
// segments parent first and derives the local anchors and frames. Throws ModelError
// "<locate(part, index)>: <problem>".
Model assemble(const std::string& name, std::vector<Segment> segments, std::vector<RawJoint> joints,
               const Locate& locate);

}  // namespace puppet::detail
