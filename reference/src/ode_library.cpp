// ODE's process-wide state (ode_library.h).
#include "ode_library.h"

#include <ode/ode.h>

#include <cstdarg>
#include <cstdio>
#include <vector>

#include "puppet/model/text.h"

namespace puppet::reference::detail {
namespace {

void throw_failure(int, const char* format, va_list args) {
  char message[300];
  std::vsnprintf(message, sizeof message, format, args);
  throw OdeFailure(one_line(message, 300));
}

}  // namespace

void ensure_ode_thread() {
  static std::once_flag once;
  std::call_once(once, [] {
    dInitODE2(0);
    // ODE reports a singular LCP or a bad quaternion as a message and carries on; the testbed
    // judges the state instead (a non-finite one is diverged), so the messages are not printed
    dSetMessageHandler([](int, const char*, va_list) {});
    dSetErrorHandler(throw_failure);
    dSetDebugHandler(throw_failure);
  });
  thread_local const bool allocated = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
  (void)allocated;
}

std::mutex& quick_step_lock() {
  static std::mutex lock;
  return lock;
}

void keep_after_failure(std::initializer_list<const void*> objects) {
  static std::mutex mutex;
  static auto* kept = new std::vector<const void*>;  // never freed: what it holds must not be
  const std::lock_guard lock(mutex);
  kept->insert(kept->end(), objects.begin(), objects.end());
}

}  // namespace puppet::reference::detail

// The leak checker's view of an engine error. ODE's error and debug handlers throw (above), which
// unwinds out of a step: the world is kept (keep_after_failure), but a job record ODE's threading
// took from its pool for that step is referenced only from the frames the throw left, so the leak
// checker of a sanitizer build reports it (80 bytes per engine error, in PreallocateJobInfos).
// It is ODE's, bounded by the engine errors a process meets, and names no other allocation.
#if defined(__SANITIZE_ADDRESS__)
#define PUPPET_LEAK_CHECKED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PUPPET_LEAK_CHECKED 1
#endif
#endif
#ifdef PUPPET_LEAK_CHECKED
extern "C" const char* __lsan_default_suppressions() { return "leak:PreallocateJobInfos\n"; }
#endif
