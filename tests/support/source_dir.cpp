#include "support/source_dir.h"

namespace puppet::test {
const char* source_dir() { return PUPPET_SOURCE_ROOT; }
}  // namespace puppet::test
