// The geometry the stages share: rigid motions, a rule's correction, the body a correction moves
// and its point mass matrices. Private to procedural/.
#pragma once

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/model/rotation.h"

namespace puppet::procedural {

// false exactly for the identity a correction returns when it has nothing to do (its vector part
// is zero): such corrections skip every quaternion product
inline bool rotates(const Quaterniond& q) { return q.x() != 0.0 || q.y() != 0.0 || q.z() != 0.0; }

// a rigid motion p ↦ q·p + t, applied to a whole segment (or a subtree of them). Most
// corrections are pure translations (the literal rule's, a limit that holds).
struct Motion {
  Quaterniond q = Quaterniond::Identity();
  Vector3d t{0, 0, 0};

  bool rotates() const { return puppet::procedural::rotates(q); }
  Vector3d apply(const Vector3d& p) const { return rotates() ? Vector3d(q * p + t) : p + t; }
  void apply(BodyState& body) const {
    if (!rotates()) {
      body.x += t;
      return;
    }
    body.x = q * body.x + t;
    body.q = renormalized(q * body.q);
  }
  // (this ∘ inner)(p) = this(inner(p))
  Motion after(const Motion& inner) const { return {q * inner.q, apply(inner.t)}; }
  // rotation `rotation` about the point `centre`
  static Motion about(const Quaterniond& rotation, const Vector3d& centre) {
    return {rotation, centre - rotation * centre};
  }
};

// What close_point() gives: the rule's rotation R of a body about its centre, then the
// translation T of its centre (eq. 5). A single segment takes it directly (its centre is its x);
// a composite turns it into the rigid motion of everything it carries.
struct Correction {
  Quaterniond rotation = Quaterniond::Identity();
  Vector3d translation{0, 0, 0};

  bool rotates() const { return puppet::procedural::rotates(rotation); }
  // p ↦ centre + T + R (p − centre)
  Motion motion(const Vector3d& centre) const {
    if (!rotates()) return {rotation, translation};
    return {rotation, centre + translation - rotation * centre};
  }
  // a single segment: x ↦ x + T, q ↦ R q
  void apply(BodyState& body) const {
    body.x += translation;
    if (rotates()) body.q = renormalized(rotation * body.q);
  }
};

// The side of a joint that a correction moves: one segment, or a composite subtree. Its inertia
// is kept in `frame`: a segment's own orientation, where it is diagonal and constant (no tensor
// is built per correction), or for a composite the rotation its pass has given it so far, where
// its tensor is the one built at the pass's start (full, no R I Rᵀ per correction).
struct MovingBody {
  double mass = 0.0, inv_mass = 0.0;
  Vector3d centre{0, 0, 0};  // centre of mass, world
  Quaterniond frame = Quaterniond::Identity();
  bool diagonal = false;           // a segment: inertia_diag; else the two tensors
  Vector3d inertia_diag{0, 0, 0};  // about the centre, in frame
  Matrix3d inertia;                // a composite's tensor, in frame; unset for a segment
  Matrix3d inertia_inv;            // its inverse

  Vector3d to_frame(const Vector3d& world) const { return frame.conjugate() * world; }
  Vector3d to_world(const Vector3d& local) const { return frame * local; }
  // aᵀ I a, in frame
  double inertia_along(const Vector3d& a) const {
    return diagonal ? a.cwiseAbs2().dot(inertia_diag) : a.dot(inertia * a);
  }
  // an upper bound of inertia_along over unit axes: the largest principal moment, or for a
  // composite the trace (the sum of its principal moments)
  double largest_moment() const { return diagonal ? inertia_diag.maxCoeff() : inertia.trace(); }
};

// a segment as the body a correction moves, in its own frame
MovingBody single_body(const Segment& segment, const BodyState& body);

// the 3×3 effective mass of a point at offset r from the centre, K = E/m − [r]× I⁻¹ [r]×, for an
// inverse inertia tensor (symmetric; any frame, r in the same)
inline Matrix3d point_mass_matrix(double inv_mass, const Matrix3d& inertia_inv, const Vector3d& r) {
  // E/m − [r]× A [r]× = E/m + Σ (r × eᵢ)ᵀ A (r × eⱼ) for a symmetric A = I⁻¹, written out:
  // the columns A (r × eᵢ), then six dot products
  const Matrix3d& a = inertia_inv;
  const double x = r.x(), y = r.y(), z = r.z();
  const Vector3d au_x = z * a.col(1) - y * a.col(2);  // A (r × e_x), r × e_x = (0, z, −y)
  const Vector3d au_y = x * a.col(2) - z * a.col(0);  // r × e_y = (−z, 0, x)
  const Vector3d au_z = y * a.col(0) - x * a.col(1);  // r × e_z = (y, −x, 0)
  const double xx = z * au_x.y() - y * au_x.z(), yy = x * au_y.z() - z * au_y.x(),
               zz = y * au_z.x() - x * au_z.y();
  const double xy = z * au_y.y() - y * au_y.z(), xz = z * au_z.y() - y * au_z.z(),
               yz = x * au_z.z() - z * au_z.x();
  const double m = inv_mass;
  Matrix3d k;
  k << m + xx, xy, xz,  //
      xy, m + yy, yz,   //
      xz, yz, m + zz;
  return k;
}

// [r]×, the matrix of r × ·
inline Matrix3d cross_matrix(const Vector3d& r) {
  Matrix3d m;
  m << 0, -r.z(), r.y(),  //
      r.z(), 0, -r.x(),   //
      -r.y(), r.x(), 0;
  return m;
}

// the same for a segment in its own frame, where D⁻¹ = diag(inertia_inv)
inline Matrix3d diagonal_point_mass_matrix(double inv_mass, const Vector3d& inertia_inv,
                                           const Vector3d& r) {
  // −[r]× D⁻¹ [r]× for D⁻¹ = diag(a, b, c), written out: symmetric, ~20 flops
  const double a = inertia_inv.x(), b = inertia_inv.y(), c = inertia_inv.z();
  const double x = r.x(), y = r.y(), z = r.z();
  const double m = inv_mass;
  Matrix3d k;
  k << m + b * z * z + c * y * y, -c * x * y, -b * x * z,  //
      -c * x * y, m + a * z * z + c * x * x, -a * y * z,   //
      -b * x * z, -a * y * z, m + a * y * y + b * x * x;
  return k;
}

// world position of a point given in a segment's frame
inline Vector3d world_point(const BodyState& body, const Vector3d& local) {
  return body.x + body.q * local;
}

// m⁻¹ y for an invertible 3×3 m, by Cramer's rule on m's columns: one division, ~40 flops
inline Vector3d solve3(const Matrix3d& m, const Vector3d& y) {
  const Vector3d c0 = m.col(0), c1 = m.col(1), c2 = m.col(2);
  const Vector3d c12 = c1.cross(c2);
  const double inv_det = 1.0 / c0.dot(c12);
  return inv_det * Vector3d(y.dot(c12), c0.dot(y.cross(c2)), c0.dot(c1.cross(y)));
}

// The least-energy impulse λ that moves a segment's point `r_frame` (its own frame, from its
// centre) onto `target` to first order, in the segment's frame, where its inertia is diagonal:
// λ = K⁻¹ (the gap in that frame). It moves the centre by λ/m and turns the segment by
// D⁻¹ (r × λ).
inline Vector3d point_impulse(const Segment& segment, const BodyState& body,
                              const Vector3d& r_frame, const Vector3d& target) {
  const Vector3d gap = body.q.conjugate() * (target - body.x) - r_frame;
  return solve3(diagonal_point_mass_matrix(segment.inv_mass, segment.inv_inertia, r_frame), gap);
}

// The weighted correction of one segment that moves its point `r_frame` onto `target`, applied
// in place: the rotation of point_impulse(), then the translation that puts the point exactly on
// target (eq. 5). The same as close_point(kWeighted, ...) but for rounding.
inline void close_segment_point(const Segment& segment, const Vector3d& r_frame,
                                const Vector3d& target, BodyState& body) {
  const Vector3d lambda = point_impulse(segment, body, r_frame, target);
  body.q = renormalized(times_exp(body.q, segment.inv_inertia.cwiseProduct(r_frame.cross(lambda))));
  body.x = target - body.q * r_frame;
}

}  // namespace puppet::procedural
