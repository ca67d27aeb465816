// xpbd's lane kernel (xpbd_lanes.inc) in AVX-512: eight puppets per step. This file alone is
// compiled with -mavx512f; the crowd calls it only when the processor has AVX-512F
// (lane_stepper.cpp).
#include <immintrin.h>
#include <math.h>

#include "lane_kernel.h"

namespace puppet::procedural::lanes {
namespace {

typedef double V __attribute__((vector_size(64), may_alias));  // read from the slots' doubles
typedef long long M __attribute__((vector_size(64)));
constexpr int kLanes = 8;
// the zero-masked form: GCC 12 warns that _mm512_sqrt_pd reads an undefined vector
inline V vsqrt(V a) { return _mm512_maskz_sqrt_pd(0xff, a); }

#include "xpbd_lanes.inc"

}  // namespace

unsigned step_xpbd_avx512(const Plan& plan, double* slots) { return step(plan, slots); }

}  // namespace puppet::procedural::lanes
