// The solver's stages, in the order a substep runs them (solver.cpp), and the passes they are
// made of. Private to procedural/. Each declaration names the file that defines it.
//
//   update      update.cpp, tremble.cpp       every segment alone under its forces
//   adjust      adjust.cpp                    the rule's position pass: rules/*.cpp, made of the
//                                             one-sided pass (one_sided_pass.cpp) or of shared
//                                             corrections (two_sided.cpp)
//   contacts    contacts.cpp                  the ground, as the rule's contact policy says
//   velocities  velocities.cpp, contacts.cpp  v, ω from the poses; the ground's velocity pass
#pragma once

#include <array>
#include <span>
#include <vector>

#include "geometry.h"
#include "joint_limits.h"
#include "model_tables.h"
#include "puppet/model/euler_box.h"
#include "puppet/procedural/settings.h"
#include "puppet/procedural/state.h"
#include "workspace.h"

namespace puppet::procedural {

// per-substep pin targets (already interpolated across substeps)
using PinTargets = std::array<Vector3d, kMaxPins>;

// --- stage 1, update.cpp, tremble.cpp
// `user`: the user's forces per segment (grabs and tremble, user_forces.h), or empty for none
void update(const Model& model, const Environment& environment, std::span<const Wrench> user,
            State& state, double h);
// the seed's tremble (§3.4), added to positions at the end of update; delta per segment out
void tremble(const Model& model, const Settings& settings, State& state, double h,
             std::vector<Vector3d>& delta);

// --- stage 2, adjust.cpp: pins, joints and limits from the anchor, by the settings' rule
void adjust(const Model& model, const Settings& settings, const Environment& environment,
            const ModelTables& tables, int anchor, const PinTargets& targets, State& state,
            Workspace& workspace, double h);

// --- forced_rotation.cpp
// The correction that moves point c_b of `body` onto c_a: the rule's forced rotation R about
// the body's centre (eqs. 2–3 or their readings, rules/*.cpp), then the forced translation of
// eq. 5, T = (I − R)·r + s, which closes the gap exactly.
// (The literal rule's dt and mass cancel out of eqs. 2–3: no rule needs the step length.)
// The weighted reading here is for a composite body (rule subtree); a single segment is closed by
// close_segment_point(), or in a joint by its constant gain (JointTerms::rotation_gain).
Correction close_point(Rule rule, const MovingBody& body, const Vector3d& c_b, const Vector3d& c_a);

// --- one_sided_pass.cpp
// which pins a one-sided pass closes: none (a re-pass after contacts), all, or the rigid ones
// (relaxed's final pass: its sweeps pulled the compliant ones)
enum class PinClosure { kNone, kAll, kRigidOnly };
// one-sided pass of `rule` over `order`: the anchor to its pin, then every joint from the
// anchor, each moving its far side alone (rule subtree: the far side's whole subtree)
void one_sided_pass(const Model& model, std::span<const JointTerms> joints, Rule rule,
                    const AnchorOrder& order, PinClosure closure, const PinTargets& targets,
                    State& state, Workspace& workspace);
// a compliant pin's target moved back toward its point by what its compliance holds over h (the
// one-sided rules close the softened target exactly)
void soften_compliant_targets(const Model& model, const State& state, double h,
                              PinTargets& targets);
// The parent's side of a joint at the segments' orientations: its point in the parent's frame
// (parent_anchor: a box of hinges at different points carries it along its angles) and the
// parent's point mass matrix there (JointTerms' own unless the point moves)
struct ParentSide {
  Vector3d anchor;
  Matrix3d point_mass;
};
inline ParentSide parent_side(const Model& model, const JointTerms& terms, const Joint& joint,
                              const Quaterniond& q_parent, const Quaterniond& q_child) {
  if (!has_box_offsets(joint)) return {joint.anchor_in_parent, terms.point_mass[0]};
  const Segment& parent = model.segments[joint.parent];
  const Vector3d anchor = parent_anchor(joint, q_parent, q_child);
  return {anchor, diagonal_point_mass_matrix(parent.inv_mass, parent.inv_inertia, anchor)};
}

// the joint point in a's frame and in b's frame, for a link of an anchor order
struct LinkAnchors {
  const Vector3d& local_a;
  const Vector3d& local_b;
};
inline LinkAnchors link_anchors(const Joint& joint, const AnchorOrder::Link& link) {
  if (link.b_is_child) return {joint.anchor_in_parent, joint.anchor_in_child};
  return {joint.anchor_in_child, joint.anchor_in_parent};
}

// --- two_sided.cpp
// two-sided corrections of a pin, a joint's point, a joint's limit: α̃ = α/h² is the compliance
// (0: rigid, and then `lambda` is not read), lambda the multiplier accumulated over the substep
// (world). `start`, by segment: the inverse inertias (world) at the substep's start, whose
// orientations then give the lever arms (Settings::start_lever_arms); null: the current pose's
void share_pin_correction(const Model& model, const Pin& pin, const Vector3d& target,
                          double alpha_tilde, Vector3d* lambda, const Matrix3d* start,
                          State& state);
void share_joint_correction(const Model& model, const JointTerms& terms, const Joint& joint,
                            double alpha_tilde, Vector3d* lambda, const Matrix3d* start,
                            State& state);
// the world's hold on the root (RootJoint), rigid: the anchor's stray from where the hold lets it
// be closed as a pin's (the segment's generalised inverse mass at the anchor, its turns limited to
// those the hold leaves free, along the held directions only, and a slide's range along its own),
// then the held directions of its orientation turned back about the anchor (a weld's and a
// slide's all; a hinge's axis, and its range about it), which leaves the anchor where it is
void hold_root(const Model& model, const Matrix3d* start, State& state);
// each segment's inverse inertia in world at the substep's start (state.q_prev), for `start`
void start_inverse_inertias(const Model& model, const State& state, std::span<Matrix3d> out);
// the limit's, by the limit functions (xpbd) or the clamp (`functions` false: relaxed); true
// when a limit function was past its bound (the velocity pass's mark), whose rows are then in
// `rows` (their directions in the child's frame)
bool share_limit_correction(const Model& model, const JointTerms& terms, const Joint& joint,
                            double alpha_tilde, Vector3d* lambda, LimitRows* rows, bool functions,
                            State& state);

// --- stage 3, contacts.cpp
// What the contact stage does after a rule's adjust (the rule's contact policy):
enum class ContactPolicy {
  kInAdjust,          // xpbd, tree: the ground is a constraint of their sweeps or iterations
  kPushOut,           // relaxed: push out of the ground; what it reopens is reported as gap
  kPushOutAndRepass,  // the one-sided rules: push out, then re-run the pass from the deepest
};
ContactPolicy contact_policy(Rule rule);
// the stage: the ground as the rule's policy says
void contacts(const Model& model, const Settings& settings, const Environment& environment,
              const ModelTables& tables, const PinTargets& targets, State& state,
              Workspace& workspace);
// push shape points out of the ground with friction; returns the deepest-penetrating segment
// before correction, or -1 without contact
int resolve_contacts(const Model& model, const Environment& environment, State& state);
// push one segment out of the ground (shared by resolve_contacts and the sweeps); returns the
// deepest penetration (m) found before the correction
double push_out_of_ground(const Model& model, const Environment& environment, int segment,
                          State& state);
// whether the rule's velocity stage runs the ground's velocity pass (xpbd and tree: their
// positions cannot say that a contact stopped a point)
bool needs_ground_velocity_pass(Rule rule);
// the ground's velocity pass: a contact point's approaching normal velocity removed (no
// restitution), Coulomb friction bounded by μ times that impulse
void ground_velocity_pass(const Model& model, const Environment& environment, State& state);

// --- stage 4, velocities.cpp: velocities from the corrected poses and the previous ones
void derive_velocities(const Model& model, State& state, const std::vector<Vector3d>& tremble_delta,
                       double h);

// --- limit_velocities.cpp: the limits' velocity pass
// one joint's part of the pass: its rows (the limit functions its position pass found past their
// bounds) get the rate −restitution × the rate they came in with (rate_before, the child's
// frame), by opposite angular impulses and an impulse at the joint point
void hold_limit_rates(const Model& model, const JointTerms& terms, const Joint& joint,
                      const LimitRows& rows, double restitution, const Vector3d& rate_before,
                      BodyState& parent, BodyState& child);
// before adjust: no joint marked, and every segment's angular velocity kept (the update's: the
// rates the limits come in with); the rules mark a joint whose limit they corrected past a bound
void begin_limit_marks(const State& state, Workspace& ws);
// a mark's row count that asks the pass for the rows at the pose it finds, those within
// kAtLimit (rad) of their bounds (tree's); else the rows the mark carries (xpbd's)
inline constexpr int kRowsAtPose = -1;
inline constexpr double kAtLimit = 1e-4;
inline void mark_limit(Workspace& ws, int joint, const LimitRows& rows) {
  ws.limit_violated[joint] = 1;
  ws.limit_rows[joint] = rows;
}
// after derive_velocities: every marked joint's rows still at their bound (limit_velocities.cpp)
void limit_velocity_pass(const Model& model, const ModelTables& tables, double restitution,
                         const Workspace& ws, State& state);

}  // namespace puppet::procedural
