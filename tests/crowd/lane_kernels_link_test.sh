#!/usr/bin/env bash
# The crowd's lane kernels (crowd/src/lanes/xpbd_lanes_*.cpp) are compiled with -mavx2 or
# -mavx512f and called only where the processor has those instructions. An inline function that
# such a file instantiated with external linkage (a weak symbol) could be the copy the linker
# keeps for every caller, and then run on a processor without them: each kernel's object must
# define exactly one external symbol, its entry point.
#
#   lane_kernels_link_test.sh OBJECT...   (the puppet_crowd target's objects)
set -euo pipefail
checked=0
for object in "$@"; do
  case "$object" in
    *xpbd_lanes_*.o) ;;
    *) continue ;;
  esac
  isa=$(basename "$object" .cpp.o)
  isa=${isa#xpbd_lanes_}
  defined=$(nm -C --defined-only --extern-only "$object" | awk '{ $1 = ""; $2 = ""; print }' |
    sed 's/^ *//')
  expected="puppet::procedural::lanes::step_xpbd_$isa(puppet::procedural::lanes::Plan const&, double*)"
  if [ "$defined" != "$expected" ]; then
    echo "lane_kernels_link_test: $object defines more than its entry point:" >&2
    echo "$defined" >&2
    exit 1
  fi
  checked=$((checked + 1))
done
if [ "$checked" -ne 3 ]; then
  echo "lane_kernels_link_test: expected the 3 kernels' objects, found $checked" >&2
  exit 1
fi
echo "lane_kernels_link_test: 3 kernels, each defines its entry point alone"
