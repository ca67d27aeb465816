#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace puppet::testbed {

Progress::Progress(std::string label)
    : label_(std::move(label)), terminal_(isatty(fileno(stderr))), start_(Clock::now()) {}

void Progress::operator()(size_t done, size_t total) {
  const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  const int tenth = static_cast<int>(10 * done / std::max<size_t>(total, 1));
  if (!terminal_ && tenth == last_tenth_ && done != total) return;
  last_tenth_ = tenth;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(kWidth * done / std::max<size_t>(total, 1));
  std::fprintf(stderr, "%s%s [%s%s] %zu/%zu jobs, %.0f s%s", terminal_ ? "\r" : "", label_.c_str(),
               std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(), done,
               total, seconds, terminal_ && done != total ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace puppet::testbed
