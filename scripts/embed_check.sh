#!/usr/bin/env bash
# Installs the libraries from a build into a fresh prefix and builds examples/embed against the
# installed package alone (find_package(puppet CONFIG)), from a clean build folder; then runs it.
#   scripts/embed_check.sh [BUILD_DIR]     (default build/release, built already)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S examples/embed -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-Wall -Wextra -Werror" >/dev/null
cmake --build "$work/build" >/dev/null
"$work/build/embed" models/pinocchio.json
"$work/build/embed" chain:8
echo "embed_check: examples/embed builds against the installed package and runs"
