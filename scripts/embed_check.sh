#!/usr/bin/env bash
# Installs the libraries from a build into a fresh prefix and, against the installed package
# alone (find_package(puppet CONFIG)), from clean build folders that set no C++ standard:
#   - builds examples/embed and runs it: on `pinocchio` by name, which the installed package must
#     read from its own share/puppet/models, the example grabbing the end of the right forearm
#     (Pinocchio's arms end there); and on chain:8;
#   - compiles every installed header on its own, one translation unit each, so that a header
#     that uses what it does not include fails here;
# and runs examples/python/tour.py on the installed Python package, from outside the source tree
# with the package's folder alone on PYTHONPATH (where the build has the package).
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
said=$("$work/build/embed")
echo "$said"
case "$said" in
  "pinocchio ($work/prefix/share/puppet/models/pinocchio.json): the end of r_forearm at "*", rule xpbd") ;;
  *) echo "embed_check: the example did not load the installed Pinocchio by name and grab its" \
       "right forearm's end with rule xpbd" >&2; exit 1 ;;
esac
"$work/build/embed" chain:8

# one translation unit per installed header, nothing before its #include
mkdir -p "$work/headers"
headers=0
sources=""
while IFS= read -r header; do
  relative=${header#"$work/prefix/include/"}
  unit="$work/headers/$(echo "$relative" | tr '/.' '__').cpp"
  printf '#include "%s"\n' "$relative" >"$unit"
  sources="$sources $unit"
  headers=$((headers + 1))
done < <(find "$work/prefix/include/puppet" -name '*.h' | sort)
cat >"$work/headers/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.25)
project(puppet_headers LANGUAGES CXX)
find_package(puppet 0.1 CONFIG REQUIRED)
add_library(headers OBJECT $sources)
target_link_libraries(headers PRIVATE puppet::crowd)
CMAKE
cmake -S "$work/headers" -B "$work/headers/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_CXX_FLAGS="-Wall -Wextra -Werror" >/dev/null
cmake --build "$work/headers/build" >/dev/null
python=""
site=$(find "$work/prefix" -path '*/dist-packages/puppet' -type d -printf '%h\n' | head -1)
if [ -n "$site" ]; then
  (cd "$work" && PYTHONPATH="$site" /usr/bin/python3 "$OLDPWD/examples/python/tour.py" "$work" \
    >"$work/tour.log" 2>&1) || {
    cat "$work/tour.log" >&2
    exit 1
  }
  grep -q "puppet/models/pinocchio.json" <(cd "$work" && PYTHONPATH="$site" /usr/bin/python3 -c \
    'import puppet; puppet._puppet._testbed(["list"])') ||
    { echo "embed_check: the installed package reads Pinocchio from elsewhere" >&2; exit 1; }
  python="; the installed Python package runs examples/python/tour.py from ${site#"$work/prefix/"}"
fi
echo "embed_check: examples/embed builds against the installed package (no standard set) and" \
  "runs; each of the $headers installed headers compiles on its own$python"
