// The model's joint limits as btMultiBody constraints (see limit_rows.cpp).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

#include <memory>

#include "puppet/model/model.h"

namespace puppet::reference::detail {

// Where a joint sits in a btMultiBody whose link frames are the segments' frames: the links of
// the model's child and parent segments (−1 for the base), whichever way the tree is rooted, and
// the link whose coordinates are the joint's (the child's, or the parent's in a tree rooted on
// the child's side).
struct JointLinks {
  int child = -1;
  int parent = -1;
  int coordinates = -1;
};

// limits the joint as the model says: a hinge's range, or a ball's swing ellipse and twist or box
// of Euler angles; the joint must outlive the constraint
std::unique_ptr<btMultiBodyConstraint> make_limit(btMultiBody* body, const JointLinks& links,
                                                  const Joint& joint);

// A hard pin: the point `local_point` of link `link` (its frame) held at a world target that
// moves. Like btMultiBodyPoint2Point, three Baumgarte rows; unlike it, each row aims at the
// target's velocity over the step, not at rest, so a point dragged at constant speed keeps up
// with its target instead of trailing it by v·dt·(1/m_erp − 1).
class PinRows final : public btMultiBodyConstraint {
 public:
  PinRows(btMultiBody* body, int link, const Vector3d& local_point, const Vector3d& target);

  // the target for the end of the next step; the one it replaces is where the target starts
  // the step, which gives its velocity (after a step both are the target: it rests until moved)
  void set_target(const Vector3d& target);
  void step_done() { previous_ = target_; }
  const Vector3d& target() const { return target_; }
  const Vector3d& previous_target() const { return previous_; }
  void restore(const Vector3d& target, const Vector3d& previous);

  void finalizeMultiDof() override;
  int getIslandIdA() const override;
  int getIslandIdB() const override;
  void debugDraw(btIDebugDraw* /*drawer*/) override {}
  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;

 private:
  btVector3 local_point_;
  Vector3d target_, previous_;
};

}  // namespace puppet::reference::detail
