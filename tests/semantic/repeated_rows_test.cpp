// Tests engine/semantic/dgcnn/repeated_rows.hpp and the network on blocks
// with repeated rows: folding the repeats must give the logits of the whole
// repeated block, which forward_with_copies() with one copy per row computes
// row by row as before (the golden tests hold that path to PyTorch).
#include "engine/semantic/dgcnn/repeated_rows.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "engine/semantic/dgcnn/block_sampling.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"
#include "kernels/knn.hpp"
#include "tests/semantic/dgcnn_test_data.hpp"

namespace sarmap {
namespace {

using testing::kDgcnnDataDir;

std::vector<std::uint32_t> as_vector(const kernels::AlignedBuffer<std::uint32_t>& b, std::size_t n) {
  return {b.data(), b.data() + n};
}

TEST(RepeatedRows, FindsIdenticalRowsInOrderOfFirstAppearance) {
  // Rows a, b, a, c, b, a of two channels; d differs from c in sign of zero only.
  const std::vector<float> rows = {1, 2, 3, 4, 1, 2, 0.0f, 5, 3, 4, 1, 2, -0.0f, 5};
  RepeatedRows r;
  ASSERT_EQ(find_repeated_rows(rows.data(), 7, 2, r), 4u);
  EXPECT_EQ(as_vector(r.row_of, 7), (std::vector<std::uint32_t>{0, 1, 0, 2, 1, 0, 3}));
  EXPECT_EQ(as_vector(r.copies, 4), (std::vector<std::uint32_t>{3, 2, 1, 1}));
  EXPECT_EQ(std::vector<float>(r.distinct.data(), r.distinct.data() + 8),
            (std::vector<float>{1, 2, 3, 4, 0.0f, 5, -0.0f, 5}));

  EXPECT_EQ(find_repeated_rows(rows.data(), 1, 2, r), 1u);
  EXPECT_EQ(find_repeated_rows(rows.data(), 2, 2, r), 2u);  // no repeats
  EXPECT_EQ(as_vector(r.row_of, 2), (std::vector<std::uint32_t>{0, 1}));
  const std::vector<float> same(5 * 3, 0.25f);
  ASSERT_EQ(find_repeated_rows(same.data(), 5, 3, r), 1u);
  EXPECT_EQ(r.copies.data()[0], 5u);
  EXPECT_EQ(as_vector(r.row_of, 5), (std::vector<std::uint32_t>(5, 0)));
}

// Distinct points with random copy counts (some far above k), drawn in
// random order: the repeated block, its distinct rows and their copies.
struct Repeated {
  std::vector<float> block, distinct;
  std::vector<std::uint32_t> copies, row_of;
};

Repeated repeated_points(std::size_t distinct, std::size_t dim, std::mt19937& rng) {
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f);
  std::uniform_int_distribution<int> small(1, 4);
  Repeated r;
  r.distinct.resize(distinct * dim);
  for (float& v : r.distinct) v = coord(rng);
  r.copies.resize(distinct);
  for (std::size_t i = 0; i < distinct; ++i) r.copies[i] = i % 7 == 3 ? 40 : small(rng);
  for (std::size_t i = 0; i < distinct; ++i) r.row_of.insert(r.row_of.end(), r.copies[i], std::uint32_t(i));
  std::shuffle(r.row_of.begin(), r.row_of.end(), rng);
  for (const std::uint32_t d : r.row_of) r.block.insert(r.block.end(), &r.distinct[d * dim], &r.distinct[d * dim] + dim);
  return r;
}

TEST(RepeatedRows, KeptNeighboursAreTheDistinctPointsAmongTheKNearestOfTheRepeatedBlock) {
  std::mt19937 rng(7);
  const std::size_t k = 16;
  for (const std::size_t distinct : {1, 3, 15, 16, 17, 60, 300}) {
    for (const std::size_t dim : {3, 8}) {
      const Repeated r = repeated_points(distinct, dim, rng);
      const std::size_t n = r.row_of.size();
      std::vector<std::uint32_t> full(n * k), kept(distinct * k);
      kernels::knn_reference(r.block.data(), dim, n, dim, k, full.data());
      kernels::knn_reference(r.distinct.data(), dim, distinct, dim, k, kept.data());
      keep_k_nearest_copies(kept.data(), distinct, k, r.copies.data());
      for (std::size_t i = 0; i < n; ++i) {
        std::set<std::uint32_t> expected, got;
        for (std::size_t j = 0; j < k; ++j) expected.insert(r.row_of[full[i * k + j]]);
        got.insert(&kept[r.row_of[i] * k], &kept[r.row_of[i] * k] + k);
        ASSERT_EQ(got, expected) << distinct << " distinct points of " << dim << " dimensions, row " << i;
      }
    }
  }
}

TEST(RepeatedRows, OneCopyEachKeepsTheListsAsTheyAre) {
  // Four distinct points, k = 3, each list nearest first.
  std::vector<std::uint32_t> lists = {0, 3, 1, 1, 0, 2, 2, 1, 0, 3, 0, 2};
  const std::vector<std::uint32_t> before = lists, ones(4, 1);
  keep_k_nearest_copies(lists.data(), 4, 3, ones.data());
  EXPECT_EQ(lists, before);
  // Point 0's three copies fill its k = 3 places: it keeps only itself;
  // the others keep themselves and point 0 (point 2 with its two copies, point 1).
  const std::vector<std::uint32_t> copies = {3, 1, 2, 1};
  keep_k_nearest_copies(lists.data(), 4, 3, copies.data());
  EXPECT_EQ(lists, (std::vector<std::uint32_t>{0, 0, 0, 1, 0, 1, 2, 1, 2, 3, 0, 3}));
}

// The fixture network on a block of `distinct` of the reference block's
// points filled up to 512 as the classifiers fill sparse blocks (512, not
// the model's 4,096: the sanitizer jobs run every forward pass here).
TEST(DgcnnRepeatedRows, FoldedRepeatsGiveTheLogitsOfTheWholeBlock) {
  const NpyArray source = read_npy_f32(kDgcnnDataDir + "block_c6_n1024.npy");
  const std::size_t n = 512, c = 6;
  for (kernels::SimdLevel level : {kernels::SimdLevel::Sse42, kernels::SimdLevel::Avx2, kernels::SimdLevel::Avx512}) {
    if (!kernels::simd_level_supported(level)) continue;
    const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c6.safetensors", level);
    const std::size_t classes = model.classes();
    DgcnnWorkspace ws;
    for (const std::size_t distinct : {1, 9, 200, 400, 512}) {
      const std::vector<std::uint32_t> samples = sample_block(distinct, n, 5, distinct);
      std::vector<float> block;
      for (const std::uint32_t s : samples) block.insert(block.end(), &source.values[s * c], &source.values[s * c] + c);
      const std::vector<std::uint32_t> one_each(n, 1);
      std::vector<float> whole(n * classes), folded(n * classes);
      model.forward_with_copies(block.data(), n, one_each.data(), whole.data(), ws);
      model.forward(block.data(), n, folded.data(), ws);
      ASSERT_EQ(folded, whole) << distinct << " distinct points, " << kernels::to_string(level);

      // The distinct rows with their copies, given directly.
      std::vector<std::uint32_t> copies(distinct, 0);
      for (const std::uint32_t s : samples) ++copies[s];
      std::vector<float> given(distinct * classes);
      model.forward_with_copies(source.values.data(), distinct, copies.data(), given.data(), ws);
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(std::vector<float>(&given[samples[i] * classes], &given[samples[i] * classes] + classes),
                  std::vector<float>(&whole[i * classes], &whole[i * classes] + classes))
            << "row " << i << " of " << distinct << " distinct points";
      }
    }
  }
}

TEST(DgcnnRepeatedRows, RejectsARowWithoutCopiesOrTooManyInAll) {
  const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c6.safetensors");
  const std::vector<float> rows(2 * 6, 0.5f);
  std::vector<float> logits(2 * model.classes());
  DgcnnWorkspace ws;
  const std::vector<std::uint32_t> none = {3, 0}, too_many = {DgcnnModel::kMaxBlockPoints, 1};
  EXPECT_THROW(model.forward_with_copies(rows.data(), 2, none.data(), logits.data(), ws), Error);
  EXPECT_THROW(model.forward_with_copies(rows.data(), 2, too_many.data(), logits.data(), ws), Error);
}

}  // namespace
}  // namespace sarmap
