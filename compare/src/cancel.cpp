#include "puppet/compare/cancel.h"

namespace puppet::compare {
namespace {

std::atomic<int> g_signal{0};

}  // namespace

// both stores are lock-free atomics: safe in a signal handler
void request_cancel(int signal) {
  g_signal.store(signal);
  cancel_flag().store(true);
}

int cancel_signal() { return g_signal.load(); }

}  // namespace puppet::compare
