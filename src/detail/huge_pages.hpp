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

/// The smallest block take_block lends from those given back (smaller ones are malloc's). Not
/// larger: a fit's freed temporaries of a few hundred KiB at 10^3 points left glibc's heap top
/// above its trim threshold, and it gave them back to the kernel after every fit (32 page
/// faults a fit, 0.17 → 0.6–0.8 ms, depending on what else the process had freed before).
inline constexpr std::size_t kKeptBlockMinBytes = std::size_t{64} << 10;

/// Raw memory of one fit (min-energy's arenas, its Scratch arrays and BlockVectors).
struct Block {
  std::unique_ptr<std::byte[]> data;
  std::size_t size = 0;
};

/// A block of at least `bytes`, advised for huge pages: the smallest large enough of those this
/// thread gave back (its pages are mapped already) if it is at most twice the size asked for,
/// else a new one (uninitialized either way).
Block take_block(std::size_t bytes);
/// Keeps `b` for this thread's next take_block, or frees it. Blocks of kKeptBlockMinBytes and
/// more are kept (glibc maps large ones afresh, and the kernel zeroes their pages again: ~200 MB
/// at 10^6 points, 12% of a fit; smaller ones it may return to the kernel as its heap top),
/// at most sixteen and 256 MiB in all: the largest stay. They are freed when the thread ends.
void give_block(Block b) noexcept;

/// An allocator whose arrays of kKeptBlockMinBytes and more are take_block's and go back by
/// give_block (the optimizer's vectors; at 10^6 points fresh pages for them were ~8% of a fit).
template <typename T>
struct BlockAllocator {
  static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
  using value_type = T;
  BlockAllocator() = default;
  template <typename U>
  explicit BlockAllocator(const BlockAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n * sizeof(T) < kKeptBlockMinBytes) return std::allocator<T>{}.allocate(n);
    return reinterpret_cast<T*>(take_block(n * sizeof(T)).data.release());
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kKeptBlockMinBytes) return std::allocator<T>{}.deallocate(p, n);
    // (The block may be larger than n elements: it is given back as this size.)
    give_block({std::unique_ptr<std::byte[]>(reinterpret_cast<std::byte*>(p)), n * sizeof(T)});
  }
  friend bool operator==(const BlockAllocator&, const BlockAllocator&) = default;
};

template <typename T>
using BlockVector = std::vector<T, BlockAllocator<T>>;

/// v.reserve(n), the new storage advised before anything touches it.
template <typename T, typename A>
void reserve_huge(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) {
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
  }
}

/// v.resize(n), the new storage advised before anything touches it (reserve does not).
template <typename T, typename A>
void resize_huge(std::vector<T, A>& v, std::size_t n) {
  reserve_huge(v, n);
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
