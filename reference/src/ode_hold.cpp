// The world's hold on an ODE ragdoll's root (the ode engine, ode.cpp)
#include <ode/ode.h>

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

}  // namespace puppet::reference::detail
