// Large arrays in transparent huge pages where the system offers them (private).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace fairspline::detail {

/// Asks the kernel to back the whole 2 MiB pages inside [p, p + bytes) with transparent huge
/// pages when they are first touched. A fresh 4 KiB page cost ~7 µs to fault in on the
/// measuring machine (16 MiB of new memory: 30 ms; with huge pages 1.7 ms), and a long fit
/// writes tens of MiB of new memory (docs/methods/min-energy.md, "Performance"). Only a hint:
/// nothing happens for blocks under 4 MiB, for pages already touched, where THP is off, or
/// off Linux. Memory is not rounded up: the partial pages at either end stay small.
void advise_huge_pages(void* p, std::size_t bytes) noexcept;

/// Raw memory of one fit (min-energy's arenas).
struct Block {
  std::unique_ptr<std::byte[]> data;
  std::size_t size = 0;
};

/// A block of at least `bytes`, advised for huge pages: the smallest large enough of those this
/// thread gave back (its pages are mapped already), else a new one (uninitialized either way).
Block take_block(std::size_t bytes);
/// Keeps `b` for this thread's next take_block, or frees it. Only blocks of 4 MiB and more are
/// kept (malloc reuses smaller ones itself; larger ones it maps afresh, and the kernel zeroes
/// their pages again: ~130 MB at 10^6 points, 7% of a fit), at most three and 256 MiB in all:
/// the largest stay. They are freed when the thread ends.
void give_block(Block b) noexcept;

/// v.resize(n), the new storage advised before anything touches it (reserve does not).
template <typename T, typename A>
void resize_huge(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) {
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
  }
  v.resize(n);
}

/// v.assign(n, value), advised as resize_huge.
template <typename T, typename A>
void assign_huge(std::vector<T, A>& v, std::size_t n, const T& value) {
  if (n > v.capacity()) {
    std::vector<T, A>(v.get_allocator()).swap(v);  // no copy of the old contents
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
  }
  v.assign(n, value);
}

}  // namespace fairspline::detail
