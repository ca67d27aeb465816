// The rows of the engine catalogue (engines.h), one function per engine file; catalogue.cpp
// lists them.
#pragma once

#include "puppet/compare/engines.h"

namespace puppet::compare {

Engine procedural_engine();
Engine bullet_multibody_engine();
Engine bullet_rigid_engine();
Engine mujoco_engine();

}  // namespace puppet::compare
