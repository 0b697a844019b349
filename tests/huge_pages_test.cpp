// The per-thread cache of large blocks (src/detail/huge_pages.cpp) that min-energy's arenas take
// their memory from.
#include "detail/huge_pages.hpp"

#include "fairspline/fit.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace fairspline::detail {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

TEST(BlockCache, ALargeBlockGivenBackIsTakenAgain) {
  std::thread([] {  // (a thread of its own: an empty cache)
    Block a = take_block(8 * kMiB);
    ASSERT_NE(a.data, nullptr);
    EXPECT_EQ(a.size, 8 * kMiB);
    std::byte* const p = a.data.get();
    give_block(std::move(a));
    // Any request it covers gets it, with its full size; a larger one gets a new block.
    Block b = take_block(5 * kMiB);
    EXPECT_EQ(b.data.get(), p);
    EXPECT_EQ(b.size, 8 * kMiB);
    Block c = take_block(9 * kMiB);
    EXPECT_NE(c.data.get(), p);
    // Given back, the smallest that covers a request is taken.
    give_block(std::move(c));
    give_block(std::move(b));
    EXPECT_EQ(take_block(6 * kMiB).data.get(), p);
  })
      .join();
}

TEST(BlockCache, SmallAndHugeBlocksAreNotKept) {
  std::thread([] {
    // Under kKeptBlockMinBytes: freed, so a smaller request gets a block of its size.
    give_block(take_block(kKeptBlockMinBytes - 1));
    EXPECT_EQ(take_block(kKeptBlockMinBytes / 2).size, kKeptBlockMinBytes / 2);
    // From it on, kept: a fit at 10^3 points takes its temporaries from here.
    give_block(take_block(kKeptBlockMinBytes + 64));
    EXPECT_EQ(take_block(kKeptBlockMinBytes).size, kKeptBlockMinBytes + 64);
    // Above the 256 MiB limit: freed too.
    give_block(take_block(300 * kMiB));
    EXPECT_EQ(take_block(5 * kMiB).size, 5 * kMiB);
  }).join();
}

TEST(BlockCache, KeepFitMemoryFalseFreesTheKeptBlocksAndKeepsNoMore) {
  std::thread([] {
    give_block(take_block(8 * kMiB));
    keep_fit_memory(false);  // the 8 MiB block is freed now
    EXPECT_EQ(take_block(5 * kMiB).size, 5 * kMiB);
    give_block(take_block(8 * kMiB));  // and this one when given back
    EXPECT_EQ(take_block(5 * kMiB).size, 5 * kMiB);
    keep_fit_memory(true);
    give_block(take_block(8 * kMiB));
    EXPECT_EQ(take_block(5 * kMiB).size, 8 * kMiB);
  }).join();
}

TEST(BlockCache, AKeptBlockServesUpToTwiceTheRequest) {
  std::thread([] {
    give_block(take_block(16 * kMiB));
    EXPECT_EQ(take_block(7 * kMiB).size, 7 * kMiB);  // 16 MiB is more than twice 7: a new one
    EXPECT_EQ(take_block(8 * kMiB).size, 16 * kMiB);
  }).join();
}

TEST(BlockCache, AtMostSixteenAndTheLargestStay) {
  std::thread([] {
    std::vector<Block> blocks;
    for (std::size_t k = 0; k < 17; ++k) blocks.push_back(take_block((4 + k) * kMiB));
    for (Block& b : blocks) give_block(std::move(b));
    // 4 MiB was dropped for 20 MiB: a 4 MiB request now gets the 5 MiB block, and so on.
    for (std::size_t k = 1; k < 5; ++k) EXPECT_EQ(take_block(4 * kMiB).size, (4 + k) * kMiB);
    EXPECT_EQ(take_block(19 * kMiB).size, 19 * kMiB);
    EXPECT_EQ(take_block(19 * kMiB).size, 20 * kMiB);
    EXPECT_EQ(take_block(20 * kMiB).size, 20 * kMiB);  // a new one
    // Over 256 MiB in all, the smallest go first.
    give_block(take_block(250 * kMiB));
    EXPECT_EQ(take_block(9 * kMiB).size, 9 * kMiB);  // 9 … 18 MiB were given up for it
    EXPECT_EQ(take_block(200 * kMiB).size, 250 * kMiB);
  }).join();
}

}  // namespace
}  // namespace fairspline::detail
