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

// The model's own joint limits (the ones the procedural solver and the metrics use), as
// one-sided angular rows between the link (A) and its parent (B), each C ≤ 0 with
// dC/dt = J · (ω_A − ω_B). Bullet's btMultiBodySphericalJointLimit bounds Euler angles whose x
// and y turn with the twist, and with the shoulders' 110° swing it blew up a free spinning
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
  LimitRows(btMultiBody* body, int link, const Joint& joint, const Quaterniond& joint_in_link)
      : btMultiBodyConstraint(
            body, body, link, body->getLink(link).m_parent, row_count(joint), true,
            joint.type == JointType::kHinge ? MULTIBODY_CONSTRAINT_LIMIT
                                            : MULTIBODY_CONSTRAINT_SPHERICAL_LIMIT),
        joint_(joint),
        joint_in_link_(joint_in_link),
        identity_(joint_in_link.isApprox(Quaterniond::Identity(), 1e-15)) {
    m_maxAppliedImpulse = kMaxImpulse;
  }

  void finalizeMultiDof() override {
    allocateJacobiansMultiDof();
    m_numDofsFinalized = m_jacSizeBoth;
  }
  int getIslandIdA() const override { return island(m_linkA); }
  int getIslandIdB() const override { return island(m_linkB); }
  void debugDraw(btIDebugDraw* /*drawer*/) override {}

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override {
    if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
    if (joint_.type == JointType::kHinge) {
      // θ is the model's right-handed angle about the link's axis (multibody.cpp)
      const double angle = m_bodyA->getJointPos(m_linkA);
      const bool towards_upper = angle >= 0.5 * (joint_.lower + joint_.upper);
      const double c = towards_upper ? angle - joint_.upper : joint_.lower - angle;
      if (out_of_reach(c, std::abs(m_bodyA->getJointVel(m_linkA)), info)) return;
      const btVector3 axis =
          m_bodyA->localDirToWorld(m_linkA, m_bodyA->getLink(m_linkA).getAxisTop(0));
      add_row(rows, data, info, 0, towards_upper ? from_bt(axis) : Vector3d(-from_bt(axis)), c);
      return;
    }
    // the joint coordinate (x, y, z, w) is the model's q_rel seen in the link frame (A·q_rel·A⁻¹,
    // multibody.cpp), and the child's joint frame is the link frame turned by A
    const double* p = m_bodyA->getJointPosMultiDof(m_linkA);
    Quaterniond q_rel = Quaterniond(p[3], p[0], p[1], p[2]).normalized();
    const btMatrix3x3 link_basis = m_bodyA->localFrameToWorld(m_linkA, btMatrix3x3::getIdentity());
    Matrix3d child_frame;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) child_frame(r, c) = link_basis[r][c];
    if (!identity_) {
      q_rel = joint_in_link_.conjugate() * q_rel * joint_in_link_;
      child_frame = child_frame * joint_in_link_.toRotationMatrix();
    }
    // the parent's joint frame in world
    const Matrix3d parent_frame = child_frame * q_rel.conjugate().toRotationMatrix();
    if (joint_.ball_limit == BallLimit::kEulerBox) {
      box_rows(rows, data, info, q_rel, parent_frame);
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
  int island(int link) const {
    const btMultiBodyLinkCollider* collider =
        link < 0 ? m_bodyA->getBaseCollider() : m_bodyA->getLink(link).m_collider;
    return collider ? collider->getIslandTag() : -1;
  }

  static int row_count(const Joint& joint) {
    if (joint.type == JointType::kHinge) return 1;
    return joint.ball_limit == BallLimit::kEulerBox ? 3 : 2;
  }

  void box_rows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                const btContactSolverInfo& info, const Quaterniond& q_rel,
                const Matrix3d& parent_frame) {
    const auto& order = joint_.box_order.axes;
    const Vector3d angles = euler_angles(joint_.box_order, q_rel);
    const Eigen::AngleAxisd r0(angles[0], Vector3d::Unit(order[0]));
    const Eigen::AngleAxisd r1(angles[1], Vector3d::Unit(order[1]));
    const std::array<Vector3d, 3> n = {Vector3d::Unit(order[0]), r0 * Vector3d::Unit(order[1]),
                                       r0 * (r1 * Vector3d::Unit(order[2]))};
    const double det = n[0].dot(n[1].cross(n[2]));
    // each angle turns at most |ω_rel| / |det N| (|n_i × n_j| ≤ 1)
    const double* w = m_bodyA->getJointVelMultiDof(m_linkA);
    const double speed = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / std::abs(det);
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
  Quaterniond joint_in_link_;
  bool identity_;  // the link frame is the joint frame: nothing to turn
};

}  // namespace

std::unique_ptr<btMultiBodyConstraint> make_limit(btMultiBody* body, int link, const Joint& joint,
                                                  const Quaterniond& joint_in_link) {
  return std::make_unique<LimitRows>(body, link, joint, joint_in_link);
}

}  // namespace puppet::reference::detail
