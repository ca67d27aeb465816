// MuJoCo's process-wide state as the mujoco engine (mujoco.cpp) needs it: its warnings quieted,
// its errors turned into a jump back to the guarded call that raised them (never an exit), and
// its compiler, which keeps globals, run under one lock.
#pragma once

#include <mujoco/mujoco.h>

#include <csetjmp>
#include <string>

#include "puppet/model/text.h"

namespace puppet::reference::detail {

// MuJoCo's errors. mju_error's default handler prints "Press Enter to exit", waits for a key on
// a terminal and calls exit(1): a whole command, or a Python interpreter, would end inside one
// step. The process-wide handler installed here jumps back instead, with MuJoCo's message, to
// the guarded() call on this thread that called into MuJoCo. MuJoCo is C, and guarded() runs
// nothing but calls into it, so no destructor lies between the jump and where it lands. (The
// compiler sets thread-local handlers of its own while it compiles: mj_loadXML reports its
// errors through its error buffer, never here.)
struct MujocoJump {
  std::jmp_buf where;
  char message[400];
};
// runs call(context) under the jump back; false with MuJoCo's message in `jump.message` when
// MuJoCo raised its error inside it
bool jump_guard(void (*call)(const void*), const void* context, MujocoJump& jump);

// runs `call` (calls into MuJoCo only); false with MuJoCo's message in `error` when MuJoCo raised
// its error inside it
template <class Call>
bool guarded(const Call& call, std::string& error) {
  MujocoJump jump{};
  const auto trampoline = [](const void* context) { (*static_cast<const Call*>(context))(); };
  if (jump_guard(trampoline, &call, jump)) return true;
  error = one_line(jump.message, 300);
  return false;
}

// MJCF text → mjModel, through MuJoCo's virtual file system (nothing touches the disk); throws
// ModelError with the compiler's message
mjModel* compile(const std::string& xml);

}  // namespace puppet::reference::detail
