// The kNN kernel written once over the xsimd architecture, compiled per
// instruction set by knn_{sse42,avx2,avx512}.cpp. Distances are ranked as
// |b|^2 - 2 a.b (|a|^2 is the same for a whole row), computed a register tile
// at a time like a GEMM, so the N x N matrix never exists; each row keeps its
// k best in a small sorted list (inserted into a vector at a time, without
// branches) and a vector compare against the current k-th distance skips
// most of a tile without touching the list. The list keeps
// kKnnExtra more candidates than k, and the final k are chosen among them by
// exact distances (double, the reference's arithmetic). A row whose list
// cannot be proved to hold its k nearest (a near tie across the list's end
// that float rounding may have reordered) is redone exactly,
// so the neighbours are always the reference's.
//
// Each chunk of rows starts at its own panel and wraps around: when the points
// come in a spatial order (knn.hpp's visit order), the first panels hold the
// rows' near neighbours, the threshold falls at once and later tiles are
// skipped by the vector compare instead of inserted one by one. The start
// depends only on the chunk, so results do not depend on the thread count.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernels/exact_distance.hpp"
#include "kernels/knn_args.hpp"
#include "kernels/knn_candidate_list.hpp"
#include "kernels/knn_limits.hpp"
#include "kernels/knn_panel_sort.hpp"
#include "kernels/microkernel.hpp"

namespace sarmap::kernels {
namespace {

// Whether the squared distance between two boxes (lower and upper corners of
// dim each), times `shrink`, exceeds `limit`. The squared distance is a lower
// bound of every squared distance between their points, up to float
// rounding (relative, below dim * 2^-24; the caller's shrink allows for it).
// It is summed a vector of dimensions at a time and the answer is given as
// soon as the partial sum exceeds the limit: the terms are never negative, so
// a partial sum is a lower bound too. Most panels a tile tests are far away
// and are rejected after the first 16 or 32 of 64 dimensions.
template <class Arch>
inline bool box_gap_exceeds(const float* lo_a, const float* hi_a, const float* lo_b, const float* hi_b,
                            std::size_t dim, double shrink, double limit) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr std::size_t kCheckEvery = 2 * L;  // dimensions between early checks
  const B zero(0.0f);
  B sum(0.0f);
  std::size_t c = 0;
  for (; c + L <= dim; c += L) {
    const B gap = xsimd::max(xsimd::max(B::load_unaligned(lo_b + c) - B::load_unaligned(hi_a + c),
                                        B::load_unaligned(lo_a + c) - B::load_unaligned(hi_b + c)),
                             zero);
    sum = fmadd<Arch>(gap, gap, sum);
    if ((c + L) % kCheckEvery == 0 && c + L < dim && shrink * xsimd::hadd(sum) > limit) return true;
  }
  float total = xsimd::hadd(sum);
  for (; c < dim; ++c) {
    const float gap = std::max({lo_b[c] - hi_a[c], lo_a[c] - hi_b[c], 0.0f});
    total += gap * gap;
  }
  return shrink * total > limit;
}

// gaps[p] = squared distance between the box [lo_a, hi_a] and panel p's
// box, for every panel at once: panels across the vector lanes, boxes laid
// out dimension by dimension (KnnArgs::panel_boxes_by_dim). The same lower
// bound as box_gap_exceeds() (any summation order is within its allowance).
template <class Arch>
inline void box_gaps_to_all_panels(const float* lo_a, const float* hi_a, const float* boxes_by_dim,
                                   std::size_t stride, std::size_t panel_count, std::size_t dim, float* gaps) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  const B zero(0.0f);
  for (std::size_t p = 0; p < panel_count; p += L) {
    B sum(0.0f);
    for (std::size_t c = 0; c < dim; ++c) {
      const B lo_b = B::load_unaligned(boxes_by_dim + 2 * c * stride + p);
      const B hi_b = B::load_unaligned(boxes_by_dim + (2 * c + 1) * stride + p);
      const B gap = xsimd::max(xsimd::max(lo_b - B(hi_a[c]), B(lo_a[c]) - hi_b), zero);
      sum = fmadd<Arch>(gap, gap, sum);
    }
    sum.store_unaligned(gaps + p);
  }
}

// exact_squared_distance() with its eight partial sums in vector lanes: the
// same operations in the same order per lane, so bit for bit the same double
// (these files are compiled with -ffp-contract=off, so nothing is fused).
// Re-ranking the candidates by it was an eighth of the 64-d kernel in scalar.
template <class Arch>
inline double exact_squared_distance_wide(const float* a, const float* b, std::size_t dim) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    if (dim >= 8) {
      __m512d partial = _mm512_setzero_pd();
      std::size_t j = 0;
      for (; j + 8 <= dim; j += 8) {
        const __m512d diff = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_loadu_ps(a + j)), _mm512_cvtps_pd(_mm256_loadu_ps(b + j)));
        partial = _mm512_add_pd(partial, _mm512_mul_pd(diff, diff));
      }
      alignas(64) double p[8];
      _mm512_store_pd(p, partial);
      for (std::size_t l = 0; j < dim; ++j, ++l) {
        const double diff = static_cast<double>(a[j]) - static_cast<double>(b[j]);
        p[l] += diff * diff;
      }
      return ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
    }
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
    if (dim >= 8) {
      __m256d low = _mm256_setzero_pd(), high = _mm256_setzero_pd();  // partial sums 0-3 and 4-7
      std::size_t j = 0;
      for (; j + 8 <= dim; j += 8) {
        const __m256d diff_low = _mm256_sub_pd(_mm256_cvtps_pd(_mm_loadu_ps(a + j)), _mm256_cvtps_pd(_mm_loadu_ps(b + j)));
        const __m256d diff_high =
            _mm256_sub_pd(_mm256_cvtps_pd(_mm_loadu_ps(a + j + 4)), _mm256_cvtps_pd(_mm_loadu_ps(b + j + 4)));
        low = _mm256_add_pd(low, _mm256_mul_pd(diff_low, diff_low));
        high = _mm256_add_pd(high, _mm256_mul_pd(diff_high, diff_high));
      }
      alignas(32) double p[8];
      _mm256_store_pd(p, low);
      _mm256_store_pd(p + 4, high);
      for (std::size_t l = 0; j < dim; ++j, ++l) {
        const double diff = static_cast<double>(a[j]) - static_cast<double>(b[j]);
        p[l] += diff * diff;
      }
      return ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
    }
  }
#endif
  return exact_squared_distance(a, b, dim);
}

// A computed |b|^2 - 2a.b is within ranking_slack(dim) * (|b| + |a|)^2 of
// the exact one (a generous bound on float rounding over dim + 1 terms), and
// a box gap at least box_gap_shrink(dim) times its exact value.
inline double ranking_slack(std::size_t dim) { return 8.0 * static_cast<double>(dim + 2) * 0x1p-24; }
inline double box_gap_shrink(std::size_t dim) { return 1.0 - 4.0 * static_cast<double>(dim + 2) * 0x1p-24; }

// Inserts (d, id) into the ascending list best_d / best_i of n entries (at
// most k), ordered by distance and then index; returns the new n.
inline std::size_t insert_exact(double* best_d, std::uint32_t* best_i, std::size_t n, std::size_t k, double d,
                                std::uint32_t id) {
  const auto before = [&](std::size_t pos) { return best_d[pos] < d || (best_d[pos] == d && best_i[pos] < id); };
  if (n == k && before(k - 1)) return n;
  std::size_t pos = n < k ? n++ : k - 1;
  for (; pos > 0 && !before(pos - 1); --pos) {
    best_d[pos] = best_d[pos - 1];
    best_i[pos] = best_i[pos - 1];
  }
  best_d[pos] = d;
  best_i[pos] = id;
  return n;
}

// Writes to out the k nearest of row self_id among the candidates
// id_of(0 .. candidates), by exact distance, ties by index (the reference's
// answer), repeating the nearest when fewer than k. Non-finite distances are
// never neighbours, as in the fast path.
template <class Arch, class IdOf>
void write_exact_nearest(const detail::KnnArgs& q, std::uint32_t self_id, std::size_t candidates, IdOf id_of,
                         std::uint32_t* out) {
  const std::size_t k = q.k;
  double best_d[kKnnMaxK];
  std::uint32_t best_i[kKnnMaxK];
  std::size_t n = 0;
  const float* self = q.points + static_cast<std::size_t>(self_id) * q.stride;
  for (std::size_t j = 0; j < candidates; ++j) {
    const std::uint32_t id = id_of(j);
    const double d = exact_squared_distance_wide<Arch>(self, q.points + static_cast<std::size_t>(id) * q.stride, q.dim);
    if (d < std::numeric_limits<double>::infinity()) n = insert_exact(best_d, best_i, n, k, d, id);
  }
  const std::uint32_t fill = n > 0 ? best_i[0] : self_id;
  for (std::size_t j = 0; j < k; ++j) out[j] = j < n ? best_i[j] : fill;
}

// The k nearest of one row by exact distance to every point.
template <class Arch>
void exact_row(const detail::KnnArgs& q, std::uint32_t self_id, std::uint32_t* out) {
  write_exact_nearest<Arch>(q, self_id, q.count, [](std::size_t j) { return static_cast<std::uint32_t>(j); }, out);
}

// The k nearest of one row, exactly, when its candidate list could not be
// proved complete: a second pass over the panels collects every point whose
// rank allows it to be as near as the list's k-th exact distance (a true
// k nearest can be no farther), and those are ranked by exact distance. A
// tie larger than kKnnTieCandidates (thousands of copies of one point) falls
// back to ranking every point.
template <class Arch>
void exact_row_near(const detail::KnnArgs& q, const float* a_scaled_row, double row_norm, double kth_exact,
                    std::uint32_t self_id, std::uint32_t* out) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr std::size_t NR = 2 * L;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::size_t dim = q.dim, count = q.count;
  const std::size_t panel_count = (count + NR - 1) / NR;
  const double slack = ranking_slack(dim), gap_shrink = box_gap_shrink(dim);
  const double bound = kth_exact * (1.0 + 0x1p-40);
  const double row_radius = std::sqrt(row_norm);
  float self_centred[kKnnMaxDim];
  for (std::size_t c = 0; c < dim; ++c) self_centred[c] = -0.5f * a_scaled_row[c];  // exact: a power of two
  std::uint32_t near[kKnnTieCandidates];
  std::size_t near_count = 0;
  for (std::size_t p = 0; p < panel_count; ++p) {
    const double reach = static_cast<double>(q.panel_max_radius[p]) + row_radius;
    const double allowance = slack * reach * reach;
    const float* box = q.panel_boxes + p * 2 * dim;
    if (box_gap_exceeds<Arch>(self_centred, self_centred, box, box + dim, dim, gap_shrink, bound + allowance)) continue;
    B acc[1][2] = {{B::load_aligned(q.norms + p * NR), B::load_aligned(q.norms + p * NR + L)}};
    accumulate<Arch, 1>(a_scaled_row, dim, q.panels + p * NR * dim, dim, acc);
    const B ceiling(std::nextafter(static_cast<float>(bound - row_norm + allowance), kInf));
    std::uint64_t within = lane_mask<Arch>(acc[0][0] <= ceiling) | (std::uint64_t{lane_mask<Arch>(acc[0][1] <= ceiling)} << L);
    while (within != 0) {
      const std::size_t col = p * NR + static_cast<std::size_t>(__builtin_ctzll(within));
      within &= within - 1;
      if (col >= count) continue;
      if (near_count == kKnnTieCandidates) return exact_row<Arch>(q, self_id, out);
      near[near_count++] = q.original != nullptr ? q.original[col] : static_cast<std::uint32_t>(col);
    }
  }
  write_exact_nearest<Arch>(q, self_id, near_count, [&near](std::size_t j) { return near[j]; }, out);
}

// tile[r][j] = |b_j|^2 - 2 a_r.b_j for the R rows of a_scaled (already
// -2a) against one packed panel. Not inlined, on purpose: inside
// knn_rows_impl the selection code's constants stay live across the
// accumulation, and with AVX2's 16 registers the compiler then kept three of
// the twelve accumulators on the stack, which made every step of the 64-d
// loop wait on a store.
template <class Arch, int R>
__attribute__((noinline)) void ranked_tile(const float* a_scaled, std::size_t dim, const float* panel,
                                           const float* norms, float (&tile)[R][2 * Batch<Arch>::size]) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  B acc[R][2];
  const B n0 = B::load_aligned(norms), n1 = B::load_aligned(norms + L);
  for (int r = 0; r < R; ++r) {
    acc[r][0] = n0;
    acc[r][1] = n1;
  }
  accumulate<Arch, R>(a_scaled, dim, panel, dim, acc);
  // Stored with constant indices: the caller's selection loop indexes rows
  // at run time.
#pragma GCC unroll 16
  for (int r = 0; r < R; ++r) {
    acc[r][0].store_aligned(tile[r]);
    acc[r][1].store_aligned(tile[r] + L);
  }
}

// One row of a tile: its centred coordinates times -2 into a_scaled, the
// tile's box [lo, hi] widened to hold it (set to it for the first row), and
// its squared norm in double, returned. Across the vector lanes, since this
// runs once per row and dimension and in scalar code showed in the 64-d
// kernel's profile; the norm is summed in kNormLanes partial sums (any order is
// within the allowance its users add for rounding).
template <class Arch>
inline double set_up_row(const float* src, const float* centre, std::size_t dim, bool first_row, float* a_scaled,
                         float* lo, float* hi) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr std::size_t kNormLanes = 8;
  double partial[kNormLanes] = {};
  std::size_t c = 0;
  for (; c + L <= dim; c += L) {
    const B centred = B::load_unaligned(src + c) - B::load_unaligned(centre + c);
    (B(-2.0f) * centred).store_unaligned(a_scaled + c);
    const B new_lo = first_row ? centred : xsimd::min(B::load_unaligned(lo + c), centred);
    const B new_hi = first_row ? centred : xsimd::max(B::load_unaligned(hi + c), centred);
    new_lo.store_unaligned(lo + c);
    new_hi.store_unaligned(hi + c);
    alignas(64) float lanes[L];
    centred.store_aligned(lanes);
    for (std::size_t l = 0; l < L; ++l) {
      partial[l % kNormLanes] += static_cast<double>(lanes[l]) * static_cast<double>(lanes[l]);
    }
  }
  for (; c < dim; ++c) {
    const float centred = src[c] - centre[c];
    a_scaled[c] = -2.0f * centred;
    lo[c] = first_row ? centred : std::min(lo[c], centred);
    hi[c] = first_row ? centred : std::max(hi[c], centred);
    partial[c % kNormLanes] += static_cast<double>(centred) * centred;
  }
  double norm = 0.0;
  for (double p : partial) norm += p;
  return norm;
}

template <class Arch>
void knn_rows_impl(const detail::KnnArgs& q, std::size_t begin, std::size_t end) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr std::size_t NR = 2 * L;
  constexpr int MR = tile_rows<Arch>();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::size_t k = q.k, dim = q.dim;
  const std::size_t panel_count = (q.count + NR - 1) / NR;
  // Rows and panel columns are positions in visit order; original() maps a
  // position to the caller's index (identity without a visit order), which is
  // what the lists hold and q.points is indexed by. Locals, not q's fields:
  // the list stores could alias them otherwise.
  const std::uint32_t* const original_of = q.original;
  const float* const points = q.points;
  const std::size_t count = q.count, stride = q.stride;
  const auto original = [original_of](std::size_t i) {
    return original_of != nullptr ? original_of[i] : static_cast<std::uint32_t>(i);
  };
  const auto point = [points, stride](std::uint32_t id) { return points + static_cast<std::size_t>(id) * stride; };

  alignas(64) float a_scaled[MR * kKnnMaxDim];
  std::uint32_t row_id[MR];
  // The tile's rows as a box (centred like the panels) and their exact
  // squared norms, for skipping panels.
  float rows_lo[kKnnMaxDim], rows_hi[kKnnMaxDim];
  double row_norm[MR];
  // With these allowances a panel is skipped only when no rounding could
  // have let one of its points in.
  const double slack = ranking_slack(dim), gap_shrink = box_gap_shrink(dim);
  constexpr std::size_t kSlots = kKnnMaxK + kKnnExtra;
  const std::size_t keep = k + kKnnExtra < q.count ? k + kKnnExtra : q.count;
  // Per row: the sorted candidate list (knn_candidate_list.hpp), a vector of
  // sentinel in front and whole vectors of slots.
  constexpr std::size_t KL = keys_per_vector<Arch>();
  constexpr std::size_t kListLanes = (kSlots + KL - 1) / KL * KL;
  constexpr std::int64_t kNoKey = std::numeric_limits<std::int64_t>::max();
  const std::size_t chunks = (keep + KL - 1) / KL;
  alignas(64) std::int64_t list[MR][KL + kListLanes];
  std::uint32_t best_i[MR][kSlots];
  double exact[kSlots];   // exact squared distances, filled where the order needed them
  float ranked[kSlots];    // the candidates' computed ranks
  std::size_t found[MR];
  float threshold[MR];  // the last entry's rank once the list is full, +inf before

  for (std::size_t row = begin; row < end; row += MR) {
    const int rows = static_cast<int>(min_size(MR, end - row));
    with_rows<MR>(rows, [&](auto rc) {
      constexpr int R = decltype(rc)::value;
      double max_row_norm = 0.0;
      float max_row_radius = 0.0f;
      for (int r = 0; r < R; ++r) {
        row_id[r] = original(row + r);
        row_norm[r] = set_up_row<Arch>(point(row_id[r]), q.centre, dim, r == 0, a_scaled + r * dim, rows_lo, rows_hi);
        max_row_norm = std::max(max_row_norm, row_norm[r]);
        max_row_radius = static_cast<float>(std::sqrt(max_row_norm));
        found[r] = 0;
        threshold[r] = kInf;
        // Only the sentinel and the `chunks` vectors in use: clearing all
        // kListLanes slots per row showed in the 64-d kernel's profile.
        std::fill_n(list[r], KL, std::numeric_limits<std::int64_t>::min());
        std::fill_n(list[r] + KL, chunks * KL, kNoKey);
      }
      // Panels outward from the tile's own: p0, p0 + 1, p0 - 1, p0 + 2, ...
      std::ptrdiff_t up = static_cast<std::ptrdiff_t>((row + R / 2) / NR), down = up - 1;
      if (up >= static_cast<std::ptrdiff_t>(panel_count)) up = static_cast<std::ptrdiff_t>(panel_count) - 1, down = up - 1;
      bool take_up = true;
      const auto next_panel = [&]() {
        const std::size_t p = static_cast<std::size_t>(
            up < static_cast<std::ptrdiff_t>(panel_count) && (take_up || down < 0) ? up++ : down--);
        take_up = !take_up;
        return p;
      };
      // Inserts the lanes of one ranked tile that beat each row's threshold.
      // A distance equal to the threshold gets in when its index is smaller
      // than the last entry's (the keys order ties by index, whatever the
      // visiting order). +inf (padding columns) and NaN never get in.
      const auto passing = [&](const float* tmp, float threshold_of_row) {
        const B t(threshold_of_row), inf(kInf);
        const B low = B::load_aligned(tmp), high = B::load_aligned(tmp + L);
        return static_cast<std::uint64_t>(lane_mask<Arch>((low <= t) & (low < inf))) |
               (std::uint64_t{lane_mask<Arch>((high <= t) & (high < inf))} << L);
      };
      // The row's count and threshold after its list changed.
      const auto refresh = [&](int r) {
        if (found[r] < keep) {
          std::size_t n = found[r];
          while (n < keep && list[r][KL + n] != kNoKey) ++n;
          found[r] = n;
        }
        if (found[r] == keep) threshold[r] = rank_of_key(list[r][KL + keep - 1]);
      };
      const auto select_in_registers = [&](std::size_t p, const float (&tile)[R][NR], auto chunk_count) {
        constexpr auto Chunks = static_cast<std::size_t>(decltype(chunk_count)::value);
        for (int r = 0; r < R; ++r) {
          const float* tmp = tile[r];
          const std::uint64_t below = passing(tmp, threshold[r]);
          if (below == 0) continue;
          insert_candidates_in_registers<Arch, Chunks>(
              list[r] + KL, below, [&](std::size_t l) { return candidate_key(tmp[l], original(p * NR + l)); });
          refresh(r);
        }
      };
      const auto select_in_memory = [&](std::size_t p, const float (&tile)[R][NR]) {
        for (int r = 0; r < R; ++r) {
          const float* tmp = tile[r];
          // Each insertion may lower the threshold for the lanes after it,
          // so the key is checked against the current last entry.
          std::uint64_t below = passing(tmp, threshold[r]);
          bool inserted = false;
          while (below != 0) {
            const std::size_t l = static_cast<std::size_t>(__builtin_ctzll(below));
            below &= below - 1;
            const std::int64_t key = candidate_key(tmp[l], original(p * NR + l));
            if (key < list[r][KL + keep - 1]) {
              insert_candidate<Arch>(list[r] + KL, chunks, key);
              inserted = true;
            }
          }
          if (inserted) refresh(r);
        }
      };
      const auto select = [&](std::size_t p, const float (&tile)[R][NR]) {
        if constexpr (max_register_chunks<Arch>() > 0) {
          if (chunks <= max_register_chunks<Arch>()) {
            // with_rows() turns any small run-time count into a constant.
            with_rows<static_cast<int>(max_register_chunks<Arch>())>(static_cast<int>(chunks),
                                                                     [&](auto cc) { select_in_registers(p, tile, cc); });
            return;
          }
        }
        select_in_memory(p, tile);
      };
      // The first panel, whose lanes all enter the still empty lists.
      const auto take_whole_panel = [&](std::size_t p, const float (&tile)[R][NR]) {
        if constexpr (has_panel_sort<Arch>()) {
          const std::size_t lanes = min_size(NR, count - p * NR);
          for (int r = 0; r < R; ++r) {
            panel_keys_sorted<Arch>(list[r] + KL, chunks, tile[r], passing(tile[r], kInf),
                                    original_of != nullptr ? original_of + p * NR : nullptr,
                                    static_cast<std::uint32_t>(p * NR), lanes);
            refresh(r);
          }
        }
      };
      // Low-dimensional points: the tile's distance to every panel's box
      // at once, up front (knn_limits.hpp).
      alignas(64) float panel_gap[kKnnGapsUpFrontMaxPanels + 16];
      const bool gaps_up_front = q.panel_boxes_by_dim != nullptr;
      if (gaps_up_front) {
        box_gaps_to_all_panels<Arch>(rows_lo, rows_hi, q.panel_boxes_by_dim, q.panel_stride, panel_count, dim,
                                     panel_gap);
      }
      // Skip a panel when even its nearest possible point lies beyond every
      // row's k-th candidate (true squared distance = ranked value + |a|^2).
      // Until a row's list is full its threshold is +inf. The largest such
      // distance changes only when a panel was taken, so it is kept.
      double rows_limit = kInf;
      // Groups of panels (knn_limits.hpp): whether each was tested yet, and
      // whether it was too far. The limit only falls, so a group found too
      // far stays so; one that was near is left to its panels' own tests.
      // The largest squared distance a box may be from the tile's and still
      // hold a neighbour of one of its rows, for points of at most `radius`.
      const auto limit_for = [&](float radius) {
        const double reach = static_cast<double>(radius) + max_row_radius;
        return rows_limit + slack * reach * reach;
      };
      const bool grouped = q.group_boxes != nullptr;
      constexpr std::size_t kGroupWords = kKnnMaxGroupedPanels / kKnnPanelsPerGroup / 64;
      std::uint64_t group_tested[kGroupWords], group_far[kGroupWords];
      if (grouped) {
        const std::size_t words = (panel_count + kKnnPanelsPerGroup * 64 - 1) / (kKnnPanelsPerGroup * 64);
        std::fill_n(group_tested, words, std::uint64_t{0});
        std::fill_n(group_far, words, std::uint64_t{0});
      }
      for (std::size_t visit = 0; visit < panel_count; ++visit) {
        const std::size_t p = next_panel();
        if (rows_limit < kInf) {
          if (grouped) {
            const std::size_t g = p / kKnnPanelsPerGroup;
            const std::uint64_t bit = std::uint64_t{1} << (g % 64);
            if ((group_far[g / 64] & bit) != 0) continue;
            if ((group_tested[g / 64] & bit) == 0) {
              group_tested[g / 64] |= bit;
              const float* box = q.group_boxes + g * 2 * dim;
              if (box_gap_exceeds<Arch>(rows_lo, rows_hi, box, box + dim, dim, gap_shrink,
                                        limit_for(q.group_max_radius[g]))) {
                group_far[g / 64] |= bit;
                continue;
              }
            }
          }
          const double limit = limit_for(q.panel_max_radius[p]);
          if (gaps_up_front) {
            if (gap_shrink * static_cast<double>(panel_gap[p]) > limit) continue;
          } else {
            const float* box = q.panel_boxes + p * 2 * dim;
            if (box_gap_exceeds<Arch>(rows_lo, rows_hi, box, box + dim, dim, gap_shrink, limit)) continue;
          }
        }
        alignas(64) float tile[R][NR];
        ranked_tile<Arch, R>(a_scaled, dim, q.panels + p * NR * dim, q.norms + p * NR, tile);
        if (has_panel_sort<Arch>() && visit == 0) {
          take_whole_panel(p, tile);
        } else {
          select(p, tile);
        }
        rows_limit = 0.0;
        for (int r = 0; r < R; ++r) rows_limit = std::max(rows_limit, static_cast<double>(threshold[r]) + row_norm[r]);
      }
      for (int r = 0; r < R; ++r) {
        for (std::size_t c = 0; c < found[r]; ++c) {
          best_i[r][c] = index_of_key(list[r][KL + c]);
          ranked[c] = rank_of_key(list[r][KL + c]);
        }
        // Order the candidates by exact distance, ties by index, as far as
        // the k-th. A computed rank is within `allowance` of the exact
        // distance less |a|^2, so two candidates whose ranks differ by more
        // than twice that are already in exact order; only runs of
        // candidates closer than that are ranked by exact distance (most
        // runs are single candidates, and computing every candidate's exact
        // distance showed in the 64-d kernel's profile). A non-finite allowance
        // (non-finite input) makes one run of all.
        const float* self = point(row_id[r]);
        const double row_reach = static_cast<double>(q.max_radius) + std::sqrt(row_norm[r]);
        const double run_gap = 2.0 * slack * row_reach * row_reach * (1.0 + 0x1p-40);
        for (std::size_t start = 0, stop = 0; start < found[r] && start < k; start = stop) {
          stop = start + 1;
          while (stop < found[r] && !(static_cast<double>(ranked[stop]) - static_cast<double>(ranked[stop - 1]) > run_gap)) {
            ++stop;
          }
          if (stop - start == 1) {
            // Alone in its run, it is in place; only the k-th's exact
            // distance is needed (for the proof below).
            if (start == k - 1) exact[start] = exact_squared_distance_wide<Arch>(self, point(best_i[r][start]), dim);
            continue;
          }
          for (std::size_t c = start; c < stop; ++c) {
            const std::uint32_t id = best_i[r][c];
            const double d = exact_squared_distance_wide<Arch>(self, point(id), dim);
            std::size_t pos = c;
            while (pos > start && (exact[pos - 1] > d || (exact[pos - 1] == d && best_i[r][pos - 1] > id))) {
              exact[pos] = exact[pos - 1];
              best_i[r][pos] = best_i[r][pos - 1];
              --pos;
            }
            exact[pos] = d;
            best_i[r][pos] = id;
          }
        }
        std::uint32_t* out = q.idx + static_cast<std::size_t>(row_id[r]) * k;
        // The candidates are proved to hold the k nearest when every point
        // left out is farther than the k-th: a point outside the list ranked
        // at or above its last entry, so its true squared distance is at
        // least that rank + |a|^2 less the rounding allowance. Otherwise (a
        // near tie across the list's end, which rounding might have
        // reordered) the row is redone exactly (exact_row_near).
        // (The 2^-40 covers the double sums' own rounding.)
        if (found[r] == keep && keep < count) {
          const double reach = static_cast<double>(q.max_radius) + std::sqrt(row_norm[r]);
          const double excluded_floor =
              static_cast<double>(rank_of_key(list[r][KL + keep - 1])) + row_norm[r] - slack * reach * reach;
          // A k-th neighbour at distance 0 is a copy of the row's point, and
          // so are all points at distance 0; copies rank exactly alike, so
          // the list holds the lowest-indexed of them: proved too. (Padding a
          // sparse block by repetition makes this the common tie.)
          const bool proved = exact[k - 1] == 0.0 || exact[k - 1] * (1.0 + 0x1p-40) < excluded_floor;
          // A non-finite floor comes from non-finite input, which keeps the fast lists.
          if (!proved && std::isfinite(excluded_floor)) {
            exact_row_near<Arch>(q, a_scaled + r * dim, row_norm[r], exact[k - 1], row_id[r], out);
            continue;
          }
        }
        if (found[r] > k) found[r] = k;
        // Fewer than k points (or non-finite input): repeat the nearest, which
        // leaves every max over the neighbourhood unchanged.
        const std::uint32_t fill = found[r] > 0 ? best_i[r][0] : row_id[r];
        for (std::size_t j = 0; j < k; ++j) out[j] = j < found[r] ? best_i[r][j] : fill;
      }
    });
  }
}

}  // namespace
}  // namespace sarmap::kernels
