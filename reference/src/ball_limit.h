// The model's ball-joint limits as a btMultiBody constraint (see ball_limit.cpp).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

#include <memory>

#include "puppet/model/model.h"

namespace puppet::reference::detail {

// limits the spherical link `link` of `body` as the ball joint `joint` says (its swing ellipse and
// twist, or its box of Euler angles), the joint frame being `joint_in_link` in the link's frame;
// the joint must outlive the constraint
std::unique_ptr<btMultiBodyConstraint> make_ball_limit(btMultiBody* body, int link,
                                                       const Joint& joint,
                                                       const Quaterniond& joint_in_link);

}  // namespace puppet::reference::detail
