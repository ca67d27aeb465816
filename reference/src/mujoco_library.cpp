#include "mujoco_library.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "puppet/model/model.h"

namespace puppet::reference::detail {
namespace {

// MuJoCo reports what it noticed (a bad qacc, a full contact list) on stdout by default; the
// solver reads the same counts from mjData instead
void quiet_warning(const char*) {}

thread_local MujocoJump* t_jump = nullptr;

[[noreturn]] void jump_back(const char* message) {
  if (t_jump == nullptr) {
    // a call this file did not guard: nothing to return to, and MuJoCo must not go on
    std::fprintf(stderr, "mujoco: %.300s (outside a guarded call; stopping)\n", message);
    std::abort();
  }
  std::snprintf(t_jump->message, sizeof t_jump->message, "%s", message);
  std::longjmp(t_jump->where, 1);
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_warning = quiet_warning;
    mju_user_error = jump_back;
  });
}

std::mutex& compiler_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

// runs call(context) under the jump back; false with MuJoCo's message in `jump.message` when
// MuJoCo raised its error inside it. Nothing but trivially copyable locals lives in the frame
// that calls setjmp, so nothing the jump skips can be clobbered (gcc's -Wclobbered at -O1).
[[gnu::noinline]] bool jump_guard(void (*call)(const void*), const void* context,
                                  MujocoJump& jump) {
  MujocoJump* const outer = t_jump;
  t_jump = &jump;
  if (setjmp(jump.where) == 0) {
    call(context);
    t_jump = outer;
    return true;
  }
  t_jump = outer;
  return false;
}

// MJCF text → mjModel, through MuJoCo's virtual file system (nothing touches the disk)
mjModel* compile(const std::string& xml) {
  install_handlers();
  const std::lock_guard<std::mutex> lock(compiler_mutex());  // the XML parser keeps globals
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  const char* name = "puppet.xml";
  if (mj_makeEmptyFileVFS(&vfs, name, static_cast<int>(xml.size())) != 0) {
    throw ModelError("mujoco: cannot stage the MJCF document");
  }
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, name)], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(name, &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  if (m == nullptr) {
    std::string what = error;
    std::replace(what.begin(), what.end(), '\n', ' ');
    throw ModelError("mujoco: the compiler rejected the model: " + what.substr(0, 300));
  }
  return m;
}

}  // namespace puppet::reference::detail
