#!/usr/bin/env bash
# Set up, build and run the whole test suite. With --sanitize: the debug build with
# AddressSanitizer and UndefinedBehaviorSanitizer instead of the release build; with --clang:
# the release build with clang 14.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=release
case "${1:-}" in
  "") ;;
  --sanitize) preset=debug-asan ;;
  --clang) preset=clang ;;
  *) echo "test.sh: unknown option '$1' (expected --sanitize or --clang)" >&2; exit 2 ;;
esac
scripts/setup.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset"
