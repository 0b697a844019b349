#include "detail/huge_pages.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>

#include "fairspline/fit.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fairspline::detail {

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = kHugePageBytes;
  if (p == nullptr || bytes < kHuge) return;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = (a + kHuge - 1) & ~(kHuge - 1), hi = (a + bytes) & ~(kHuge - 1);
  // (A failure, e.g. EINVAL where THP is compiled out, leaves ordinary pages: nothing to do.)
  if (hi > lo) static_cast<void>(madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE));
#else
  static_cast<void>(p);
  static_cast<void>(bytes);
#endif
}

void FreeBlock::operator()(std::byte* p) const noexcept {
  std::free(p);
}

void prefault(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr std::uintptr_t kPage = 4096;
  if (p == nullptr || bytes < kAlignedBlockMinBytes) return;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = (a + kPage - 1) & ~(kPage - 1), hi = (a + bytes) & ~(kPage - 1);
  if (hi <= lo) return;
  // Memory malloc reuses (a repeated fit's freed arrays, below its mmap threshold) is mapped in
  // already, and walking its pages again cost ~8% of a 10^5-point local fit: a first page that
  // is resident stands for the range (a fresh mapping has none).
  unsigned char first = 0;
  if (mincore(reinterpret_cast<void*>(lo), kPage, &first) == 0 && (first & 1) != 0) return;
  // (EINVAL before Linux 5.14: the pages fault in when touched, as without the call.)
  static_cast<void>(madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_POPULATE_WRITE));
#else
  static_cast<void>(p);
  static_cast<void>(bytes);
#endif
}

namespace {

constexpr std::size_t kKeptMaxBytes = std::size_t{256} << 20;

thread_local std::array<Block, 16> t_kept;
thread_local bool t_keep = true;

}  // namespace

Block take_block(std::size_t bytes) {
  Block* best = nullptr;
  // (A small request is malloc's; a kept block is lent only up to twice the size asked for.)
  for (Block& b : t_kept) {
    if (bytes >= kKeptBlockMinBytes && b.data && b.size >= bytes && b.size / 2 <= bytes &&
        (!best || b.size < best->size)) {
      best = &b;
    }
  }
  if (best) return std::exchange(*best, Block{});
  // (aligned_alloc wants a multiple of the alignment; free takes either kind.)
  const bool whole_pages = bytes >= kAlignedBlockMinBytes;
  const std::size_t size =
      whole_pages ? (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes : bytes;
  Block b{std::unique_ptr<std::byte[], FreeBlock>(static_cast<std::byte*>(
              whole_pages ? std::aligned_alloc(kHugePageBytes, size) : std::malloc(size))),
          size};
  if (!b.data && size > 0) throw std::bad_alloc();
  advise_huge_pages(b.data.get(), size);
  return b;
}

void give_block(Block b) noexcept {
  if (!t_keep || !b.data || b.size < kKeptBlockMinBytes || b.size > kKeptMaxBytes) return;
  // Into an empty slot, else in place of the smallest kept block if b is larger.
  Block* slot = &t_kept[0];
  for (Block& k : t_kept) {
    if (!k.data || (slot->data && k.size < slot->size)) slot = &k;
  }
  if (slot->data && slot->size >= b.size) return;
  *slot = std::move(b);
  std::size_t total = 0;
  for (const Block& k : t_kept) total += k.size;
  while (total > kKeptMaxBytes) {  // the smallest go first
    Block* smallest = nullptr;
    for (Block& k : t_kept) {
      if (k.data && (!smallest || k.size < smallest->size)) smallest = &k;
    }
    total -= smallest->size;
    *smallest = Block{};
  }
}

}  // namespace fairspline::detail

namespace fairspline {

void keep_fit_memory(bool keep) {
  detail::t_keep = keep;
  if (!keep) detail::t_kept = {};
}

}  // namespace fairspline
