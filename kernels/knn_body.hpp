// The kNN kernel written once over the xsimd architecture, compiled per
// instruction set by knn_{sse42,avx2,avx512}.cpp. Distances are ranked as
// |b|^2 - 2 a.b (|a|^2 is the same for a whole row), computed a register tile
// at a time like a GEMM, so the N x N matrix never exists; each row keeps its
// k best in a small sorted list (inserted into a vector at a time, without
// branches) and a vector compare against the current k-th distance skips
// most of a tile without touching the list. The list keeps
// kKnnExtra more candidates than k, and the final k are chosen among them by
// exact distances (double, the reference's arithmetic), so the neighbours do
// not depend on the instruction set's rounding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "kernels/exact_distance.hpp"
#include "kernels/knn_args.hpp"
#include "kernels/knn_limits.hpp"
#include "kernels/microkernel.hpp"

namespace sarmap::kernels {
namespace {

// Inserts x into the ascending list d of `chunks` vectors (padded with +inf;
// d[-1] is a -inf sentinel) after any entries equal to it, shifting the
// greater ones up a slot; the last falls off. Branch-free, a vector at a time,
// from the top down so each vector reads its unshifted predecessor. Equal
// distances thus keep their arrival order, which is index order: ties go to
// the smaller index. ids moves alongside: index bits kept in float lanes,
// only ever blended, never computed with.
template <class Arch>
inline void insert_sorted(float* d, float* ids, std::size_t chunks, float x, float id_bits) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  const B xv(x), iv(id_bits);
  for (std::size_t c = chunks; c-- > 0;) {
    float* dc = d + c * L;
    float* ic = ids + c * L;
    const B cur = B::load_aligned(dc), prev = B::load_unaligned(dc - 1);
    const auto shift = prev > xv;
    const auto place = (cur > xv) && !shift;
    xsimd::select(shift, prev, xsimd::select(place, xv, cur)).store_aligned(dc);
    const B icur = B::load_aligned(ic), iprev = B::load_unaligned(ic - 1);
    xsimd::select(shift, iprev, xsimd::select(place, iv, icur)).store_aligned(ic);
  }
}

inline float id_as_float(std::uint32_t id) {
  float f;
  std::memcpy(&f, &id, sizeof f);
  return f;
}

inline std::uint32_t id_of(float f) {
  std::uint32_t id;
  std::memcpy(&id, &f, sizeof id);
  return id;
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

  alignas(64) float a_scaled[MR * kKnnMaxDim];
  constexpr std::size_t kSlots = kKnnMaxK + kKnnExtra;
  const std::size_t keep = k + kKnnExtra < q.count ? k + kKnnExtra : q.count;
  // Per row: the sorted candidate list, a vector of sentinel in front and
  // whole vectors of slots.
  constexpr std::size_t kListLanes = (kSlots + L - 1) / L * L;
  const std::size_t chunks = (keep + L - 1) / L;
  alignas(64) float list_d[MR][L + kListLanes];
  alignas(64) float list_i[MR][L + kListLanes];
  std::uint32_t best_i[MR][kSlots];
  double exact[kSlots];
  std::size_t found[MR];
  float threshold[MR];

  for (std::size_t row = begin; row < end; row += MR) {
    const int rows = static_cast<int>(min_size(MR, end - row));
    with_rows<MR>(rows, [&](auto rc) {
      constexpr int R = decltype(rc)::value;
      for (int r = 0; r < R; ++r) {
        const float* src = q.points + (row + r) * q.stride;
        for (std::size_t c = 0; c < dim; ++c) a_scaled[r * dim + c] = -2.0f * (src[c] - q.centre[c]);
        found[r] = 0;
        threshold[r] = kInf;
        list_d[r][L - 1] = -kInf;
        for (std::size_t j = L; j < L + kListLanes; ++j) list_d[r][j] = kInf;
      }
      for (std::size_t p = 0; p < panel_count; ++p) {
        B acc[R][2];
        const B n0 = B::load_aligned(q.norms + p * NR), n1 = B::load_aligned(q.norms + p * NR + L);
        for (int r = 0; r < R; ++r) {
          acc[r][0] = n0;
          acc[r][1] = n1;
        }
        accumulate<Arch, R>(a_scaled, dim, q.panels + p * NR * dim, dim, acc);
        // Spill the tile with constant indices first: indexing acc with the
        // run-time row of the selection loop would keep it in memory during
        // the accumulation too.
        alignas(64) float tile[R][NR];
#pragma GCC unroll 16
        for (int r = 0; r < R; ++r) {
          acc[r][0].store_aligned(tile[r]);
          acc[r][1].store_aligned(tile[r] + L);
        }
        for (int r = 0; r < R; ++r) {
          const B t(threshold[r]);
          const float* tmp = tile[r];
          // Visit only the lanes under the threshold, in index order (which
          // keeps ties going to the smaller index); each insertion may lower
          // the threshold for the lanes after it.
          std::uint64_t below = lane_mask<Arch>(B::load_aligned(tmp) < t) |
                                (std::uint64_t{lane_mask<Arch>(B::load_aligned(tmp + L) < t)} << L);
          while (below != 0) {
            const std::size_t l = static_cast<std::size_t>(__builtin_ctzll(below));
            below &= below - 1;
            const std::size_t col = p * NR + l;
            if (tmp[l] < threshold[r] && col < q.count) {
              insert_sorted<Arch>(list_d[r] + L, list_i[r] + L, chunks, tmp[l],
                                  id_as_float(static_cast<std::uint32_t>(col)));
              if (found[r] < keep) ++found[r];
              threshold[r] = list_d[r][L + keep - 1];  // +inf until the list is full
            }
          }
        }
      }
      for (int r = 0; r < R; ++r) {
        for (std::size_t c = 0; c < found[r]; ++c) best_i[r][c] = id_of(list_i[r][L + c]);
        // Re-rank the candidates by exact distance, ties by index.
        const float* self = q.points + (row + r) * q.stride;
        std::size_t n = 0;
        for (std::size_t c = 0; c < found[r]; ++c) {
          const std::uint32_t id = best_i[r][c];
          const float* other = q.points + static_cast<std::size_t>(id) * q.stride;
          const double d = exact_squared_distance(self, other, dim);
          std::size_t pos = n++;
          while (pos > 0 && (exact[pos - 1] > d || (exact[pos - 1] == d && best_i[r][pos - 1] > id))) {
            exact[pos] = exact[pos - 1];
            best_i[r][pos] = best_i[r][pos - 1];
            --pos;
          }
          exact[pos] = d;
          best_i[r][pos] = id;
        }
        if (found[r] > k) found[r] = k;
        std::uint32_t* out = q.idx + (row + r) * k;
        // Fewer than k points (or non-finite input): repeat the nearest, which
        // leaves every max over the neighbourhood unchanged.
        const std::uint32_t fill = found[r] > 0 ? best_i[r][0] : static_cast<std::uint32_t>(row + r);
        for (std::size_t j = 0; j < k; ++j) out[j] = j < found[r] ? best_i[r][j] : fill;
      }
    });
  }
}

}  // namespace
}  // namespace sarmap::kernels
