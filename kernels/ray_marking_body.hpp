// mark_ray_cells() and mark_ray_cells_dense() written once over the xsimd
// architecture, compiled per instruction set by ray_marking_{avx2,avx512}.cpp.
// Each lane of a vector of floats (16 on AVX-512, 8 on AVX2) carries one
// ray's DdaState (dda_walk.hpp) and steps it to the same values as
// dda_step() (the same float operations on the same operands), so every
// lane visits exactly the cells the scalar walk visits. Three fields are
// held one step ahead, which takes work off the chain that runs from one
// step to the next (the walk waits on that chain, not on its arithmetic):
// the face plus the step, the cell before the last, and the next crossing
// already +inf where it would lead past the last cell (RayStage).
// Cells are held as floats too (integers below 2^24 are exact in a float).
// A lane whose ray reaches its end cell takes the next ray, set up ahead in
// a RayStage, at the next refill (one every kStepsPerRefill steps).
// walk_ray_lanes() does that and hands each step's cells to a marker, which
// finds the word and bit of each lane's cell in vector code and ORs them in
// scalar code one step later: a scalar load right after the vector store
// of the same step waited for the store to commit (store forwarding does
// not split a vector store), which cost more than the step itself. Two
// markers: BlockSinkMarker asks a sink for a lane's block when the lane
// enters a new one (one step in eight or so); DenseGridMarker computes the
// word in a dense grid of blocks and needs no look-up at all.
#pragma once

#include <xsimd/xsimd.hpp>

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

template <class Arch>
inline unsigned lane_bits(const xsimd::batch_bool<float, Arch>& b) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    return static_cast<unsigned>(static_cast<__mmask16>(b));
  } else
#endif
  {
    static_assert(std::is_base_of_v<xsimd::avx, Arch>, "lane_bits: no mask extraction for this instruction set");
    return static_cast<unsigned>(_mm256_movemask_ps(b));
  }
}

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
  // Where each DdaState field's three axes start among the fields.
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
      top_up_one_by_one();
  }

  // top_up()'s filling, one ray at a time with the scalar dda_setup().
  void top_up_one_by_one() {
    while (staged_ < kCapacity && taken_ < stretch_ * N) {
      const std::size_t k = taken_++;
      const std::size_t r = (k % N) * stretch_ + k / N;
      if (r >= count_) continue;
      const DdaState s = dda_setup(start_, ends_ + 3 * r);
      if (!s.moves) continue;
      for (int i = 0; i < 3; ++i) {
        fields_[kV + i][staged_] = static_cast<float>(s.v[i]);
        // The cell from which the axis's next crossing leads onto its last
        // cell (the last cell itself for an axis that never moves): where the
        // crossing after that, next, is +inf.
        fields_[kBeforeLast + i][staged_] = static_cast<float>(s.last[i] - s.step[i]);
        fields_[kStep + i][staged_] = static_cast<float>(s.step[i]);
        // The face after the one the ray leaves through (face + step, both
        // small integers, exact in floats): the value the next crossing's
        // parameter is computed from, kept so that a step adds one less.
        fields_[kNextFace + i][staged_] = s.face[i] + static_cast<float>(s.step[i]);
        fields_[kInv + i][staged_] = s.inv[i];
        fields_[kT + i][staged_] = s.t[i];
        fields_[kNext + i][staged_] =
            s.v[i] == s.last[i] - s.step[i] ? std::numeric_limits<float>::infinity() : s.next[i];
      }
      ++staged_;
    }
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
    while (staged_ < kCapacity && taken_ < stretch_ * N) {
      const std::size_t q = taken_ / N;  // the rays q, stretch + q, 2 stretch + q, ...
      taken_ += N;
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
    while (staged_ < kCapacity && taken_ < stretch_ * N) {
      const std::size_t q = taken_ / N;  // the rays q, stretch + q, 2 stretch + q, ...
      taken_ += N;
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
  const double* ends_;
  std::size_t count_, stretch_, taken_ = 0, staged_ = 0, cursor_ = 0;
  DdaState at_start_;  // at_start()
  // kCapacity rays and room for one more group of N set up at once.
  alignas(64) float fields_[kFields][kCapacity + N];
};

// Steps between two refills of the lanes whose rays arrived. Refilled at
// once, the lanes took a branch on arrival about every fifth step, taken
// at random and mispredicted; a lane now idles for up to this many steps
// after its ray arrives, a few percent of the lane steps against a
// mispredicted branch every few steps (the A/B is in docs/perf-history.md).
inline constexpr int kStepsPerRefill = 8;

// Walks the rays to ends[3 r ..] from start, N at a time, calling
// marker.record(cells, active, buffer) with each step's cells (3 vectors,
// one per axis, lanes not in active hold nothing to mark) and then
// marker.mark(other buffer) to mark the step before. Returns the cells visited.
template <class Arch, class Marker>
std::size_t walk_ray_lanes(const double start[3], const double* ends, std::size_t count, Marker& marker) {
  using D = xsimd::batch<float, Arch>;
  constexpr std::size_t N = D::size;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  static_assert(N <= 16, "lane sets are bits of an unsigned");

  // The lanes' states in registers, field by field in RayStage's order, all
  // parked to begin with. The start relative to its cell is the same for
  // every ray (dda_setup() computes it from the start alone).
  using Stage = RayStage<N>;
  D state[Stage::kFields];
#pragma GCC unroll 21
  for (int f = 0; f < Stage::kFields; ++f) state[f] = D(Stage::parked(f));
  D* const vv = state + Stage::kV;
  D* const before_lastv = state + Stage::kBeforeLast;
  D* const stepv = state + Stage::kStep;
  D* const next_facev = state + Stage::kNextFace;
  D* const invv = state + Stage::kInv;
  D* const tv = state + Stage::kT;
  D* const nextv = state + Stage::kNext;
  Stage stage(start, ends, count);
  const DdaState& at_start = stage.at_start();
  const D startv[3] = {D(at_start.start[0]), D(at_start.start[1]), D(at_start.start[2])};
  const D inf(kInf), tie(kDdaTieParameter);
  unsigned active = 0;
  std::size_t visits = 0, parity = 0;

  // Gives the lanes in `lanes` the next staged rays, and parks those left
  // without one.
  const auto refill = [&](unsigned lanes) {
    const std::size_t ready = stage.ready(static_cast<std::size_t>(std::popcount(lanes)));
    unsigned fill = lanes;  // the lowest `ready` of them
    while (static_cast<std::size_t>(std::popcount(fill)) > ready) fill &= ~(1u << (31 - std::countl_zero(fill)));
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
      // Straight into the registers: an expanding load per field puts the
      // next rays into the masked lanes, in order. With 16 lanes a lane
      // changes ray every few steps, and the trip of the whole state through
      // memory that AVX2 takes below made the walk measurably slower
      // (docs/perf-history.md).
      const auto m = static_cast<__mmask16>(fill), park = static_cast<__mmask16>(lanes & ~fill);
#pragma GCC unroll 21
      for (int f = 0; f < Stage::kFields; ++f) {
        state[f] = D(_mm512_mask_expandloadu_ps(state[f], m, stage.field(f)));
        if (park != 0) state[f] = D(_mm512_mask_mov_ps(state[f], park, _mm512_set1_ps(Stage::parked(f))));
      }
    } else
#endif
    {
      // Through memory: AVX2 has no expanding load.
      alignas(64) float lane_values[Stage::kFields][N];
#pragma GCC unroll 21
      for (int f = 0; f < Stage::kFields; ++f) state[f].store_aligned(lane_values[f]);
      std::size_t taken = 0;
      for (unsigned bits = lanes; bits != 0; bits &= bits - 1) {
        const auto lane = static_cast<std::size_t>(std::countr_zero(bits));
        const bool parks = ((fill >> lane) & 1u) == 0;
        for (int f = 0; f < Stage::kFields; ++f) lane_values[f][lane] = parks ? Stage::parked(f) : stage.field(f)[taken];
        taken += parks ? 0 : 1;
      }
#pragma GCC unroll 21
      for (int f = 0; f < Stage::kFields; ++f) state[f] = D::load_aligned(lane_values[f]);
    }
    stage.take(static_cast<std::size_t>(std::popcount(fill)));
    active = (active & ~lanes) | fill;
  };
  constexpr unsigned kAllLanes = N == 16 ? 0xffffu : (1u << N) - 1u;
  refill(kAllLanes);
  if (active == 0) return 0;

  D tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
  while (true) {
    // kStepsPerRefill steps without a branch on the data: a lane whose ray
    // arrives leaves `active` and idles until the refill below.
#pragma GCC unroll 1
    for (int k = 0; k < kStepsPerRefill; ++k) {
      marker.record(vv, active, parity);
      marker.mark(parity ^ 1);
      visits += static_cast<std::size_t>(std::popcount(active));
      parity ^= 1;

      // dda_step() on every lane. An axis that steps takes next as it is
      // (+inf once on its last cell, decided off the chain below), and the
      // minimum of the crossings is taken once per step, for the next step
      // and the arrival test alike. Idle lanes step too, harmlessly: they
      // mark nothing and are overwritten when refilled.
      for (int i = 0; i < 3; ++i) {
        const auto stepping = (tv[i] - tie) <= tmin;
        vv[i] = xsimd::select(stepping, vv[i] + stepv[i], vv[i]);
        next_facev[i] = xsimd::select(stepping, next_facev[i] + stepv[i], next_facev[i]);
        tv[i] = xsimd::select(stepping, nextv[i], tv[i]);
        nextv[i] = xsimd::select(vv[i] == before_lastv[i], inf, (next_facev[i] - startv[i]) * invv[i]);
      }
      tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
      // A lane has arrived when every axis is done (t = +inf on each), which
      // is exactly when its cell is the end cell: an axis's t becomes +inf
      // only as it steps onto its last cell, or from the start when it never moves.
      active &= ~lane_bits<Arch>(tmin == inf);
    }
    const unsigned idle = kAllLanes & ~active;
    if (idle != 0) {
      refill(idle);
      if (active == 0) break;
      tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
    }
  }
  marker.mark(parity ^ 1);  // the last step's marks (the loop left before marking them)
  return visits;
}

// Marks into block masks found through a sink (BlockMaskSink).
template <class Arch>
class BlockSinkMarker {
 public:
  using D = xsimd::batch<float, Arch>;
  static constexpr std::size_t N = D::size;

  explicit BlockSinkMarker(const BlockMaskSink& sink) : sink_(sink) {
    for (int i = 0; i < 3; ++i) block_[i] = D(std::numeric_limits<float>::quiet_NaN());
  }

  void record(const D* cell, unsigned active, std::size_t buffer) {
    // Cell coordinates are integers below 2^24 in floats, so the block
    // (floor of a division by 8) and the place in it are exact.
    D b[3], in_block[3];
    for (int i = 0; i < 3; ++i) {
      b[i] = xsimd::floor(cell[i] * D(0.125f));
      in_block[i] = cell[i] - b[i] * D(8.0f);
    }
    (in_block[0] + in_block[1] * D(8.0f) + in_block[2] * D(64.0f)).store_aligned(local_[buffer]);
    // Written as "not equal" by hand: a NaN (no block yet) must count as a
    // change, and xsimd's != is an ordered compare, false for NaN.
    moved_[buffer] = ~lane_bits<Arch>((b[0] == block_[0]) && (b[1] == block_[1]) && (b[2] == block_[2])) & active;
    marking_[buffer] = active;
    if (moved_[buffer] != 0) {
      for (int i = 0; i < 3; ++i) {
        b[i].store_aligned(new_block_[buffer][i]);
        block_[i] = b[i];  // lanes that did not move already hold b
      }
    }
  }

  void mark(std::size_t buffer) {
    for (unsigned bits = moved_[buffer]; bits != 0; bits &= bits - 1) {
      const int lane = std::countr_zero(bits);
      block_index_[lane] = sink_.block_index(sink_.context, static_cast<std::int32_t>(new_block_[buffer][0][lane]),
                                             static_cast<std::int32_t>(new_block_[buffer][1][lane]),
                                             static_cast<std::int32_t>(new_block_[buffer][2][lane]));
    }
    std::uint64_t* const masks = *sink_.masks;
    // Every lane, without branches (nearly all are marking): a lane that is
    // not ORs nothing into its last word.
    const unsigned lanes = marking_[buffer];
    if (lanes == 0) return;  // the first step: no marks and maybe no masks yet
#pragma GCC unroll 16
    for (std::size_t lane = 0; lane < N; ++lane) {
      const auto cell = static_cast<unsigned>(local_[buffer][lane]);
      const std::uint64_t bit = static_cast<std::uint64_t>((lanes >> lane) & 1u) << (cell & 63);
      masks[kMarkBlockWords * block_index_[lane] + (cell >> 6)] |= bit;
    }
  }

 private:
  const BlockMaskSink& sink_;
  D block_[3];  // the block each lane marks into (NaN: none yet)
  // Per step, double-buffered: each lane's cell index in its block, the
  // blocks of lanes that entered one, which lanes moved, which marked.
  alignas(64) float local_[2][N];
  alignas(64) float new_block_[2][3][N];
  unsigned moved_[2] = {0, 0}, marking_[2] = {0, 0};
  std::uint32_t block_index_[N] = {};
};

// Marks into a DenseMaskGrid: word = 8 x the block's place in the grid + z
// in the block, bit = x + 8 y in the block. The block and the place in it
// are found in floats (exact, as above); the word in 32-bit integers, which
// hold any word of a grid (fewer than 2^31) where a float would not.
template <class Arch>
class DenseGridMarker {
 public:
  using D = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  static constexpr std::size_t N = D::size;

  explicit DenseGridMarker(const DenseMaskGrid& grid)
      : words_(grid.words),
        first_{I(grid.first_block[0]), I(grid.first_block[1]), I(grid.first_block[2])},
        blocks_x_(grid.blocks[0]),
        blocks_y_(grid.blocks[1]) {}

  void record(const D* cell, unsigned active, std::size_t buffer) {
    D b[3], in_block[3];
    for (int i = 0; i < 3; ++i) {
      b[i] = xsimd::floor(cell[i] * D(0.125f));
      in_block[i] = cell[i] - b[i] * D(8.0f);
    }
    // Lanes not marking may be anywhere (a parked lane sits on cell 0): mark()
    // sends them to word 0 with no bit, so their word need not be in the grid
    // (the integer arithmetic wraps harmlessly for them).
    const I block = ((xsimd::to_int(b[2]) - first_[2]) * blocks_y_ + (xsimd::to_int(b[1]) - first_[1])) * blocks_x_ +
                    (xsimd::to_int(b[0]) - first_[0]);
    ((block << 3) + xsimd::to_int(in_block[2])).store_aligned(word_[buffer]);
    xsimd::to_int(in_block[0] + in_block[1] * D(8.0f)).store_aligned(bit_[buffer]);
    marking_[buffer] = active;
  }

  void mark(std::size_t buffer) {
    const unsigned lanes = marking_[buffer];
#pragma GCC unroll 16
    for (std::size_t lane = 0; lane < N; ++lane) {
      const std::uint32_t on = (lanes >> lane) & 1u;
      const std::uint64_t bit = static_cast<std::uint64_t>(on) << bit_[buffer][lane];
      words_[static_cast<std::uint32_t>(word_[buffer][lane]) & (0u - on)] |= bit;
    }
  }

 private:
  std::uint64_t* words_;
  I first_[3], blocks_x_, blocks_y_;
  // Per step, double-buffered: each lane's word and bit, which lanes mark.
  alignas(64) std::int32_t word_[2][N] = {};
  alignas(64) std::int32_t bit_[2][N] = {};
  unsigned marking_[2] = {0, 0};
};

template <class Arch>
std::size_t mark_ray_cells_impl(const double start[3], const double* ends, std::size_t count,
                                const BlockMaskSink& sink) {
  BlockSinkMarker<Arch> marker(sink);
  return walk_ray_lanes<Arch>(start, ends, count, marker);
}

template <class Arch>
std::size_t mark_ray_cells_dense_impl(const double start[3], const double* ends, std::size_t count,
                                      const DenseMaskGrid& grid) {
  DenseGridMarker<Arch> marker(grid);
  return walk_ray_lanes<Arch>(start, ends, count, marker);
}

}  // namespace
}  // namespace sarmap::kernels
