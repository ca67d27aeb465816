#!/usr/bin/env bash
# Set up, build and run the whole test suite. With --sanitize: the debug build with
# AddressSanitizer and UndefinedBehaviorSanitizer instead of the release build.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=release
if [ "${1:-}" = "--sanitize" ]; then preset=debug-asan; fi
scripts/setup.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset"
