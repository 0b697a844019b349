#include "detail/huge_pages.hpp"

#include <array>
#include <cstdint>
#include <utility>

#include "fairspline/fit.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fairspline::detail {

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  if (p == nullptr || bytes < 2 * kHuge) return;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = (a + kHuge - 1) & ~(kHuge - 1), hi = (a + bytes) & ~(kHuge - 1);
  // (A failure, e.g. EINVAL where THP is compiled out, leaves ordinary pages: nothing to do.)
  if (hi > lo) static_cast<void>(madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE));
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
  Block b{std::make_unique_for_overwrite<std::byte[]>(bytes), bytes};
  advise_huge_pages(b.data.get(), bytes);
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
