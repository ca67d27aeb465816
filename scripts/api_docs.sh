#!/usr/bin/env bash
# The API reference of the installed libraries, from their public headers (docs/Doxyfile):
# build/doxygen/html/index.html. Fails on any Doxygen warning.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v doxygen >/dev/null || bash scripts/setup.sh
rm -rf build/doxygen && mkdir -p build
doxygen docs/Doxyfile
echo "api_docs: build/doxygen/html/index.html, no warnings"
