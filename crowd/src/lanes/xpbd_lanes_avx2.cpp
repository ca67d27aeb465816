// xpbd's lane kernel (xpbd_lanes.inc) in AVX2: four puppets per step. This file alone is compiled
// with -mavx2; the crowd calls it only when the processor has AVX2 (lane_stepper.cpp).
#include <immintrin.h>
#include <math.h>

#include "lane_kernel.h"

namespace puppet::procedural::lanes {
namespace {

typedef double V __attribute__((vector_size(32), may_alias));  // read from the slots' doubles
typedef long long M __attribute__((vector_size(32)));
constexpr int kLanes = 4;
inline V vsqrt(V a) { return _mm256_sqrt_pd(a); }

#include "xpbd_lanes.inc"

}  // namespace

unsigned step_xpbd_avx2(const Plan& plan, double* slots) { return step(plan, slots); }

}  // namespace puppet::procedural::lanes
