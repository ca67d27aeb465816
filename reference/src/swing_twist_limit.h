// The model's ball-joint limit as a btMultiBody constraint (see swing_twist_limit.cpp).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

#include <memory>

#include "puppet/model/model.h"

namespace puppet::reference::detail {

// limits the spherical link `link` of `body` as the ball joint `joint` says, the joint frame
// being `joint_in_link` in the link's frame; the joint must outlive the constraint
std::unique_ptr<btMultiBodyConstraint> make_swing_twist_limit(btMultiBody* body, int link,
                                                              const Joint& joint,
                                                              const Quaterniond& joint_in_link);

}  // namespace puppet::reference::detail
