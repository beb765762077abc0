// update_lane_field(): update_receptive_field() without update_D for every output's copy of one
// field at once, one vector lane per output (lane_fields.hpp). The kernel
// (lane_field_update_kernel.inc) is compiled three times: AVX-512 (one group of 8 lanes per
// block), AVX2 (two groups of 4) and SSE2 (four groups of 2); groups whose lanes are all padding
// are skipped. Each lane runs update_statistics()' and finish_field_update()'s operations in the
// same order, without FMA, so every copy gives the same bits as update_receptive_field().
#include "engine/lwpr/lane_fields.hpp"

#include <emmintrin.h>
#include <immintrin.h>

#include <algorithm>
#include <cstring>

namespace armfarm::lwpr {
namespace {

namespace sse2 {
constexpr int kW = 2;
typedef double V __attribute__((vector_size(kW * sizeof(double))));
__attribute__((always_inline)) inline void vsqrt(V& root, const V& a) {
  __m128d t;
  std::memcpy(&t, &a, sizeof t);
  t = _mm_sqrt_pd(t);
  std::memcpy(&root, &t, sizeof t);
}
#include "engine/lwpr/lane_field_update_kernel.inc"

void update(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y, double w,
            LaneField& field, LaneScratch& scratch) {
  update_field<0>(params, trust_n_data, x, y, w, field, scratch);
}
}  // namespace sse2

// Each copy's functions get its instruction set from a region pragma (GCC's target pragma; clang,
// which the fuzz build uses, takes an attribute pragma instead).
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
namespace avx2 {
constexpr int kW = 4;
typedef double V __attribute__((vector_size(kW * sizeof(double))));
__attribute__((always_inline)) inline void vsqrt(V& root, const V& a) {
  __m256d t;
  std::memcpy(&t, &a, sizeof t);
  t = _mm256_sqrt_pd(t);
  std::memcpy(&root, &t, sizeof t);
}
#include "engine/lwpr/lane_field_update_kernel.inc"

__attribute__((noinline)) void update_n(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x,
                                        const double* y, double w, LaneField& field, LaneScratch& scratch) {
  update_field<0>(params, trust_n_data, x, y, w, field, scratch);
}
__attribute__((noinline)) void update_21(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x,
                                         const double* y, double w, LaneField& field, LaneScratch& scratch) {
  update_field<21>(params, trust_n_data, x, y, w, field, scratch);
}
}  // namespace avx2
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

// AVX-512F has FMA and GCC would contract a·b + c into it: fp-contract=off keeps the roundings of
// SSE2 and AVX2 (as receptive_field.cpp's AVX-512 copies).
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512dq"))), apply_to = function)
#pragma clang fp contract(off)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq")
#pragma GCC optimize("fp-contract=off")
#endif
namespace avx512 {
constexpr int kW = 8;
typedef double V __attribute__((vector_size(kW * sizeof(double))));
__attribute__((always_inline)) inline void vsqrt(V& root, const V& a) {
  __m512d t;
  std::memcpy(&t, &a, sizeof t);
  // (not _mm512_sqrt_pd: GCC 12's header gives it a -Wmaybe-uninitialized)
  t = _mm512_mask_sqrt_pd(t, static_cast<__mmask8>(0xFF), t);
  std::memcpy(&root, &t, sizeof t);
}
#include "engine/lwpr/lane_field_update_kernel.inc"

__attribute__((noinline)) void update_n(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x,
                                        const double* y, double w, LaneField& field, LaneScratch& scratch) {
  update_field<0>(params, trust_n_data, x, y, w, field, scratch);
}
__attribute__((noinline)) void update_21(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x,
                                         const double* y, double w, LaneField& field, LaneScratch& scratch) {
  update_field<21>(params, trust_n_data, x, y, w, field, scratch);
}
}  // namespace avx512
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

}  // namespace

void update_lane_field(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y,
                       double w, LaneField& field, LaneScratch& scratch) {
  const bool fixed = field.input_dim() == 21;
  if (scratch.use_avx512 && scratch.use_avx2) {
    if (fixed) return avx512::update_21(params, trust_n_data, x, y, w, field, scratch);
    return avx512::update_n(params, trust_n_data, x, y, w, field, scratch);
  }
  if (scratch.use_avx2) {
    if (fixed) return avx2::update_21(params, trust_n_data, x, y, w, field, scratch);
    return avx2::update_n(params, trust_n_data, x, y, w, field, scratch);
  }
  sse2::update(params, trust_n_data, x, y, w, field, scratch);
}

// The two fields one after the other: the lane layout already overlaps the outputs' chains (one
// vector op per projection step for all of them). Alternating the two fields' runs projection by
// projection (as update_statistics_pair()) was measured and did not pay (engine/lwpr/README.md,
// Speed: lane fields).
void update_lane_field_pair(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y,
                            double w_a, LaneField& field_a, double w_b, LaneField& field_b, LaneScratch& scratch_a,
                            LaneScratch& scratch_b) {
  update_lane_field(params, trust_n_data, x, y, w_a, field_a, scratch_a);
  update_lane_field(params, trust_n_data, x, y, w_b, field_b, scratch_b);
}

}  // namespace armfarm::lwpr
