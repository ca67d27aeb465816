// What every model front end (JSON, MJCF) hands to the one builder that validates the tree and
// derives the local quantities, so that both kinds of file are checked alike.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "puppet/model/model.h"
#include "puppet/model/text.h"

namespace puppet::detail {

// The model's limits (docs/model.md, "Limits"), checked by every front end through assemble()
inline constexpr double kMinLength = 1e-4, kMaxLength = 1e3;      // shape sizes (m)
inline constexpr double kMinMass = 1e-6, kMaxMass = 1e6;          // kg
inline constexpr double kMinInertia = 1e-16, kMaxInertia = 1e13;  // principal moments (kg m²)
inline constexpr double kMaxCoordinate = 1e5;                     // positions, anchors (m)
inline constexpr double kMaxGravity = 1e3;                        // each component (m/s²)
inline constexpr double kMinNorm = 1e-9, kMaxNorm = 1e9;          // quaternions and axes as given
inline constexpr size_t kMaxNameLength = 64;                      // bytes
inline constexpr size_t kMaxFileBytes = size_t{16} << 20;         // a model file

using puppet::printable;
using puppet::shown;
// the shortest text that reads back as exactly x: a value just outside a range never prints as
// its bound ("a mass of 9.9999999999999995e-07 kg", not "1e-06")
std::string number(double x);
// what is wrong with a name (empty when nothing): 1 to 64 bytes of letters, digits, _ - . :
std::string name_problem(std::string_view name);
// what keeps a model file's bytes from being read as UTF-8 text (a UTF-16 or UTF-32 byte-order
// mark, a NUL byte), or empty
std::string text_problem(std::string_view text);
// what is wrong with a segment, a joint, gravity (empty when nothing), by the limits above: the
// triangle inequality of the moments of inertia, unit rotations and axes
std::string shape_problem(const Shape& shape);
std::string segment_problem(const Segment& segment);
std::string joint_problem(const Joint& joint);
std::string gravity_problem(const Vector3d& gravity);
// what is wrong with a quaternion or axis as given before it is normalised (empty when nothing)
std::string norm_problem(const Eigen::Ref<const Eigen::VectorXd>& v);
// v / |v| for such a vector: Eigen's normalized() where its squared norm is finite (the same
// bits as always), through the stable norm where it overflows
template <typename V>
V normalized(const V& v) {
  const double squared = v.squaredNorm();
  return std::isfinite(squared) && squared > 0.0 ? V(v.normalized()) : V(v / v.stableNorm());
}

// A body's solids composed as MuJoCo's compiler composes a body's geoms (mjCBody::GeomFrame):
// the masses add, the centre of mass is their mean weighted by mass, each solid's inertia is
// turned into the frame and carried to that centre (parallel axes) and the tensors add.
struct Composite {
  double mass = 0.0;
  Vector3d weighted_sum{0, 0, 0};                 // Σ mᵢ cᵢ
  Matrix3d inertia_at_origin = Matrix3d::Zero();  // Σ about the frame's origin
  // a solid of the frame: `shape` placed in it (position, orientation), with its mass
  void add(const Shape& shape, double mass);
  Vector3d centre() const { return weighted_sum / mass; }
  // the tensor about the centre of mass, in the frame's axes
  Matrix3d inertia() const;
};

// The principal frame of an inertia tensor (in some frame F): the rotation, in F, whose axes are
// principal, and the moments about them. Of the 24 such right-handed frames where the moments
// differ, the one nearest `near` (its axes best aligned with near's); `near` itself when it is
// principal already (a symmetric body keeps its axes)
void principal_frame(const Matrix3d& inertia, const Quaterniond& near, Quaterniond* frame,
                     Vector3d* moments);

// Places a segment from solids given in a frame (x, q in world): one solid keeps its own frame
// (the segment is centred on it, with its axes, as MuJoCo copies a single geom's frame); several
// are composed (Composite) and the segment frame is their principal frame at their centre of
// mass, nearest the first solid's axes. Sets the segment's mass, inertia, rest pose and shapes
// (each placed in the segment frame) and derives its mass terms.
void place_solids(const std::vector<Shape>& solids, const std::vector<double>& masses,
                  const Vector3d& x, const Quaterniond& q, Segment& segment);

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

// How far outside either shape a joint's anchor may lie: a JSON file's 5 cm catches a typo; an
// MJCF file's anchors are MuJoCo's, which takes any (published ankles and hips sit 5 to 11 cm
// outside their geoms), so only one past half a metre, a unit's slip, is refused there
inline constexpr double kJsonAnchorReach = 0.05;  // m
inline constexpr double kMjcfAnchorReach = 0.5;   // m

// Builds the model from segments (each complete, in any order) and joints: one root, no cycle,
// each segment the child of at most one joint, anchors within `anchor_reach` of both shapes;
// orders the segments parent first and derives the local anchors and frames. Throws ModelError
// "<locate(part, index)>: <problem>".
Model assemble(const std::string& name, std::vector<Segment> segments, std::vector<RawJoint> joints,
               const Locate& locate, double anchor_reach = kJsonAnchorReach);

}  // namespace puppet::detail
