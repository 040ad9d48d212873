// Fixed-chunk loops (core/parallel.h): the same chunks and the same results on
// any number of threads.

#include "msdeform/core/parallel.h"

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace msdeform {
namespace {

TEST(ParallelTest, ChunksCoverTheRangeOnceWhateverTheThreadCount) {
  // 1,000 items in chunks of 64: 15 full chunks and one of 40.
  EXPECT_EQ(NumChunks(1000, 64), 16);
  EXPECT_EQ(NumChunks(0, 64), 0);
  for (int threads : {1, 2, 3}) {
    std::vector<int> visits(1000, 0);
    std::vector<int64_t> chunk_begin(16, -1), chunk_end(16, -1);
    ForEachChunk(1000, 64, threads, [&](int64_t begin, int64_t end, int64_t c) {
      chunk_begin[c] = begin;
      chunk_end[c] = end;
      for (int64_t i = begin; i < end; ++i) ++visits[i];
    });
    for (int i = 0; i < 1000; ++i) EXPECT_EQ(visits[i], 1) << i;
    for (int c = 0; c < 16; ++c) {
      EXPECT_EQ(chunk_begin[c], 64 * c);
      EXPECT_EQ(chunk_end[c], c == 15 ? 1000 : 64 * (c + 1));
    }
  }
}

TEST(ParallelTest, SelectedIndicesAreTheSerialFilterInOrder) {
  // Multiples of 3 or 7 below 10,000, chunks of 100: 100 chunks on 1-3 threads.
  auto keep = [](int i) { return i % 3 == 0 || i % 7 == 0; };
  std::vector<int> expected;
  for (int i = 0; i < 10000; ++i)
    if (keep(i)) expected.push_back(i);
  for (int threads : {1, 2, 3}) {
    EXPECT_EQ(SelectIndices(10000, threads, keep, 100), expected) << threads << " threads";
  }
  EXPECT_TRUE(SelectIndices(0, 2, keep, 100).empty());
}

TEST(ParallelTest, CopiedColumnsEqualTheSource) {
  // 100,000 columns: four chunks of 2^15 columns.
  const Eigen::Matrix3Xd source = Eigen::Matrix3Xd::Random(3, 100000);
  const Eigen::Matrix3Xi ids = Eigen::Matrix3Xi::Random(3, 100000);
  for (int threads : {1, 2, 3}) {
    Eigen::Matrix3Xd copy;
    Eigen::Matrix3Xi ids_copy;
    CopyColumns(source, threads, &copy);
    CopyColumns(ids, threads, &ids_copy);
    EXPECT_TRUE(copy == source);
    EXPECT_TRUE(ids_copy == ids);
  }
}

}  // namespace
}  // namespace msdeform
