// The seed paper's procedural solver (Bae, Baek, Lee & Ryu 2001): each segment moves alone
// under its forces (update), then one geometric pass over the tree rotates and translates
// segments so that joints meet again and limits hold (adjust). No linear system is solved.
//
//   step(dt) = for each substep: update → adjust → resolve_contacts → derive_velocities
//
// shared/DESIGN.md, "The procedural solver", defines each stage and the adjust rules.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::procedural {

// how a joint's gap is split between b's rotation and translation (DESIGN.md, "Adjust rules")
// (the seed's readings, then `xpbd`, the position-based family's substepped two-sided solver,
// and `tree`, the same projection solved exactly on the tree)
enum class Rule { kLiteral, kSmoothed, kWeighted, kSubtree, kRelaxed, kXpbd, kTree };
inline constexpr std::array kAllRules = {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted,
                                         Rule::kSubtree, Rule::kRelaxed,  Rule::kXpbd,
                                         Rule::kTree};
std::string_view rule_name(Rule rule);
std::optional<Rule> parse_rule(std::string_view name);

// iterations or substeps left at this value take the rule's own (rule_defaults())
constexpr int kRuleDefault = -1;
// xpbd's substeps per step unless told (chosen by measurement: docs, the substep sweep)
constexpr int kXpbdSubsteps = 8;
// tree's substeps and Newton iterations per substep unless told (chosen by measurement)
constexpr int kTreeSubsteps = 8;
constexpr int kTreeIterations = 1;

struct Settings {
  Rule rule = Rule::kRelaxed;
  // two-sided sweeps per substep (relaxed: 4, xpbd: 1); tree: Newton iterations per substep
  int iterations = kRuleDefault;
  int substeps = kRuleDefault;  // each step(dt) runs this many stages of dt/substeps (xpbd: 8)
  // xpbd and tree: compliance of the joints' point constraints (m/N) and of their limits
  // (rad/(N·m)); 0 is rigid, as every model joint is. A pin's compliance is the pin's own
  // (Pin::compliance).
  double joint_compliance = 0.0;
  double limit_compliance = 0.0;
  bool derive_velocities = true;  // v, ω from the corrected poses (the seed is silent)
  bool tremble = false;           // the seed's active response (§3.4)
  bool time_stages = false;       // measure each stage's wall time (costs a few clock reads)
  uint64_t tremble_seed = 2001;
};

// empty when valid, else what is wrong
std::string validate(const Settings& settings);
// the settings with every kRuleDefault replaced by the rule's own value
Settings rule_defaults(Settings settings);

constexpr int kMaxPins = 4;

// everything that changes during a run; allocated once, plain contiguous data
struct State {
  std::vector<BodyState> bodies;  // per segment
  std::vector<Vector3d> x_prev;   // poses at the start of the (sub)step
  std::vector<Quaterniond> q_prev;
  std::vector<Vector3d> user_force;  // world, at the COM; left in place between steps
  std::vector<Vector3d> user_torque;
  std::vector<Vector3d> tremble_offset;  // current tremble displacement per segment
  std::array<Pin, kMaxPins> pins{};
  std::array<Vector3d, kMaxPins> pin_previous_target{};
  std::array<double, kMaxPins> pin_force{};  // last correction expressed as a force (N)
  int pin_count = 0;
  double tremble_phase = 0.0;
  double time = 0.0;
  bool diverged = false;  // a non-finite value appeared; the state is no longer advanced
  double diverged_time = 0.0;
};

enum Stage { kUpdate, kAdjust, kContacts, kVelocities, kStageCount };
inline constexpr std::array<std::string_view, kStageCount> kStageNames = {"update", "adjust",
                                                                          "contacts", "velocities"};

// An order of the tree from one anchor, computed once per anchor: segments in depth-first
// preorder, each with the joint that places it and the segment it hangs from in this order.
struct AnchorOrder {
  struct Link {
    int joint = -1;
    int a = -1;              // placed already
    int b = -1;              // moved now
    bool b_is_child = true;  // false when the edge is walked against the model's direction
  };
  int anchor = -1;
  std::vector<Link> links;           // links[k] places preorder[k + 1]
  std::vector<int> preorder;         // segments, anchor first
  std::vector<int> subtree_end;      // preorder position one past the subtree of preorder[k]
  std::vector<int> parent_position;  // preorder position of the segment preorder[k] hangs from
  // links in breadth-first order: parents still come before children, and consecutive links
  // (siblings, cousins) are independent, so the processor overlaps their latency. A one-sided
  // pass of single segments gives bit for bit the same result in any parent-first order.
  std::vector<AnchorOrder::Link> level_links;
};
// the joints at each segment, both ways (compressed rows: joints[offsets[s] .. offsets[s + 1]))
struct Incidence {
  std::vector<int> offsets;
  std::vector<int> joints;
};
Incidence make_incidence(const Model& model);
// scratch of fill_anchor_order, sized by the model: filling allocates nothing once reserved
struct AnchorOrderScratch {
  std::vector<int> position, depth, depth_start;
  struct Frame {
    int segment, via_joint, from_position;
  };
  std::vector<Frame> stack;
  void reserve(int segments);
};
// the order from `anchor` into `order` in O(n), reusing its storage (no allocation when `order`
// has held an order of this model and `scratch` is reserved for it)
void fill_anchor_order(const Model& model, const Incidence& incidence, int anchor,
                       AnchorOrder& order, AnchorOrderScratch& scratch);
AnchorOrder make_anchor_order(const Model& model, int anchor);

// What the corrections read of one joint. A segment's inertia is diagonal and constant in its own
// frame, and so is its joint point, so everything here is too: [0] is the parent's side, [1] the
// child's (index by b_is_child).
struct JointTerms {
  // cos(ρ/2) for the largest angle ρ that no limit of the joint can reach (limit_free_w())
  double limit_free_w = 2.0;
  // Fc ⊗ Fp⁻¹, the joint's frame in the child carried into the parent's: w is unchanged by
  // conjugation, so w(q_rel) = w(Fp⁻¹ q_p⁻¹ q_c Fc) = q_p · (q_c ⊗ frame_shift), a 4-D dot product
  // that tells a joint surely inside its limits without forming q_rel
  Quaterniond frame_shift = Quaterniond::Identity();
  // K = E/m − [r]× D⁻¹ [r]× of the joint point, r its offset from the segment's centre:
  // relaxed's shared corrections add the two sides' K in one frame
  std::array<Matrix3d, 2> point_mass;
  // the weighted rule's rotation vector of that side per unit gap, both in its frame:
  // D⁻¹ [r]× K⁻¹ (the minimum-energy correction of the gap, made a constant matrix)
  std::array<Matrix3d, 2> rotation_gain;
  // the literal rule: |r × s|² below which moving that side closes the joint by translation alone
  // (literal_still_cross(), squared; at least the parallel threshold)
  std::array<double, 2> literal_still_cross2{0.0, 0.0};
};

// Everything the solver reads that depends on the model alone, built once. Solvers of one model
// (a crowd's puppets) share one table instead of each holding a copy.
// Every anchor's order is kept for models of up to kKeptOrderSegments segments (O(n²) memory:
// 0.9 MB for 128); a larger model keeps none, and each solver fills the orders it needs into its
// workspace when its anchor changes (O(n) each, see anchor_order()).
inline constexpr int kKeptOrderSegments = 128;
struct ModelTables {
  std::vector<AnchorOrder> orders;  // by anchor segment: every one, or none for a large model
  std::vector<JointTerms> joints;   // by joint
  Incidence incidence;
};
std::shared_ptr<const ModelTables> make_model_tables(const Model& model);

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix36d = Eigen::Matrix<double, 3, 6>;

// one node of rule tree's system (tree_projection.cpp): a segment (six unknowns: Δx world, Δθ in
// its frame) or a constraint (a joint's point and active limit rows, or the first pin). Blocks
// are stored 6×6; a three-row constraint uses their top-left 3×3 and 3×6 (or 6×3) corners.
struct TreeNode {
  enum Kind { kSegment, kJoint, kPin };
  Kind kind = kSegment;
  int index = -1;                     // segment, joint or pin
  int parent = -1;                    // node nearer the root, −1 for the root
  int rows = 0;                       // its unknowns: 6 for a segment, a constraint's rows (3 to 6)
  Matrix6d d;                         // diagonal block, then its Schur complement over the subtree
  Matrix6d up;                        // the block coupling its rows to its parent's
  Matrix6d x;                         // D⁻¹ up
  Vector6d b;                         // right side
  Vector6d alpha = Vector6d::Zero();  // a constraint's α̃ per row
  Vector6d lambda = Vector6d::Zero();  // and its multipliers accumulated over the substep
  Eigen::LLT<Matrix6d> factor;         // of ±D: a segment's D, a wide constraint's −D
  Eigen::LLT<Matrix3d> factor3;        // a three-row constraint's −D
};
// a pin after the first: a loop through the world, closed through its Schur complement
struct TreeLoop {
  int node = -1;  // its segment's node
  double alpha = 0.0;
  Matrix36d jacobian;
  Vector3d c;  // C + α̃ λ
  Vector3d lambda = Vector3d::Zero();
};
inline constexpr int kMaxLoopRows = 3 * (kMaxPins - 1);
using LoopMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxLoopRows, kMaxLoopRows>;
using LoopVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxLoopRows, 1>;

// sized once for the model; nothing in it outlives a step
struct Workspace {
  // composite mass properties of each preorder subtree (rule `subtree`)
  std::vector<double> subtree_mass;
  std::vector<Vector3d> subtree_moment;  // Σ m·x
  std::vector<Matrix3d> subtree_second;  // Σ (R I Rᵀ + m(|x|²E − x xᵀ)) about the origin
  // accumulated rigid motion of each segment during a pass (rule `subtree`)
  std::vector<Quaterniond> motion_q;
  std::vector<Vector3d> motion_t;
  std::vector<Vector3d> tremble_delta;  // this substep's tremble displacement per segment
  // xpbd: each constraint's accumulated multiplier over this substep's sweeps (world), read by
  // the compliance term α̃λ; reset at every substep
  std::vector<Vector3d> joint_lambda;  // by joint
  std::vector<Vector3d> limit_lambda;  // by joint
  std::array<Vector3d, kMaxPins> pin_lambda{};
  // tree: segments, joints and the first pin as the nodes of one factorisation (2n), the
  // solution per node, H⁻¹Gᵀ's columns per loop row, and the loops
  std::vector<TreeNode> tree_nodes;
  std::vector<Vector6d> tree_solution;
  std::vector<Vector6d> tree_columns;  // kMaxLoopRows × tree_nodes.size()
  std::array<TreeLoop, kMaxPins - 1> tree_loops{};
  Eigen::PartialPivLU<LoopMatrix> tree_loop_factor;
  // a large model's anchor orders (ModelTables keeps none): the last two anchors asked for (a
  // pin's and a contact's), filled in place
  std::array<AnchorOrder, 2> orders;
  std::array<int, 2> order_anchor{-1, -1};
  int order_next = 0;
  AnchorOrderScratch order_scratch;
};
// the order from `anchor`: the tables' when they keep every one, else the workspace's, filled
// now if it does not hold it (O(n), no allocation)
const AnchorOrder& anchor_order(const Model& model, const ModelTables& tables, Workspace& ws,
                                int anchor);

class Solver {
 public:
  // the model must outlive the solver; throws std::invalid_argument on invalid settings.
  // `tables`: make_model_tables(model), to share them with other solvers of the model (built
  // here when null; tables of another model throw std::invalid_argument)
  Solver(const Model& model, const Settings& settings, const Environment& environment,
         std::shared_ptr<const ModelTables> tables = nullptr);

  // place every segment (poses and velocities in world); clears pins, forces and time
  void reset(std::span<const BodyState> bodies);
  // pins change rarely (a user grabs or lets go). At most kMaxPins; the first pin is the adjust
  // pass's anchor.
  void set_pins(std::span<const Pin> pins);
  // move the pins' targets (world) for the end of the next step
  void set_pin_targets(std::span<const Vector3d> targets);
  void step(double dt);
  // One stage of a substep of length h on the current state, with the pins' targets of the last
  // substep: step() runs kUpdate … kVelocities in order; benchmarks time them one at a time.
  void run_stage(Stage stage, double h);
  // asks the cache for everything step() reads, without waiting for it: a crowd issues this for
  // the next puppet while it steps the current one
  void prefetch() const;

  const Model& model() const { return model_; }
  const Settings& settings() const { return settings_; }
  const Environment& environment() const { return environment_; }
  const State& state() const { return state_; }
  State& mutable_state() { return state_; }
  // wall time (s) of each stage in the last step; zeros unless settings.time_stages
  const std::array<double, kStageCount>& stage_seconds() const { return stage_seconds_; }

 private:
  void substep(double h, double target_fraction);
  void check_finite();

  const Model& model_;
  Settings settings_;
  Environment environment_;
  State state_;
  Workspace workspace_;
  std::shared_ptr<const ModelTables> tables_;
  std::array<double, kStageCount> stage_seconds_{};
  std::array<Vector3d, kMaxPins> substep_targets_{};  // pins' targets at the end of the substep
};

}  // namespace puppet::procedural
