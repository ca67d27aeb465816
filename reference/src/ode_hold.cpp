// The joints of an ODE ragdoll that take no motor (the ode engine, ode.cpp): the world's hold on
// its root, and a hinge, a fixed joint or a slide between two of its bodies
#include <ode/ode.h>

#include <cmath>
#include <numbers>

#include "ode_library.h"

namespace puppet::reference::detail {

// The world's hold on the root (RootJoint), built at rest: a fixed joint, a hinge, a slider or a
// ball between the root and the static world (body 0 in ODE). With the root as ODE's first body
// its angle and position are the model's own (+θ, +s); the planar root is refused
// (ode_model_problem)
dJointID make_hold(dWorldID world, dBodyID body, const RootJoint& root) {
  dJointID hold = nullptr;
  const Vector3d& a = root.axes[0];
  const Vector3d& p = root.anchor_world;
  switch (root.hold) {
    case RootHold::kFree:
    case RootHold::kPlanar:
      return nullptr;
    case RootHold::kWeld:
      hold = dJointCreateFixed(world, nullptr);
      dJointAttach(hold, body, nullptr);
      dJointSetFixed(hold);
      return hold;
    case RootHold::kBall:
      hold = dJointCreateBall(world, nullptr);
      dJointAttach(hold, body, nullptr);
      dJointSetBallAnchor(hold, p.x(), p.y(), p.z());
      return hold;
    case RootHold::kHinge:
      hold = dJointCreateHinge(world, nullptr);
      dJointAttach(hold, body, nullptr);
      dJointSetHingeAnchor(hold, p.x(), p.y(), p.z());
      dJointSetHingeAxis(hold, a.x(), a.y(), a.z());
      if (root.limited) {
        dJointSetHingeParam(hold, dParamLoStop, root.lower);
        dJointSetHingeParam(hold, dParamHiStop, root.upper);
      }
      return hold;
    case RootHold::kSlide:
      hold = dJointCreateSlider(world, nullptr);
      dJointAttach(hold, body, nullptr);
      dJointSetSliderAxis(hold, a.x(), a.y(), a.z());
      if (root.limited) {
        dJointSetSliderParam(hold, dParamLoStop, root.lower);
        dJointSetSliderParam(hold, dParamHiStop, root.upper);
      }
      return hold;
  }
  return nullptr;
}

// a hinge, a fixed joint or a slide between two bodies at their rest poses (the parent first):
// ODE takes a hinge's and a slider's zero from the bodies' poses when its axis is set, and gives
// their angle and position as the first body's less the second's, minus the model's
dJointID make_pair_joint(dWorldID world, const Joint& joint, dBodyID parent, dBodyID child,
                         const Vector3d& anchor, const Quaterniond& frame_world) {
  dJointID made = nullptr;
  switch (joint.type) {
    case JointType::kHinge: {
      made = dJointCreateHinge(world, nullptr);
      dJointAttach(made, parent, child);
      dJointSetHingeAnchor(made, anchor.x(), anchor.y(), anchor.z());
      const Vector3d axis = frame_world * joint.hinge_axis;
      dJointSetHingeAxis(made, axis.x(), axis.y(), axis.z());
      if (joint.lower > -std::numbers::pi || joint.upper < std::numbers::pi) {
        // ODE's angle is minus the model's; HiStop first so that LoStop ≤ HiStop throughout
        dJointSetHingeParam(made, dParamHiStop, -joint.lower);
        dJointSetHingeParam(made, dParamLoStop, -joint.upper);
      }
      break;
    }
    case JointType::kFixed:
      made = dJointCreateFixed(world, nullptr);
      dJointAttach(made, parent, child);
      dJointSetFixed(made);
      break;
    case JointType::kSlide: {
      // its zero is the rest pose, where the axis is set
      made = dJointCreateSlider(world, nullptr);
      dJointAttach(made, parent, child);
      const Vector3d axis = frame_world * joint.hinge_axis;
      dJointSetSliderAxis(made, axis.x(), axis.y(), axis.z());
      if (std::isfinite(joint.lower)) {
        // ODE's position is minus the model's (the first body's less the second's), as its
        // hinge's angle is; HiStop first so that LoStop ≤ HiStop throughout
        dJointSetSliderParam(made, dParamHiStop, -joint.lower);
        dJointSetSliderParam(made, dParamLoStop, -joint.upper);
      }
      break;
    }
    case JointType::kBall:
      break;
  }
  return made;
}

}  // namespace puppet::reference::detail
