// The rays a SIMD walk takes next (ray_marking_body.hpp), set up ahead of
// the lanes in the lanes' form: a RayStage holds up to kCapacity rays'
// DdaState fields (dda_walk.hpp), set up 16 rays at a time on AVX-512 and
// 8 on AVX2 with dda_setup()'s operations in vector form, bit for bit the
// values dda_setup() gives each ray. Included by ray_marking_body.hpp only,
// in each instruction set's own translation unit (hence the unnamed
// namespace: each compiles its own copy with its own flags).
#pragma once

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernels/dda_walk.hpp"
#include "kernels/ray_marking.hpp"

namespace sarmap::kernels {
namespace {

#if defined(__AVX2__)
// Per mask of 8 lanes, the lanes whose bits are set, in order, then the
// rest: a permutation that packs the set lanes to the front.
struct alignas(32) PackLanes8 : std::array<std::int32_t, 8> {};
constexpr std::array<PackLanes8, 256> pack_lanes_8() {
  std::array<PackLanes8, 256> table{};
  for (unsigned mask = 0; mask < 256; ++mask) {
    int n = 0;
    for (int l = 0; l < 8; ++l) {
      if ((mask >> l) & 1u) table[mask][n++] = l;
    }
    for (int l = 0; l < 8; ++l) {
      if (!((mask >> l) & 1u)) table[mask][n++] = l;
    }
  }
  return table;
}
inline constexpr std::array<PackLanes8, 256> kPackLanes8 = pack_lanes_8();
#endif

// Rays set up ahead for the lanes, field by field: the 21 floats of a
// DdaState in lanes' form (cells as floats; face, last and next one step
// ahead, as top_up() says), for up to kCapacity rays, taken
// from the call's rays in the order 0, stretch, 2 stretch, ..., 1,
// stretch + 1, ... (N stretches). Consecutive rays (neighbouring pixels) run
// nearly parallel; as neighbouring lanes they would mark the same mask word
// in the same step, each OR waiting for the one before (with float lanes
// marking is a large part of the walk; this order's A/B is in
// docs/perf-history.md).
template <std::size_t N>
class RayStage {
 public:
  // Where each field's three axes start among the fields. Per axis, from
  // the ray's DdaState s: kV the cell s.v; kBeforeLast the cell from which
  // the axis's next crossing leads onto its last cell, s.last - s.step (the
  // last cell itself for an axis that never moves), where the crossing
  // after that, next, is +inf; kStep s.step; kNextFace the face after the
  // one the ray leaves through, s.face + s.step (both small integers, exact
  // in floats: the value the next crossing's parameter is computed from,
  // kept so that a step adds one less); kInv s.inv; kT s.t; kNext s.next,
  // or +inf where s.v is already the cell before the last.
  static constexpr int kV = 0, kBeforeLast = 3, kStep = 6, kNextFace = 9, kInv = 12, kT = 15, kNext = 18,
                       kFields = 21;
  static constexpr std::size_t kCapacity = 4 * N;

  // Field f of a parked lane (no ray left): on cell (0, 0, 0) with nothing
  // to step, all zero but t = +inf.
  static constexpr float parked(int f) {
    return f >= kT && f < kT + 3 ? std::numeric_limits<float>::infinity() : 0.0f;
  }

  RayStage(const double start[3], const double* ends, std::size_t count)
      : start_(start), ends_(ends), count_(count), stretch_((count + N - 1) / N), at_start_(dda_setup(start, start)) {}
  // The rays of pieces, one piece after the other (each interleaved as
  // above), the next asked for as soon as the last is staged: the lanes
  // walk on across pieces instead of draining at the end of each.
  RayStage(const double start[3], const RayPieces& pieces)
      : start_(start),
        ends_(nullptr),
        count_(0),
        stretch_(0),
        pieces_(&pieces),
        at_start_(dda_setup(start, start)) {}

  // Rays ready from field(f)[0] on; tops up first if fewer than wanted.
  std::size_t ready(std::size_t wanted) {
    if (staged_ - cursor_ < wanted) top_up();
    return staged_ - cursor_;
  }
  const float* field(int f) const { return &fields_[f][cursor_]; }
  // The start's cell and its place in it (dda_setup() from the start to
  // itself), the same for every ray.
  const DdaState& at_start() const { return at_start_; }
  void take(std::size_t n) { cursor_ += n; }

 private:
  // Moves what is left to the front and sets up rays that visit anything
  // until full or out of rays.
  void top_up() {
    for (auto& f : fields_) std::copy(f + cursor_, f + staged_, f);
    staged_ -= cursor_;
    cursor_ = 0;
    while (true) {
#if defined(__AVX512F__)
      if constexpr (N == 16) {
        top_up_16();
      } else
#endif
#if defined(__AVX2__)
      if constexpr (N == 8) {
        top_up_8();
      } else
#endif
      {
        static_assert(N != N, "RayStage: no vector set-up of N rays in this instruction set");
      }
      // Full, or this piece all staged: then the next piece, if any (here,
      // not in the set-up's loop, which the call would slow down).
      if (staged_ >= kCapacity || pieces_ == nullptr) return;
      if (!pieces_->next(pieces_->context, &ends_, &count_)) return;
      stretch_ = (count_ + N - 1) / N;
      taken_ = 0;
    }
  }

  // The next group of N rays to set up, q, stretch + q, 2 stretch + q, ...
  // (one from each stretch), while there is room for a group and rays are
  // left; false when not.
  bool next_group(std::size_t& q) {
    if (staged_ >= kCapacity || taken_ >= stretch_ * N) return false;
    q = taken_ / N;
    taken_ += N;
    return true;
  }

#if defined(__AVX512F__)
  // top_up() on AVX-512, 16 rays at a time (one from each stretch, in the
  // same order), with dda_setup()'s operations in vector form: each lane
  // holds the values the scalar set-up gives its ray, bit for bit (the same
  // roundings, an IEEE division). Set up one by one, the rays took a large
  // part of the walk (docs/perf-history.md).
  void top_up_16() {
    const __m512i lane = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
    const __m512 inf = _mm512_set1_ps(std::numeric_limits<float>::infinity());
    const __m512 one = _mm512_set1_ps(1.0f);
    const __m512 minus_below_one_gap = _mm512_set1_ps(-kDdaBelowOneGap);
    for (std::size_t q = 0; next_group(q);) {
      const __m512i ray = _mm512_add_epi32(_mm512_mullo_epi32(lane, _mm512_set1_epi32(static_cast<std::int32_t>(stretch_))),
                                           _mm512_set1_epi32(static_cast<std::int32_t>(q)));
      const __mmask16 exists = _mm512_cmplt_epu32_mask(ray, _mm512_set1_epi32(static_cast<std::int32_t>(count_)));
      const __m512i first_coordinate = _mm512_mullo_epi32(ray, _mm512_set1_epi32(3));
      __m512 field[kFields];
      __mmask16 moves = 0;
      for (int i = 0; i < 3; ++i) {
        // The end's coordinate (the start's where there is no ray: it does
        // not move), its cell, and its place relative to the start's cell.
        const __m512i index = _mm512_add_epi32(first_coordinate, _mm512_set1_epi32(i));
        const __m512d missing = _mm512_set1_pd(start_[i]);
        const __m512d end_low = _mm512_mask_i32gather_pd(missing, static_cast<__mmask8>(exists),
                                                         _mm512_castsi512_si256(index), ends_, 8);
        const __m512d end_high = _mm512_mask_i32gather_pd(missing, static_cast<__mmask8>(exists >> 8),
                                                          _mm512_extracti64x4_epi64(index, 1), ends_, 8);
        const __m512i last = _mm512_inserti64x4(
            _mm512_castsi256_si512(_mm512_cvttpd_epi32(_mm512_roundscale_pd(end_low, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC))),
            _mm512_cvttpd_epi32(_mm512_roundscale_pd(end_high, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)), 1);
        const __m512d origin = _mm512_set1_pd(static_cast<double>(at_start_.v[i]));
        const __m512 end_rounded = _mm512_insertf32x8(_mm512_castps256_ps512(_mm512_cvtpd_ps(_mm512_sub_pd(end_low, origin))),
                                                      _mm512_cvtpd_ps(_mm512_sub_pd(end_high, origin)), 1);
        const __m512i v = _mm512_set1_epi32(at_start_.v[i]);
        const __mmask16 up = _mm512_cmpgt_epi32_mask(last, v), down = _mm512_cmplt_epi32_mask(last, v);
        const __m512i step = _mm512_mask_mov_epi32(_mm512_maskz_mov_epi32(up, _mm512_set1_epi32(1)), down,
                                                   _mm512_set1_epi32(-1));
        const __m512 stepf = _mm512_cvtepi32_ps(step);
        const __m512 end_local = _mm512_mask_mov_ps(
            end_rounded, down & _mm512_cmp_ps_mask(end_rounded, minus_below_one_gap, _CMP_GT_OQ), minus_below_one_gap);
        const __m512 start = _mm512_set1_ps(at_start_.start[i]);
        const __m512 face = _mm512_maskz_mov_ps(up, one);
        const __m512 inv = _mm512_maskz_div_ps(up | down, one, _mm512_sub_ps(end_local, start));
        const __m512 t = _mm512_mask_mov_ps(inf, up | down, _mm512_mul_ps(_mm512_sub_ps(face, start), inv));
        const __m512 next = _mm512_mul_ps(_mm512_sub_ps(_mm512_add_ps(face, stepf), start), inv);
        const __m512i before_last = _mm512_sub_epi32(last, step);
        field[kV + i] = _mm512_set1_ps(static_cast<float>(at_start_.v[i]));
        field[kBeforeLast + i] = _mm512_cvtepi32_ps(before_last);
        field[kStep + i] = stepf;
        field[kNextFace + i] = _mm512_add_ps(face, stepf);
        field[kInv + i] = inv;
        field[kT + i] = t;
        field[kNext + i] = _mm512_mask_mov_ps(next, _mm512_cmpeq_epi32_mask(v, before_last), inf);
        moves |= up | down;
      }
      const __mmask16 kept = moves & exists;
      for (int f = 0; f < kFields; ++f) _mm512_storeu_ps(&fields_[f][staged_], _mm512_maskz_compress_ps(kept, field[f]));
      staged_ += static_cast<std::size_t>(std::popcount(unsigned{kept}));
    }
  }
#endif

#if defined(__AVX2__)
  // top_up() on AVX2, 8 rays at a time: top_up_16()'s operations in 256-bit
  // form (two gathers of four doubles per axis), the rays that move packed
  // to the front through a permutation per lane mask (AVX2 has no compress).
  void top_up_8() {
    const __m256i lane = _mm256_set_epi32(7, 6, 5, 4, 3, 2, 1, 0);
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256 minus_below_one_gap = _mm256_set1_ps(-kDdaBelowOneGap);
    for (std::size_t q = 0; next_group(q);) {
      const __m256i ray = _mm256_add_epi32(_mm256_mullo_epi32(lane, _mm256_set1_epi32(static_cast<std::int32_t>(stretch_))),
                                           _mm256_set1_epi32(static_cast<std::int32_t>(q)));
      // Ray indices and counts are below 2^31: a signed compare will do.
      const __m256i exists = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<std::int32_t>(count_)), ray);
      const __m256d exists_low = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(exists)));
      const __m256d exists_high = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_extracti128_si256(exists, 1)));
      const __m256i first_coordinate = _mm256_mullo_epi32(ray, _mm256_set1_epi32(3));
      __m256 field[kFields];
      __m256i moves = _mm256_setzero_si256();
      for (int i = 0; i < 3; ++i) {
        // The end's coordinate (the start's where there is no ray: it does
        // not move), its cell, and its place relative to the start's cell.
        const __m256i index = _mm256_add_epi32(first_coordinate, _mm256_set1_epi32(i));
        const __m256d missing = _mm256_set1_pd(start_[i]);
        const __m256d end_low = _mm256_mask_i32gather_pd(missing, ends_, _mm256_castsi256_si128(index), exists_low, 8);
        const __m256d end_high =
            _mm256_mask_i32gather_pd(missing, ends_, _mm256_extracti128_si256(index, 1), exists_high, 8);
        const __m256i last = _mm256_set_m128i(
            _mm256_cvttpd_epi32(_mm256_round_pd(end_high, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)),
            _mm256_cvttpd_epi32(_mm256_round_pd(end_low, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)));
        const __m256d origin = _mm256_set1_pd(static_cast<double>(at_start_.v[i]));
        const __m256 end_rounded = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_sub_pd(end_high, origin)),
                                                   _mm256_cvtpd_ps(_mm256_sub_pd(end_low, origin)));
        const __m256i v = _mm256_set1_epi32(at_start_.v[i]);
        const __m256i up = _mm256_cmpgt_epi32(last, v), down = _mm256_cmpgt_epi32(v, last);  // all ones where true
        const __m256i step = _mm256_sub_epi32(down, up);  // 0 - (-1) = 1 up, -1 - 0 = -1 down
        const __m256 stepf = _mm256_cvtepi32_ps(step);
        const __m256 down_ps = _mm256_castsi256_ps(down), moving = _mm256_castsi256_ps(_mm256_or_si256(up, down));
        const __m256 end_local = _mm256_blendv_ps(
            end_rounded, minus_below_one_gap,
            _mm256_and_ps(down_ps, _mm256_cmp_ps(end_rounded, minus_below_one_gap, _CMP_GT_OQ)));
        const __m256 start = _mm256_set1_ps(at_start_.start[i]);
        const __m256 face = _mm256_and_ps(_mm256_castsi256_ps(up), one);
        // Lanes that do not move divide too, and their quotient is dropped for 0.
        const __m256 inv = _mm256_and_ps(moving, _mm256_div_ps(one, _mm256_sub_ps(end_local, start)));
        const __m256 t = _mm256_blendv_ps(inf, _mm256_mul_ps(_mm256_sub_ps(face, start), inv), moving);
        const __m256 next = _mm256_mul_ps(_mm256_sub_ps(_mm256_add_ps(face, stepf), start), inv);
        const __m256i before_last = _mm256_sub_epi32(last, step);
        field[kV + i] = _mm256_set1_ps(static_cast<float>(at_start_.v[i]));
        field[kBeforeLast + i] = _mm256_cvtepi32_ps(before_last);
        field[kStep + i] = stepf;
        field[kNextFace + i] = _mm256_add_ps(face, stepf);
        field[kInv + i] = inv;
        field[kT + i] = t;
        field[kNext + i] = _mm256_blendv_ps(next, inf, _mm256_castsi256_ps(_mm256_cmpeq_epi32(v, before_last)));
        moves = _mm256_or_si256(moves, _mm256_castps_si256(moving));
      }
      const auto kept = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_and_si256(moves, exists))));
      const __m256i packed = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPackLanes8[kept].data()));
      for (int f = 0; f < kFields; ++f) _mm256_storeu_ps(&fields_[f][staged_], _mm256_permutevar8x32_ps(field[f], packed));
      staged_ += static_cast<std::size_t>(std::popcount(kept));
    }
  }
#endif

  const double* start_;
  const double* ends_;  // the rays (of the piece) being staged
  std::size_t count_, stretch_, taken_ = 0, staged_ = 0, cursor_ = 0;
  const RayPieces* pieces_ = nullptr;  // where more rays come from, if anywhere
  DdaState at_start_;  // at_start()
  // kCapacity rays and room for one more group of N set up at once.
  alignas(64) float fields_[kFields][kCapacity + N];
};

}  // namespace
}  // namespace sarmap::kernels
