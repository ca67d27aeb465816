// ODE's process-wide state as the ode engine (ode.cpp) needs it: the library initialised once,
// its handlers (its errors and internal checks thrown as OdeFailure, never an exit or an abort),
// each thread's own collision data, and the lock around its one random generator; and the world's
// hold on a ragdoll's root.
#pragma once

#include <ode/ode.h>

#include <initializer_list>
#include <mutex>
#include <stdexcept>

#include "puppet/model/model.h"

namespace puppet::reference::detail {

// ODE's internal checks (dIASSERT, dUASSERT: its debug handler) and its errors (dError) end the
// process once their handler returns (abort(), exit(1)). The handlers ensure_ode_thread installs
// throw this instead, with ODE's message as one line: ODE is C++ built with exceptions, so the
// throw unwinds through it, its locks and arenas included, to the caller's catch.
class OdeFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ODE initialised (once per process, with the handlers above) and this thread's collision data
// allocated (once per thread)
void ensure_ode_thread();

// dWorldQuickStep shuffles its rows with ODE's one process-wide random generator (dRandInt): two
// worlds stepped at once race on it, and a world's result would depend on every step any other
// world took before. Each solver keeps its own generator state and steps under this lock.
std::mutex& quick_step_lock();

// keeps ODE's objects of a world whose step ODE stopped with its error, unfreed and reachable,
// for the life of the process (freeing them trips ODE's checks again)
void keep_after_failure(std::initializer_list<const void*> objects);

// the world's hold on the root (RootJoint) as an ODE joint between `body` and the static world,
// built at the rest pose (ode_hold.cpp); null for a free root, and for a planar one, which ODE has
// no joint for (ode_model_problem refuses it)
dJointID make_hold(dWorldID world, dBodyID body, const RootJoint& root);

// a hinge, a fixed joint or a slide of the model between two bodies at their rest poses, the
// parent first (ode_hold.cpp); null for a ball, whose limits take motors
dJointID make_pair_joint(dWorldID world, const Joint& joint, dBodyID parent, dBodyID child,
                         const Vector3d& anchor, const Quaterniond& frame_world);

}  // namespace puppet::reference::detail
