// The per-thread cache of large blocks (src/detail/huge_pages.cpp) that min-energy's arenas take
// their memory from.
#include "detail/huge_pages.hpp"

#include "fairspline/fit.hpp"

#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
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
    Block b = take_block(6 * kMiB);
    EXPECT_EQ(b.data.get(), p);
    EXPECT_EQ(b.size, 8 * kMiB);
    Block c = take_block(10 * kMiB);
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
    EXPECT_EQ(take_block(6 * kMiB).size, 6 * kMiB);
  }).join();
}

TEST(BlockCache, KeepFitMemoryFalseFreesTheKeptBlocksAndKeepsNoMore) {
  std::thread([] {
    give_block(take_block(8 * kMiB));
    keep_fit_memory(false);  // the 8 MiB block is freed now
    EXPECT_EQ(take_block(6 * kMiB).size, 6 * kMiB);
    give_block(take_block(8 * kMiB));  // and this one when given back
    EXPECT_EQ(take_block(6 * kMiB).size, 6 * kMiB);
    keep_fit_memory(true);
    give_block(take_block(8 * kMiB));
    EXPECT_EQ(take_block(6 * kMiB).size, 8 * kMiB);
  }).join();
}

TEST(BlockCache, AKeptBlockServesUpToTwiceTheRequest) {
  std::thread([] {
    give_block(take_block(16 * kMiB));
    EXPECT_EQ(take_block(6 * kMiB).size, 6 * kMiB);  // 16 MiB is more than twice 6: a new one
    EXPECT_EQ(take_block(8 * kMiB).size, 16 * kMiB);
  }).join();
}

TEST(BlockCache, AtMostSixteenAndTheLargestStay) {
  std::thread([] {
    // (Blocks under kAlignedBlockMinBytes keep the size asked for.)
    constexpr std::size_t kKiB = 1024;
    std::vector<Block> blocks;
    for (std::size_t k = 0; k < 17; ++k) blocks.push_back(take_block((64 + 8 * k) * kKiB));
    for (Block& b : blocks) give_block(std::move(b));
    // 64 KiB was dropped for 192 KiB: a 64 KiB request now gets the 72 KiB block, and so on.
    for (std::size_t k = 1; k < 5; ++k) EXPECT_EQ(take_block(64 * kKiB).size, (64 + 8 * k) * kKiB);
    EXPECT_EQ(take_block(184 * kKiB).size, 184 * kKiB);
    EXPECT_EQ(take_block(184 * kKiB).size, 192 * kKiB);
    EXPECT_EQ(take_block(192 * kKiB).size, 192 * kKiB);  // a new one
  }).join();
}

TEST(BlockCache, Over256MiBInAllTheSmallestGoFirst) {
  std::thread([] {
    for (const std::size_t mib : {40, 60, 100, 120}) give_block(take_block(mib * kMiB));
    // 320 MiB: 40 and then 60 MiB were given up.
    EXPECT_EQ(take_block(30 * kMiB).size, 30 * kMiB);  // a new one
    EXPECT_EQ(take_block(60 * kMiB).size, 100 * kMiB);
    EXPECT_EQ(take_block(100 * kMiB).size, 120 * kMiB);
  }).join();
}

TEST(BlockCache, ALargeBlockIsWholeHugePages) {
  std::thread([] {
    // From kAlignedBlockMinBytes: on a huge page boundary, rounded up to whole ones.
    const Block a = take_block(kAlignedBlockMinBytes + 1);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data.get()) % kHugePageBytes, 0u);
    EXPECT_EQ(a.size, kHugePageBytes);
    const Block b = take_block(5 * kMiB);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data.get()) % kHugePageBytes, 0u);
    EXPECT_EQ(b.size, 6 * kMiB);
    // Smaller ones: the size asked for.
    EXPECT_EQ(take_block(kAlignedBlockMinBytes - 20).size, kAlignedBlockMinBytes - 20);
  }).join();
}

TEST(Prefault, MapsInEveryPageOfTheRange) {
  const std::size_t bytes = 4 * kMiB, page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* const p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(p, MAP_FAILED);
  const auto resident = [&] {
    std::vector<unsigned char> in(bytes / page);
    EXPECT_EQ(mincore(p, bytes, in.data()), 0);
    return static_cast<std::size_t>(
        std::count_if(in.begin(), in.end(), [](unsigned char c) { return (c & 1) != 0; }));
  };
  EXPECT_EQ(resident(), 0u);
  prefault(p, bytes);
  if (resident() == 0 && madvise(p, page, MADV_POPULATE_WRITE) != 0) {
    munmap(p, bytes);
    GTEST_SKIP() << "this kernel has no MADV_POPULATE_WRITE (Linux 5.14)";
  }
  EXPECT_EQ(resident(), bytes / page);
  munmap(p, bytes);
}

TEST(Prefault, LeavesARangeWhoseFirstPageIsMappedInAlone) {
  // Memory malloc hands back to a repeated fit is mapped in already; walking it again cost
  // 8-15% of a 10^5-point local fit. Its resident first page stands for the range.
  const std::size_t bytes = 4 * kMiB, page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* const p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(p, MAP_FAILED);
  static_cast<volatile unsigned char*>(p)[0] = 1;
  prefault(p, bytes);
  std::vector<unsigned char> in(bytes / page);
  ASSERT_EQ(mincore(p, bytes, in.data()), 0);
  // (A transparent huge page may bring the first 2 MiB in with the first byte.)
  EXPECT_EQ(in.back() & 1, 0);
  munmap(p, bytes);
}

}  // namespace
}  // namespace fairspline::detail
