#include "bullet_common.h"

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"

#include <cmath>
#include <stdexcept>

namespace puppet::reference {

std::string validate(const Settings& settings) {
  if (settings.iterations < 1 || settings.iterations > 10000)
    return "iterations must be in [1, 10000], got " + std::to_string(settings.iterations);
  if (!(settings.erp > 0.0 && settings.erp <= 1.0))
    return "erp must be in (0, 1], got " + std::to_string(settings.erp);
  return {};
}

namespace detail {

std::unique_ptr<btCollisionShape> make_shape(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return std::make_unique<btSphereShape>(shape.radius);
    case ShapeType::kCapsule:
      // btCapsuleShapeZ takes the full cylinder height
      return std::make_unique<btCapsuleShapeZ>(shape.radius, 2.0 * shape.half_length);
    case ShapeType::kBox:
      return std::make_unique<btBoxShape>(to_bt(shape.half_extents));
    case ShapeType::kCylinder:
      return std::make_unique<btCylinderShapeZ>(
          btVector3(shape.radius, shape.radius, shape.half_length));
    case ShapeType::kEllipsoid: {
      // a unit sphere scaled by the semi-axes: Bullet's sphere takes no scaling per axis, its
      // one-sphere multi-sphere shape does
      const btVector3 centre(0, 0, 0);
      const btScalar unit = 1.0;
      auto ellipsoid = std::make_unique<btMultiSphereShape>(&centre, &unit, 1);
      ellipsoid->setLocalScaling(to_bt(shape.half_extents));
      return ellipsoid;
    }
  }
  return nullptr;
}

btCollisionShape* make_segment_shape(const Segment& segment,
                                     std::vector<std::unique_ptr<btCollisionShape>>& owned) {
  if (lone_shape(segment)) {
    owned.push_back(make_shape(segment.shapes[0]));
    return owned.back().get();
  }
  auto compound = std::make_unique<btCompoundShape>(/*enableDynamicAabbTree=*/false,
                                                    static_cast<int>(segment.shapes.size()));
  for (const Shape& shape : segment.shapes) {
    owned.push_back(make_shape(shape));
    compound->addChildShape(to_bt(shape.orientation, shape.position), owned.back().get());
  }
  owned.push_back(std::move(compound));
  return owned.back().get();
}

Ground make_ground() {
  Ground ground;
  ground.shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0.0);
  btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, ground.shape.get());
  info.m_friction = 1.0;
  info.m_restitution = 0.0;
  ground.body = std::make_unique<btRigidBody>(info);
  return ground;
}

void clear_contact_caches(btCollisionDispatcher& dispatcher) {
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
    dispatcher.getManifoldByIndexInternal(i)->clearManifold();
  }
}

}  // namespace detail

std::string bullet_model_problem(Kind /*kind*/, const Model& model) {
  if (std::string problem = box_offsets_problem(model); !problem.empty()) return problem;
  return slide_armature_problem(model);
}
std::string bullet_multibody_model_problem(const Model& model) {
  return bullet_model_problem(Kind::kMultibody, model);
}
std::string bullet_rigid_model_problem(const Model& model) {
  return bullet_model_problem(Kind::kRigid, model);
}

int bullet_shared_fixed_body_constraints() {
  return btTypedConstraint::getFixedBody().getNumConstraintRefs();
}

std::unique_ptr<Solver> make_solver(Kind kind, const Model& model, const Environment& environment,
                                    const Settings& settings) {
  const std::string problem = validate(settings);
  if (!problem.empty()) throw std::invalid_argument("reference settings: " + problem);
  if (std::string p = bullet_model_problem(kind, model); !p.empty()) {
    throw ModelError("bullet: " + p);
  }
  if (kind == Kind::kMultibody) return detail::make_multibody(model, environment, settings);
  return detail::make_rigid(model, environment, settings);
}

}  // namespace puppet::reference
