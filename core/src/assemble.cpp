// From a model's parts to a Model (model_builder.h, detail::assemble): the names checked, each
// joint tied to its parent and child, the one root found, the segments ordered parent before
// child, each joint placed in both segments' frames, and the totals derived. Both readers (JSON
// and MJCF) end here, so a model is checked the same whichever file it came from.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "model_builder.h"
#include "puppet/model/euler_box.h"

namespace puppet::detail {
namespace {

// throws the ModelError naming the part
struct Failure {
  const Locate& locate;
  [[noreturn]] void operator()(Part part, int index, const std::string& problem) const {
    throw ModelError(locate(part, index) + ": " + problem);
  }
};

// every segment valid and named once: each name's index
std::map<std::string, int> index_segments(const std::vector<Segment>& segments,
                                          const Failure& fail) {
  std::map<std::string, int> index_of;
  for (size_t i = 0; i < segments.size(); ++i) {
    if (std::string problem = segment_problem(segments[i]); !problem.empty()) {
      fail(Part::kSegment, static_cast<int>(i), problem);
    }
    if (!index_of.emplace(segments[i].name, static_cast<int>(i)).second) {
      fail(Part::kSegment, static_cast<int>(i), "duplicate segment name");
    }
  }
  return index_of;
}

// each joint named once and tied to its parent and child (indices set); by segment, the joint
// that is its parent's (−1: none)
std::vector<int> link_joints(std::vector<RawJoint>& raw_joints,
                             const std::map<std::string, int>& index_of, size_t segment_count,
                             const Failure& fail) {
  std::set<std::string> joint_names;
  std::vector<int> parent_joint_of(segment_count, -1);
  for (size_t i = 0; i < raw_joints.size(); ++i) {
    const int ji = static_cast<int>(i);
    RawJoint& raw = raw_joints[i];
    if (std::string problem = name_problem(raw.joint.name); !problem.empty()) {
      fail(Part::kJoint, ji, problem);
    }
    if (!joint_names.insert(raw.joint.name).second) fail(Part::kJoint, ji, "duplicate joint name");
    auto p = index_of.find(raw.parent_name);
    if (p == index_of.end()) {
      fail(Part::kJoint, ji, "unknown parent segment \"" + raw.parent_name + "\"");
    }
    auto c = index_of.find(raw.child_name);
    if (c == index_of.end()) {
      fail(Part::kJoint, ji, "unknown child segment \"" + raw.child_name + "\"");
    }
    if (p->second == c->second) {
      fail(Part::kJoint, ji, "parent and child are the same segment (a cycle)");
    }
    raw.joint.parent = p->second;
    raw.joint.child = c->second;
    if (parent_joint_of[c->second] >= 0) {
      fail(Part::kJoint, ji,
           "segment \"" + raw.child_name + "\" already has a parent (joint \"" +
               raw_joints[parent_joint_of[c->second]].joint.name + "\"): two parents");
    }
    parent_joint_of[c->second] = ji;
  }
  return parent_joint_of;
}

// the one segment without a parent joint
int find_root(const std::vector<Segment>& segments, const std::vector<int>& parent_joint_of,
              const Failure& fail) {
  std::vector<int> roots;
  for (size_t i = 0; i < segments.size(); ++i) {
    if (parent_joint_of[i] < 0) roots.push_back(static_cast<int>(i));
  }
  if (roots.empty()) fail(Part::kModel, 0, "no root segment: the joints form a cycle");
  if (roots.size() > 1) {
    fail(Part::kModel, 0,
         "two roots: segments \"" + segments[roots[0]].name + "\" and \"" +
             segments[roots[1]].name + "\" have no parent joint");
  }
  return roots[0];
}

// The segments parent before child, depth first from the root: the old indices in the new order;
// `new_index` the other way. A segment not reached lies on a cycle.
std::vector<int> order_tree(const std::vector<Segment>& segments,
                            const std::vector<RawJoint>& raw_joints, int root,
                            std::vector<int>& new_index, const Failure& fail) {
  std::vector<std::vector<int>> children(segments.size());
  for (size_t j = 0; j < raw_joints.size(); ++j) {
    children[raw_joints[j].joint.parent].push_back(static_cast<int>(j));
  }
  std::vector<int> order;
  new_index.assign(segments.size(), -1);
  std::vector<int> stack{root};
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    new_index[s] = static_cast<int>(order.size());
    order.push_back(s);
    for (auto it = children[s].rbegin(); it != children[s].rend(); ++it) {
      stack.push_back(raw_joints[*it].joint.child);
    }
  }
  for (size_t i = 0; i < segments.size(); ++i) {
    if (new_index[i] < 0) {
      fail(Part::kSegment, static_cast<int>(i),
           "lies on a cycle of joints (not reachable from the root \"" + segments[root].name +
               "\")");
    }
  }
  return order;
}

// the joint `ji` between the placed segments of indices `parent` and `child`: its anchors and
// frames in each, its hinge's axis in its frame, and the anchor within reach of both shapes
Joint place_joint(const RawJoint& raw, int ji, const Model& model, int parent_index,
                  int child_index, double anchor_reach, const Failure& fail) {
  Joint j = raw.joint;
  j.parent = parent_index;
  j.child = child_index;
  const Segment& parent = model.segments[parent_index];
  const Segment& child = model.segments[child_index];
  if (std::string problem = joint_problem(j); !problem.empty()) fail(Part::kJoint, ji, problem);
  j.anchor_in_parent =
      parent.rest_orientation.conjugate() * (j.anchor_world - parent.rest_position);
  // a box of hinges at different points: the child's side is the last hinge's point
  const Vector3d child_point = has_box_offsets(j)
                                   ? Vector3d(j.anchor_world + j.box_offsets[0] + j.box_offsets[1])
                                   : j.anchor_world;
  j.anchor_in_child = child.rest_orientation.conjugate() * (child_point - child.rest_position);
  for (const auto* seg : {&parent, &child}) {
    const Vector3d local = seg == &parent ? j.anchor_in_parent : j.anchor_in_child;
    const double distance = signed_distance(*seg, local);
    if (distance > anchor_reach) {
      fail(Part::kJoint, ji,
           "anchor is " + number(std::round(distance * 1000.0) / 10.0) +
               " cm from the surface of segment \"" + seg->name + "\" (at most " +
               number(anchor_reach * 100.0) + " cm allowed)");
    }
  }
  j.frame_in_parent = parent.rest_orientation.conjugate() * j.frame_world;
  j.frame_in_child = child.rest_orientation.conjugate() * j.frame_world;
  if ((j.type == JointType::kHinge || j.type == JointType::kSlide) && !raw.hinge_axis_in_frame) {
    j.hinge_axis = j.frame_world.conjugate() * raw.hinge_axis_world;
  }
  if (std::string problem = joint_problem(j); !problem.empty()) fail(Part::kJoint, ji, problem);
  return j;
}

// the total mass and the rest height, top to bottom of every shape
void derive_totals(Model& model) {
  double top = -INFINITY, bottom = INFINITY;
  for (const Segment& s : model.segments) {
    model.total_mass += s.mass;
    const Vector3d up = s.rest_orientation.conjugate() * Vector3d::UnitZ();
    top = std::max(top, (s.rest_position + s.rest_orientation * support_point(s, up)).z());
    bottom = std::min(bottom, (s.rest_position + s.rest_orientation * support_point(s, -up)).z());
  }
  model.rest_height = top - bottom;
}

}  // namespace

Model assemble(const std::string& name, std::vector<Segment> segments,
               std::vector<RawJoint> raw_joints, const Locate& locate, double anchor_reach) {
  const Failure fail{locate};
  Model model;
  if (std::string problem = name_problem(name); !problem.empty()) {
    fail(Part::kModel, 0, "its name: " + problem);
  }
  model.name = name;
  const std::map<std::string, int> index_of = index_segments(segments, fail);
  const std::vector<int> parent_joint_of = link_joints(raw_joints, index_of, segments.size(), fail);
  const int root = find_root(segments, parent_joint_of, fail);
  std::vector<int> new_index;
  const std::vector<int> order = order_tree(segments, raw_joints, root, new_index, fail);
  for (int old : order) model.segments.push_back(segments[old]);
  for (int i = 1; i < model.segment_count(); ++i) {
    const int ji = parent_joint_of[order[i]];
    const int parent = new_index[raw_joints[ji].joint.parent];
    Joint joint = place_joint(raw_joints[ji], ji, model, parent, i, anchor_reach, fail);
    model.segments[i].parent_joint = i - 1;
    model.segments[i].parent = parent;
    model.joints.push_back(std::move(joint));
  }
  derive_totals(model);
  return model;
}

}  // namespace puppet::detail
