// xpbd's lane kernel (xpbd_lanes.inc) in SSE2: two puppets per step, on any x86-64.
#include <emmintrin.h>
#include <math.h>

#include "lane_kernel.h"

namespace puppet::procedural::lanes {
namespace {

typedef double V __attribute__((vector_size(16), may_alias));  // read from the slots' doubles
typedef long long M __attribute__((vector_size(16)));
constexpr int kLanes = 2;
inline V vsqrt(V a) { return _mm_sqrt_pd(a); }

#include "xpbd_lanes.inc"

}  // namespace

unsigned step_xpbd_sse2(const Plan& plan, double* slots) { return step(plan, slots); }

}  // namespace puppet::procedural::lanes
