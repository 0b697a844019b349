// The per-thread cache of large blocks (src/detail/huge_pages.cpp) that min-energy's arenas take
// their memory from.
#include "detail/huge_pages.hpp"

#include <gtest/gtest.h>

#include <thread>

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
    // Under 4 MiB: freed (malloc keeps those), so a smaller request gets a block of its size.
    give_block(take_block(kMiB));
    EXPECT_EQ(take_block(kMiB / 2).size, kMiB / 2);
    // Above the 256 MiB limit: freed too.
    give_block(take_block(300 * kMiB));
    EXPECT_EQ(take_block(5 * kMiB).size, 5 * kMiB);
  }).join();
}

TEST(BlockCache, AtMostThreeAndTheLargestStay) {
  std::thread([] {
    Block b[4] = {take_block(4 * kMiB), take_block(5 * kMiB), take_block(6 * kMiB),
                  take_block(7 * kMiB)};
    for (Block& x : b) give_block(std::move(x));
    // 4 MiB was dropped for 7 MiB: a 4 MiB request now gets the 5 MiB block.
    EXPECT_EQ(take_block(4 * kMiB).size, 5 * kMiB);
    EXPECT_EQ(take_block(4 * kMiB).size, 6 * kMiB);
    EXPECT_EQ(take_block(4 * kMiB).size, 7 * kMiB);
    EXPECT_EQ(take_block(4 * kMiB).size, 4 * kMiB);  // a new one
  }).join();
}

}  // namespace
}  // namespace fairspline::detail
