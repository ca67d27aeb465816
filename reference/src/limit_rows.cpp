#include "limit_rows.h"

#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <array>
#include <cmath>
#include <numbers>

#include "bullet_common.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/rotation.h"

namespace puppet::reference::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// the island of a link's collider (every link has one, multibody.cpp), −1 without
int island(const btMultiBody* body, int link) {
  const btMultiBodyLinkCollider* collider =
      link < 0 ? body->getBaseCollider() : body->getLink(link).m_collider;
  return collider ? collider->getIslandTag() : -1;
}

// The model's own joint limits (the ones the procedural solver and the metrics use), as
// one-sided angular rows between the model's child segment (A) and parent segment (B), each
// C ≤ 0 with dC/dt = J · (ω_A − ω_B). Bullet's btMultiBodySphericalJointLimit bounds Euler angles
// whose x and y turn with the twist, and with the shoulders' 110° swing it blew up a free spinning
// puppet at 1.25 s while every joint was inside its limits (Settings::euler_ball_limits keeps it
// available); its btMultiBodyJointLimitConstraint acts on a hinge only at or past the limit, so
// an impact bounces back a fraction of the speed that depends on where the step ends (0 to
// m_erp, never converging with dt).
//
// A hinge: one row against its nearer end, C = θ − upper (or lower − θ), J = ± its axis.
// A swing–twist limit: twist about the joint frame's z within ±twist, swing inside the ellipse
// of half-angles swing_x, swing_y; two rows:
//   swing  C = φ − φ_max(u)  J = the swing axis u in world (φ_max: the ellipse along u)
//   twist  C = |τ| − τ_max    J = ± the twist rate's gradient (below)
// A box limit (euler_box.h): q_rel = R(e₀, θ₀) R(e₁, θ₁) R(e₂, θ₂) in the parent's joint frame,
// one row per angle with a range, against its nearer face:
//   C = θₖ − upperₖ (or lowerₖ − θₖ)  J = ± the k-th row of N⁻¹
// where ω_rel = N θ̇ with N's columns n₀ = e₀, n₁ = R₀ e₁, n₂ = R₀R₁ e₂, whose inverse's rows are
// (n₁ × n₂, n₂ × n₀, n₀ × n₁) / det N, det N = ±cos θ₁ (the middle angle stays within ±85°).
// Like Bullet's hinge limit the rows are speculative: inside the limit (C < 0) they allow the
// joint to reach the limit in this step and no further; outside, Baumgarte (m_erp) pushes back.
class LimitRows final : public btMultiBodyConstraint {
 public:
  LimitRows(btMultiBody* body, const JointLinks& links, const Joint& joint)
      : btMultiBodyConstraint(body, body, links.child, links.parent, row_count(joint), true,
                              joint.type == JointType::kHinge
                                  ? MULTIBODY_CONSTRAINT_LIMIT
                                  : MULTIBODY_CONSTRAINT_SPHERICAL_LIMIT),
        joint_(joint),
        coordinates_(links.coordinates) {
    m_maxAppliedImpulse = kMaxImpulse;
  }

  void finalizeMultiDof() override {
    allocateJacobiansMultiDof();
    m_numDofsFinalized = m_jacSizeBoth;
  }
  int getIslandIdA() const override { return island(m_bodyA, m_linkA); }
  int getIslandIdB() const override { return island(m_bodyA, m_linkB); }
  void debugDraw(btIDebugDraw* /*drawer*/) override {}

  // The joint is read from the two links' world frames (the link frames are the segments'), so
  // a joint reads the same whichever of its segments is nearer the tree's root; only its speed
  // is read from the coordinates, whose size does not depend on the direction.
  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override {
    if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
    const Matrix3d child_frame = world_basis(m_linkA) * joint_.frame_in_child.toRotationMatrix();
    const Matrix3d parent_frame = world_basis(m_linkB) * joint_.frame_in_parent.toRotationMatrix();
    Quaterniond q_rel = Quaterniond(parent_frame.transpose() * child_frame).normalized();
    if (q_rel.w() < 0.0) q_rel.coeffs() = -q_rel.coeffs();  // a matrix's quaternion has either sign
    const double* w = m_bodyA->getJointVelMultiDof(coordinates_);
    double speed = 0.0;
    for (int k = 0; k < m_bodyA->getLink(coordinates_).m_dofCount; ++k) speed += w[k] * w[k];
    speed = std::sqrt(speed);  // |ω_rel|, or |θ̇| for a hinge
    if (joint_.type == JointType::kHinge) {
      const Vector3d& axis = joint_.hinge_axis;
      const double angle = 2.0 * std::atan2(q_rel.vec().dot(axis), q_rel.w());  // w ≥ 0: |θ| ≤ π
      const bool towards_upper = angle >= 0.5 * (joint_.lower + joint_.upper);
      const double c = towards_upper ? angle - joint_.upper : joint_.lower - angle;
      if (out_of_reach(c, speed, info)) return;
      const Vector3d normal = child_frame * axis;  // dθ/dt = normal · (ω_child − ω_parent)
      add_row(rows, data, info, 0, towards_upper ? normal : Vector3d(-normal), c);
      return;
    }
    if (joint_.ball_limit == BallLimit::kEulerBox) {
      box_rows(rows, data, info, q_rel, parent_frame, speed);
      return;
    }
    const SwingTwist st = decompose_swing_twist(q_rel, Vector3d::UnitZ());

    // swing, applied in the parent's joint frame (q_rel = swing · twist)
    const Vector3d swing = quat_log(st.swing);
    const double phi = swing.norm();
    const Vector3d u = phi > 1e-12 ? Vector3d(swing / phi) : Vector3d::UnitX();
    if (phi > 1e-12 && (joint_.swing_x < kPi || joint_.swing_y < kPi)) {
      const double ex = joint_.swing_x > 0.0 ? swing.x() / joint_.swing_x : INFINITY;
      const double ey = joint_.swing_y > 0.0 ? swing.y() / joint_.swing_y : INFINITY;
      const double ellipse = std::hypot(ex, ey);  // 1 on the limit, radially
      const double c = std::isinf(ellipse) ? phi : phi * (1.0 - 1.0 / ellipse);
      // dφ/dt = u · ω_rel exactly
      add_row(rows, data, info, 0, parent_frame * u, c);
    }
    // twist about z. With ω_rel in the parent's joint frame, dτ/dt = (z − tan(φ/2)·(z × u))·ω_rel
    // (differentiate q_rel = exp(φu)·exp(τz)): the child's own z would let the twist run away
    // while a large swing changes direction. Undefined at a half-turn swing.
    if (joint_.twist < kPi && std::cos(0.5 * phi) > 1e-3) {
      const double sign = st.twist_angle >= 0.0 ? 1.0 : -1.0;
      const double c = std::abs(st.twist_angle) - joint_.twist;
      const Vector3d z = Vector3d::UnitZ();
      const Vector3d rate = z - std::tan(0.5 * phi) * z.cross(u);
      add_row(rows, data, info, 1, sign * (parent_frame * rate), c);
    }
  }

 private:
  // a link's orientation in world, as Bullet's forward kinematics left it at the start of the
  // step (it runs before the constraints' rows are made)
  Matrix3d world_basis(int link) const {
    const btMatrix3x3 basis = link < 0 ? btMatrix3x3(m_bodyA->getWorldToBaseRot().inverse())
                                       : m_bodyA->getLink(link).m_cachedWorldTransform.getBasis();
    Matrix3d out;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out(r, c) = basis[r][c];
    return out;
  }

  static int row_count(const Joint& joint) {
    if (joint.type == JointType::kHinge) return 1;
    return joint.ball_limit == BallLimit::kEulerBox ? 3 : 2;
  }

  void box_rows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                const btContactSolverInfo& info, const Quaterniond& q_rel,
                const Matrix3d& parent_frame, double omega) {
    const auto& order = joint_.box_order.axes;
    const Vector3d angles = euler_angles(joint_.box_order, q_rel);
    const Eigen::AngleAxisd r0(angles[0], Vector3d::Unit(order[0]));
    const Eigen::AngleAxisd r1(angles[1], Vector3d::Unit(order[1]));
    const std::array<Vector3d, 3> n = {Vector3d::Unit(order[0]), r0 * Vector3d::Unit(order[1]),
                                       r0 * (r1 * Vector3d::Unit(order[2]))};
    const double det = n[0].dot(n[1].cross(n[2]));
    const double speed = omega / std::abs(det);  // each angle's rate is at most this
    for (int k = 0; k < 3; ++k) {
      const double lower = joint_.box_lower[k], upper = joint_.box_upper[k];
      if (lower <= -kPi && upper >= kPi) continue;
      const bool towards_upper = angles[k] >= 0.5 * (lower + upper);
      const double c = towards_upper ? angles[k] - upper : lower - angles[k];
      if (out_of_reach(c, speed, info)) continue;
      const Vector3d rate = n[(k + 1) % 3].cross(n[(k + 2) % 3]) / det;  // dθₖ/dt = rate · ω_rel
      add_row(rows, data, info, k, parent_frame * (towards_upper ? rate : Vector3d(-rate)), c);
    }
  }

  // A speculative row far inside its limit never acts: it allows the joint −C/dt, more than it
  // can turn in the step. Such rows are left out, which keeps the solver's sweeps to the rows
  // that can act (every row in every sweep made a step 2.3 times slower). Out of reach: further
  // than 4 times the step's travel at the joint's speed now, plus 3° for what forces and other
  // rows add within the step.
  static bool out_of_reach(double c, double speed, const btContactSolverInfo& info) {
    return c < -(4.0 * speed * info.m_timeStep + 3.0 * kPi / 180.0);
  }

  void add_row(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
               const btContactSolverInfo& info, int index, const Vector3d& normal, double c) {
    // Bullet aims at dC/dt = −m_erp·C/dt; inside the limit the aim is −C/dt (reach it, no
    // further), hence the division. Only impulses that push back are allowed.
    const double error = c >= 0.0 ? c : c / info.m_erp;
    const btVector3 zero(0, 0, 0);
    btMultiBodySolverConstraint& row = rows.expandNonInitializing();
    fillMultiBodyConstraint(row, data, nullptr, nullptr, to_bt(normal), zero, zero, zero, error,
                            info, -m_maxAppliedImpulse, 0.0, true);
    row.m_orgConstraint = this;
    row.m_orgDofIndex = index;  // this constraint's row, where Bullet stores its impulse
  }

  const Joint& joint_;
  int coordinates_;
};

}  // namespace

std::unique_ptr<btMultiBodyConstraint> make_limit(btMultiBody* body, const JointLinks& links,
                                                  const Joint& joint) {
  return std::make_unique<LimitRows>(body, links, joint);
}

PinRows::PinRows(btMultiBody* body, int link, const Vector3d& local_point, const Vector3d& target)
    : btMultiBodyConstraint(body, nullptr, link, -1, 3, false, MULTIBODY_CONSTRAINT_POINT_TO_POINT),
      local_point_(to_bt(local_point)),
      target_(target),
      previous_(target) {
  m_maxAppliedImpulse = kMaxImpulse;
}

void PinRows::set_target(const Vector3d& target) {
  previous_ = target_;
  target_ = target;
}

void PinRows::restore(const Vector3d& target, const Vector3d& previous) {
  target_ = target;
  previous_ = previous;
}

void PinRows::finalizeMultiDof() {
  allocateJacobiansMultiDof();
  m_numDofsFinalized = m_jacSizeBoth;
}

int PinRows::getIslandIdA() const { return island(m_bodyA, m_linkA); }
int PinRows::getIslandIdB() const { return island(m_bodyA, m_linkA); }

// Row k: C = (p − T)·e_k with T the target, which moves at v_T = its travel over the step
// divided by it. The row aims at dC/dt = −m_erp·C/dt with C taken at the start of the step (p
// now, T where the step starts), that is at a point velocity v_T·e_k − m_erp·C/dt: on its
// target the point moves with it. Bullet's own point-to-point row holds p to the target at the
// end of the step at zero velocity, so a point dragged at speed v trails its target by
// v·dt·(1/m_erp − 1).
void PinRows::createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                                   const btContactSolverInfo& info) {
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  const btVector3 point = m_bodyA->localPosToWorld(m_linkA, local_point_);
  const btVector3 target = to_bt(previous_);
  const Vector3d velocity = (target_ - previous_) / info.m_timeStep;
  const btVector3 zero(0, 0, 0);
  for (int k = 0; k < 3; ++k) {
    btVector3 normal(0, 0, 0);
    normal[k] = 1.0;
    btMultiBodySolverConstraint& row = rows.expandNonInitializing();
    row.m_orgConstraint = this;
    row.m_orgDofIndex = k;
    // the row's other side is the world: no body, no velocity of its own
    row.m_solverBodyIdA = data.m_fixedBodyId;
    row.m_solverBodyIdB = data.m_fixedBodyId;
    fillMultiBodyConstraint(row, data, nullptr, nullptr, zero, normal, point, target,
                            (point - target)[k], info, -m_maxAppliedImpulse, m_maxAppliedImpulse,
                            false, 1.0, false, velocity[k]);
  }
}

}  // namespace puppet::reference::detail
