// Stage 3, contacts: the ground z = 0 as a position-level constraint. Each shape's candidate
// points (capsule: the bottom of each cap; sphere and ellipsoid: the lowest point; box: its
// corners; cylinder: eight rim points), on every shape of a segment, found below
// the plane are moved onto it by the same minimum-energy point correction as a joint (rule
// `weighted`), with Coulomb friction on the tangential displacement of that material point over
// the step: it sticks while the slide is within μ·depth, else slides by the excess. No
// restitution. The seed's repulsion force in update() is the soft part of the same contact.
#include <algorithm>
#include <cmath>
#include <limits>

#include "rules/catalogue.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

constexpr int kContactPasses = 2;    // a capsule lying flat touches with both caps
constexpr double kClearance = 1e-9;  // m: above this no candidate point can be below z = 0
// m: a point this close to the plane after the position solve is in contact (its push-out
// lands it on z = 0 up to rounding)
constexpr double kTouching = 1e-9;

// how many candidate contact points a shape has
int candidate_count(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return 1;
    case ShapeType::kCapsule:
      return 2;
    case ShapeType::kBox:
      return 8;
    case ShapeType::kCylinder:
      return 8;  // four rim points on each end cap
    case ShapeType::kEllipsoid:
      return 1;
  }
  return 0;
}

// candidate contact point `c` of a shape, in its frame, where `up` is the world's up
Vector3d contact_candidate(const Shape& shape, const Vector3d& up, int c) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return -shape.radius * up;
    case ShapeType::kCapsule:
      return Vector3d(0, 0, c == 0 ? shape.half_length : -shape.half_length) - shape.radius * up;
    case ShapeType::kBox:
      return {(c & 1 ? 1 : -1) * shape.half_extents.x(), (c & 2 ? 1 : -1) * shape.half_extents.y(),
              (c & 4 ? 1 : -1) * shape.half_extents.z()};
    case ShapeType::kCylinder: {
      // on each cap the rim's lowest point and three more a quarter turn apart: lying, the
      // lowest two touch; standing, four hold the face
      const double radial = std::hypot(up.x(), up.y());
      const Eigen::Vector2d low =
          radial < 1e-12 ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(-up.x(), -up.y()) / radial;
      const Eigen::Vector2d turned = (c & 3) == 0   ? low
                                     : (c & 3) == 1 ? Eigen::Vector2d(-low.y(), low.x())
                                     : (c & 3) == 2 ? Eigen::Vector2d(-low)
                                                    : Eigen::Vector2d(low.y(), -low.x());
      return {shape.radius * turned.x(), shape.radius * turned.y(),
              c & 4 ? shape.half_length : -shape.half_length};
    }
    case ShapeType::kEllipsoid:
      return support_point(shape, -up);
  }
  return Vector3d::Zero();
}

// the same in the segment frame, where `up` is the world's up in that frame; a lone shape at the
// segment's origin is read as it is (every segment of a one-shape model: no rotation per point)
Vector3d segment_candidate(const Segment& segment, const Shape& shape, const Vector3d& up, int c) {
  if (lone_shape(segment)) return contact_candidate(shape, up, c);
  return from_shape(shape, contact_candidate(shape, shape.orientation.conjugate() * up, c));
}

// a segment's lowest reach below its origin along the world's up (segment frame)
double reach_below(const Segment& segment, const Vector3d& up) {
  if (lone_shape(segment)) return half_height(segment.shapes[0], up);
  double below = -std::numeric_limits<double>::infinity();
  for (const Shape& shape : segment.shapes) {
    double b = 0.0, a = 0.0;
    shape_reach(shape, up, &b, &a);
    below = std::max(below, b);
  }
  return below;
}

}  // namespace

double push_out_of_ground(const Model& model, const Environment& environment, int segment,
                          State& state) {
  const Segment& seg = model.segments[segment];
  BodyState& body = state.bodies[segment];
  // the world's up in the segment's frame: a candidate's height is one dot product with it, and
  // only a point found below the plane is carried to world
  Vector3d up = up_in_frame(body.q);
  // a segment clear of the ground by more than rounding has no candidate below it
  if (body.x.z() - reach_below(seg, up) > kClearance) return 0.0;
  double deepest = 0.0;
  for (int pass = 0; pass < kContactPasses; ++pass) {
    for (const Shape& shape : seg.shapes) {
      for (int c = 0; c < candidate_count(shape); ++c) {
        // every correction moves the segment: each candidate is read from the current pose
        const Vector3d local = segment_candidate(seg, shape, up, c);
        const double depth = -(body.x.z() + up.dot(local));
        if (depth <= 0.0) continue;
        deepest = std::max(deepest, depth);

        // the same material point at the start of the step, and its slide along the ground
        const Vector3d p = world_point(body, local);
        const Vector3d p_prev = state.x_prev[segment] + state.q_prev[segment] * local;
        Vector3d slide = p - p_prev;
        slide.z() = 0.0;
        Vector3d target(p.x(), p.y(), 0.0);
        const double slide_norm = slide.norm();
        const double stick = environment.friction * depth;
        target -= slide_norm <= stick ? slide : (stick / slide_norm) * slide;

        close_segment_point(seg, local, target, body);
        up = up_in_frame(body.q);
      }
    }
  }
  return deepest;
}

int resolve_contacts(const Model& model, const Environment& environment, State& state) {
  int lowest = -1;
  double deepest = 0.0;
  for (int s = 0; s < model.segment_count(); ++s) {
    const double depth = push_out_of_ground(model, environment, s, state);
    if (depth > deepest) {
      deepest = depth;
      lowest = s;
    }
  }
  return lowest;
}

ContactPolicy contact_policy(Rule rule) { return rule_row(rule).contacts; }

void contacts(const Model& model, const Settings& settings, const Environment& environment,
              const ModelTables& tables, const PinTargets& targets, State& state,
              Workspace& workspace) {
  switch (contact_policy(settings.rule)) {
    case ContactPolicy::kInAdjust:
      return;
    case ContactPolicy::kPushOut:
      resolve_contacts(model, environment, state);
      return;
    case ContactPolicy::kPushOutAndRepass: {
      const int lowest = resolve_contacts(model, environment, state);
      if (lowest >= 0) {
        one_sided_pass(model, tables.joints, settings.rule,
                       anchor_order(model, tables, workspace, lowest), PinClosure::kNone, targets,
                       state, workspace);
      }
      return;
    }
  }
}

bool needs_ground_velocity_pass(Rule rule) {
  return contact_policy(rule) == ContactPolicy::kInAdjust;
}

void ground_velocity_pass(const Model& model, const Environment& environment, State& state) {
  for (int s = 0; s < model.segment_count(); ++s) {
    const Segment& seg = model.segments[s];
    BodyState& body = state.bodies[s];
    const Vector3d up = up_in_frame(body.q);
    // a point touches when the position solve left it on the plane (to within kTouching)
    if (body.x.z() - reach_below(seg, up) > kTouching) continue;
    for (const Shape& shape : seg.shapes) {
      for (int c = 0; c < candidate_count(shape); ++c) {
        const Vector3d local = segment_candidate(seg, shape, up, c);
        if (body.x.z() + up.dot(local) > kTouching) continue;
        const Vector3d r = body.q * local;  // world, from the centre
        const Vector3d velocity = body.v + body.w.cross(r);
        const double approach = velocity.z();
        if (approach >= 0.0) continue;  // separating or resting: the position solve holds it
        // the impulse along each direction that cancels the point's velocity there, through the
        // segment's generalised inverse mass w = 1/m + (r × n)ᵀ I⁻¹ (r × n) (world)
        const auto inverse_mass_along = [&](const Vector3d& n) {
          const Vector3d arm = body.q.conjugate() * r.cross(n);
          return seg.inv_mass + arm.cwiseAbs2().dot(seg.inv_inertia);
        };
        const auto apply = [&](const Vector3d& impulse) {
          body.v += seg.inv_mass * impulse;
          body.w += body.q * seg.inv_inertia.cwiseProduct(body.q.conjugate() * r.cross(impulse));
        };
        const double normal = -approach / inverse_mass_along(Vector3d::UnitZ());
        apply(normal * Vector3d::UnitZ());
        // Coulomb: the tangential velocity taken out, by at most μ times the normal impulse
        const Vector3d after = body.v + body.w.cross(r);
        const Vector3d tangential(after.x(), after.y(), 0.0);
        const double speed = tangential.norm();
        if (speed <= 0.0) continue;
        const Vector3d direction = tangential / speed;
        const double stop = speed / inverse_mass_along(direction);
        apply(-std::min(stop, environment.friction * normal) * direction);
      }
    }
  }
}

}  // namespace puppet::procedural
