// A solver's scratch, sized once for its model: nothing in it outlives a step. Private to
// procedural/.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "joint_limits.h"
#include "model_tables.h"
#include "puppet/procedural/settings.h"
#include "puppet/procedural/state.h"

namespace puppet::procedural {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix36d = Eigen::Matrix<double, 3, 6>;

// one node of rule tree's system (tree_projection.cpp): a segment (six unknowns: Δx world, Δθ in
// its frame) or a constraint (a joint's point and active limit rows, or the first pin). Blocks
// are stored 6×6; a three-row constraint uses their top-left 3×3 and 3×6 (or 6×3) corners.
struct TreeNode {
  enum Kind { kSegment, kJoint, kPin, kHold };
  Kind kind = kSegment;
  int index = -1;                     // segment, joint or pin (the world's hold on the root: -1)
  int parent = -1;                    // node nearer the root, −1 for the root
  int rows = 0;                       // its unknowns: 6 for a segment, a constraint's rows (3 to 6)
  Matrix6d d;                         // diagonal block, then its Schur complement over the subtree
  Matrix6d up;                        // the block coupling its rows to its parent's
  Matrix6d x;                         // D⁻¹ up
  Matrix6d inverse;                   // D⁻¹ (a three-row constraint: its top-left 3×3)
  Vector6d b;                         // right side
  Vector6d alpha = Vector6d::Zero();  // a constraint's α̃ per row
  Vector6d lambda = Vector6d::Zero();  // and its multipliers accumulated over the substep
};
// a pin after the first (every pin, when the world holds the root): a loop through the world,
// closed through its Schur complement
struct TreeLoop {
  int node = -1;  // its segment's node
  double alpha = 0.0;
  Matrix36d jacobian;
  Vector3d c;  // C + α̃ λ
  Vector3d lambda = Vector3d::Zero();
};
inline constexpr int kMaxLoopRows = 3 * kMaxPins;
using LoopMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxLoopRows, kMaxLoopRows>;
using LoopVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxLoopRows, 1>;

// sized once for the model; nothing in it outlives a step
struct Workspace {
  // sized for the model; a large model's two orders filled once (from segment 0)
  Workspace(const Model& model, const ModelTables& tables);

  // composite mass properties of each preorder subtree (rule `subtree`)
  std::vector<double> subtree_mass;
  std::vector<Vector3d> subtree_moment;  // Σ m·x
  std::vector<Matrix3d> subtree_second;  // Σ (R I Rᵀ + m(|x|²E − x xᵀ)) about the origin
  // accumulated rigid motion of each segment during a pass (rule `subtree`)
  std::vector<Quaterniond> motion_q;
  std::vector<Vector3d> motion_t;
  std::vector<Vector3d> tremble_delta;   // this substep's tremble displacement per segment
  std::vector<Wrench> user_wrenches;     // this substep's user forces per segment (user_forces.h)
  bool user_pulled = false;              // user_wrenches holds forces (else zeros)
  std::vector<Wrench> applied_wrenches;  // with joint springs: the user's and the springs'
                                         // forces together (joint_springs.h)
  // xpbd: each constraint's accumulated multiplier over this substep's sweeps (world), read by
  // the compliance term α̃λ; reset at every substep
  std::vector<Vector3d> joint_lambda;  // by joint
  std::vector<Vector3d> limit_lambda;  // by joint
  std::array<Vector3d, kMaxPins> pin_lambda{};
  // each segment's inverse inertia (world) at the substep's start: the lever arms' (two_sided.cpp)
  std::vector<Matrix3d> start_inverse_inertia;
  // the limits' velocity pass (limit_velocities.cpp): by joint, whether the substep's position
  // pass corrected it past a limit; by segment, its angular velocity before that pass
  std::vector<char> limit_violated;
  std::vector<LimitRows> limit_rows;  // by joint: the rows found past their bounds
  std::vector<Vector3d> w_before;
  // tree: segments, joints and the first pin as the nodes of one factorisation (2n), the
  // solution per node, one more right side (a column of H⁻¹Gᵀ), every node's index, the loops'
  // nodes with their ancestors (and their marks), and the loops
  std::vector<TreeNode> tree_nodes;
  std::vector<Vector6d> tree_solution;
  std::vector<Vector6d> tree_column;
  std::vector<int> tree_all;  // 0, 1, …
  std::vector<int> tree_path;
  std::vector<char> tree_marked;
  std::vector<Matrix3d> tree_rotations;  // each segment's, at the current linearisation
  std::array<TreeLoop, kMaxPins> tree_loops{};
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

}  // namespace puppet::procedural
