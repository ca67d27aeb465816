// The model's joint limits as btMultiBody constraints (see limit_rows.cpp).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

#include <memory>

#include "puppet/model/model.h"

namespace puppet::reference::detail {

// limits the link `link` of `body` as the joint `joint` says: a revolute link's range, or a
// spherical link's swing ellipse and twist or box of Euler angles, the joint frame being
// `joint_in_link` in the link's frame; the joint must outlive the constraint
std::unique_ptr<btMultiBodyConstraint> make_limit(btMultiBody* body, int link, const Joint& joint,
                                                  const Quaterniond& joint_in_link);

}  // namespace puppet::reference::detail
