/// \file
/// The articulated body: segments, their shapes and inertia, the joints that tie them into a
/// tree, and the joints' limits. Immutable once built; every solver reads the same Model.
///
/// Conventions (docs/design.md, "The model"): SI units, right-handed, z up. Quaternions are
/// Eigen's (w, x, y, z). Everything in the file is given in world coordinates at rest; the loader
/// derives every local quantity stored here.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace puppet {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

enum class ShapeType { kSphere, kCapsule, kBox, kCylinder, kEllipsoid };

/// a collision/visual shape, placed in its segment's frame (a segment's only shape sits at the
/// origin, the centre of mass, with the segment's axes)
struct Shape {
  ShapeType type = ShapeType::kSphere;
  double radius = 0.0;             ///< sphere, capsule, cylinder
  double half_length = 0.0;        ///< capsule: half the cylinder part; cylinder: half its height;
                                   /// both along the shape's z
  Vector3d half_extents{0, 0, 0};  ///< box; ellipsoid: its semi-axes
  Vector3d position{0, 0, 0};      ///< the shape's centre in the segment frame
  Quaterniond orientation = Quaterniond::Identity();  ///< the shape's axes in the segment frame
};

/// "sphere", "capsule", "box", "cylinder", "ellipsoid"
const char* shape_type_name(ShapeType type);

/// The shape functions below read the shape in its own frame (centred, its own axes)
double shape_volume(const Shape& shape);
/// solid-body inertia of the shape with the given mass, diagonal in the shape's own frame
Vector3d solid_inertia(const Shape& shape, double mass);
/// the shape's point furthest along `direction` (shape frame); ties resolve to the middle
Vector3d support_point(const Shape& shape, const Vector3d& direction);
/// signed distance from a point (shape frame) to the shape's surface, negative inside (for an
/// ellipsoid a bound that has the right sign and is exact on the axes)
double signed_distance(const Shape& shape, const Vector3d& point);

struct Segment {
  std::string name;
  double mass = 0.0;
  Vector3d inertia{0, 0, 0};  ///< diagonal, segment frame, about the COM
  /// 1/mass and 1/inertia, derived by derive_mass_terms(): the solvers multiply, never divide
  double inv_mass = 0.0;
  Vector3d inv_inertia{0, 0, 0};
  /// one shape or more (MJCF's geoms of one body), each placed in the segment frame
  std::vector<Shape> shapes;
  Vector3d rest_position{0, 0, 0};                         ///< COM in world at rest
  Quaterniond rest_orientation = Quaterniond::Identity();  ///< segment frame in world at rest
  int parent_joint = -1;  ///< joint whose child this segment is; -1 for the root
  int parent = -1;        ///< parent segment; -1 for the root
};

/// a slide (MJCF's slide below the root) moves its child along one direction of its parent and
/// lets it turn not at all
enum class JointType { kBall, kHinge, kFixed, kSlide };

/// The passive dynamics of one degree of freedom of a joint, as MuJoCo's joint `stiffness`,
/// `springref`, `damping` and `armature` define them (docs/model-format.md, "Springs, dampers and
/// armature"): the generalized force −stiffness (angle − spring_ref) − damping · rate, and a rotor
/// inertia `armature` added to the degree of freedom's own inertia
struct JointPassive {
  double stiffness = 0.0;   ///< N m/rad
  double damping = 0.0;     ///< N m s/rad
  double spring_ref = 0.0;  ///< rad: the angle where the spring is slack (a hinge's, a box's)
  double armature = 0.0;    ///< kg m²
  bool operator==(const JointPassive&) const = default;
};

/// A ball joint's limit: a swing ellipse and a twist, or a box of intrinsic Euler angles
/// (euler_box.h: q_rel = R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂), each angle within its own range)
enum class BallLimit { kSwingTwist, kEulerBox };

/// the axes of a joint frame a box turns about, in order (0 x, 1 y, 2 z; all different)
struct EulerOrder {
  std::array<int, 3> axes{0, 1, 2};
  bool operator==(const EulerOrder&) const = default;
};

struct Joint {
  std::string name;
  JointType type = JointType::kBall;
  int parent = -1;  ///< segment indices
  int child = -1;
  Vector3d anchor_world{0, 0, 0};      ///< rest
  Vector3d anchor_in_parent{0, 0, 0};  ///< the joint point in each segment's frame
  Vector3d anchor_in_child{0, 0, 0};
  /// joint frame seen from each segment: q_rel = (q_p·frame_in_parent)⁻¹ (q_c·frame_in_child)
  Quaterniond frame_in_parent = Quaterniond::Identity();
  Quaterniond frame_in_child = Quaterniond::Identity();
  Quaterniond frame_world = Quaterniond::Identity();  ///< rest
  /// ball: which limit it has
  BallLimit ball_limit = BallLimit::kSwingTwist;
  /// ball, swing–twist: swing ellipse half-angles about the frame's x and y, |twist| about its z
  /// (rad); π each for a box (the swing–twist reading limits nothing there)
  double swing_x = 0.0, swing_y = 0.0, twist = 0.0;
  /// ball, Euler box: the order of the frame's axes and each angle's range (rad), the rest
  /// (0, 0, 0) inside; the middle angle within ±85° (away from gimbal lock)
  EulerOrder box_order;
  Vector3d box_lower{0, 0, 0}, box_upper{0, 0, 0};
  /// ball, Euler box of hinges at different points (MJCF: the humanoids' ankles, two hinges 4 cm
  /// apart): the second hinge's point less the first's, and the third's less the second's, in
  /// world at rest (as anchor_world); zero when they share one point. The anchor on the parent's
  /// side is then the first hinge's point, the one on the child's side the last's, and they meet
  /// where parent_anchor() (euler_box.h) carries the first along the box's angles
  std::array<Vector3d, 2> box_offsets{Vector3d::Zero(), Vector3d::Zero()};
  /// hinge: unit axis in the joint frame and the range of the right-handed angle about it (rad);
  /// slide: its direction in the joint frame and the range of its coordinate, the child's point
  /// less the parent's along it (m; ±infinity when not limited)
  Vector3d hinge_axis{0, 0, 1};
  double lower = 0.0, upper = 0.0;
  /// sine and cosine of each half-limit (the twist's, the hinge's lower and upper), derived by
  /// derive_limit_terms() so that limits are tested and clamped without trigonometry
  double twist_half_sin = 0.0, twist_half_cos = 1.0;
  double lower_half_sin = 0.0, lower_half_cos = 1.0;
  double upper_half_sin = 0.0, upper_half_cos = 1.0;
  /// springs, dampers and armature (joint_springs.h): a hinge's on its angle and a slide's on its
  /// coordinate (N/m, N s/m, kg) in entry 0; an Euler
  /// box's on its angle k in entry k (MuJoCo's three hinges); a swing–twist ball's entry 0 on each
  /// coordinate of its rotation from rest as a rotation vector (MuJoCo's ball: spring_ref 0); a
  /// fixed joint has none
  std::array<JointPassive, 3> passive{};
};

/// How the world holds the root segment (MJCF: the joints of the root body). Free: a floating
/// base, the scenarios hold it or let it go. The others join it to the static world: a weld (no
/// joint), a hinge, a slide, an unlimited ball, or a planar root: two orthogonal slides, then a
/// hinge about the normal of their plane (dm_control's walker, hopper and cheetah)
enum class RootHold { kFree, kWeld, kHinge, kSlide, kBall, kPlanar };

/// The joint between the world and the root segment (segment 0). Its coordinates are measured from
/// the rest pose: a hinge's angle θ about its axis through the anchor, a slide's distance s along
/// its direction, a planar root's (s₀, s₁, θ). The root's pose at coordinates c is its rest pose
/// turned by θ about the axis through the anchor, then moved by s along the slides.
struct RootJoint {
  RootHold hold = RootHold::kFree;
  /// the file's names for its degrees of freedom, in the order of `axes` (a weld's is the root's)
  std::array<std::string, 3> names;
  /// the point the joint holds or moves, at rest in world and in the root's frame (a hinge's or a
  /// ball's centre; a slide's point; a weld's, the root's centre of mass)
  Vector3d anchor_world{0, 0, 0};
  Vector3d anchor_in_root{0, 0, 0};
  /// unit axes in world at rest, one per degree of freedom: a hinge's axis or a slide's direction
  /// in entry 0; a planar root's two slides, then its hinge
  std::array<Vector3d, 3> axes{Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
  /// a hinge's (rad) or a slide's (m) range of its coordinate; none when not limited
  bool limited = false;
  double lower = 0.0, upper = 0.0;
  /// springs, dampers and armature per degree of freedom, in the order of `axes` (a slide's in
  /// N/m, N s/m and kg)
  std::array<JointPassive, 3> passive{};
  bool operator==(const RootJoint&) const = default;
};

/// how many degrees of freedom the root's joint leaves it (free 6, weld 0, ball 3, planar 3)
int root_dofs(RootHold hold);
/// the joint type's name as the JSON format says it: "ball", "hinge", "fixed", "slide"
const char* joint_type_name(JointType type);
/// the hold's name as MJCF and the docs say it: "free", "weld", "hinge", "slide", "ball", "planar"
const char* root_hold_name(RootHold hold);

/// fills the segment's inverse mass and inertia; call after setting mass and inertia
void derive_mass_terms(Segment& segment);
/// The segment's shapes together, in the segment frame: the point furthest along `direction`,
/// the signed distance of a point (the least over the shapes) and the volume (the sum; shapes
/// that overlap count twice, as MuJoCo counts their mass)
Vector3d support_point(const Segment& segment, const Vector3d& direction);
double signed_distance(const Segment& segment, const Vector3d& point);
double segment_volume(const Segment& segment);
/// whether the segment is one shape at its origin with its axes (the shape's frame is the
/// segment's: the hot paths read it without a rotation)
inline bool lone_shape(const Segment& segment) {
  const Shape& first = segment.shapes.front();
  return segment.shapes.size() == 1 && first.position.isZero() &&
         first.orientation.coeffs() == Quaterniond::Identity().coeffs();
}
/// a point of the segment frame in the shape's own frame, and back
Vector3d to_shape(const Shape& shape, const Vector3d& in_segment);
Vector3d from_shape(const Shape& shape, const Vector3d& in_shape);
/// whether `frame` (a rotation in the segment's frame) is a principal frame of the segment: its
/// inertia, seen in that frame, is diagonal to 1e-9 of its largest moment. Segment frames always
/// are; joint frames need not be (a solver whose link frames must be principal checks this)
bool is_principal_frame(const Segment& segment, const Quaterniond& frame);
/// fills the joint's half-limit terms from twist, lower and upper; call after setting them
void derive_limit_terms(Joint& joint);

/// the error raised by every model-building function: one line naming source, element, problem
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Model {
  std::string name;
  std::vector<Segment> segments;  ///< parent before child: segments[i].parent < i
  std::vector<Joint> joints;      ///< joints[j].child == j + 1 (the root is segment 0)
  RootJoint root;                 ///< how the world holds segment 0 (free by default)
  double total_mass = 0.0;
  double rest_height = 0.0;  ///< top minus bottom of every shape at rest
  /// the file's gravity (m/s²; JSON "gravity", MJCF `<option gravity>`), the scenarios' default
  Vector3d gravity{0.0, 0.0, -9.81};

  int segment_count() const { return static_cast<int>(segments.size()); }
  int joint_count() const { return static_cast<int>(joints.size()); }
  /// index of the named segment or -1
  int find_segment(const std::string& segment_name) const;
};

/// whether any joint of the model has a spring or a damper
bool has_joint_springs(const Model& model);
/// whether any joint of the model has armature
bool has_armature(const Model& model);

/// How a model file is read (MJCF's options; a JSON file has none)
struct ReadOptions {
  /// refuse what the testbed does not model instead of skipping it with a note (actuators
  /// without a control's force, sensors, tendons without effect, custom data, keyframes,
  /// cameras and lights)
  bool strict = false;
  /// let an MJCF <include> read a file outside the model file's folder
  bool include_outside = false;
};

/// Parses the JSON text of a model file. `source` names the file in error messages.
Model parse_model(const std::string& json_text, const std::string& source);
/// Loads a model file, or a built-in generated model `chain:N`. `note`, when given, gets what was
/// skipped as one line ("21 <motor>, 2 <camera>"), or nothing.
Model load_model_file(const std::string& path_or_chain, const ReadOptions& options = {},
                      std::string* note = nullptr);

#ifdef PUPPET_MODELS_DIR
/// The built-in figure's file: pinocchio.json in the models folder of the package this program
/// was built against (PUPPET_MODELS_DIR, which linking puppet::model defines: the source tree's
/// models/ in its own build, <prefix>/share/puppet/models once installed)
inline std::string pinocchio_path() { return PUPPET_MODELS_DIR "/pinocchio.json"; }
/// load_model_file, and `pinocchio`, the built-in figure, by name
inline Model load_model(const std::string& name, const ReadOptions& options = {},
                        std::string* note = nullptr) {
  return load_model_file(name == "pinocchio" ? pinocchio_path() : name, options, note);
}
#else
/// load_model_file (a program that defines no PUPPET_MODELS_DIR has no built-in figure by name)
inline Model load_model(const std::string& name, const ReadOptions& options = {},
                        std::string* note = nullptr) {
  return load_model_file(name, options, note);
}
#endif
/// N capsules (0.25 m tip to tip, 1 kg) hanging in a chain of free ball joints from z = 0.
Model make_chain(int n);

}  // namespace puppet
