// Large arrays in transparent huge pages where the system offers them (private).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace fairspline::detail {

/// Asks the kernel to back the whole 2 MiB pages inside [p, p + bytes) with transparent huge
/// pages when they are first touched. A fresh 4 KiB page cost 7–14 µs to fault in on the
/// measuring machines (16 MiB of new memory: 30 ms; with huge pages 1.7 ms), and a long fit
/// writes tens of MiB of new memory (docs/methods/min-energy.md, "Performance"). Only a hint:
/// nothing happens for pages already touched, where THP is off, or off Linux. Memory is not
/// rounded up: the partial pages at either end stay small (take_block aligns its large blocks).
void advise_huge_pages(void* p, std::size_t bytes) noexcept;

/// Maps in the pages of [p, p + bytes) for writing in one system call, for memory about to be
/// written whole: a page faulted in this way cost 6 µs on the measuring VM instead of 14 µs for
/// one first touched (the trap is most of a 4 KiB page's cost there). Only for 1 MiB and more;
/// a hint like advise_huge_pages (nothing happens where the call is unknown).
void prefault(void* p, std::size_t bytes) noexcept;

/// The smallest block take_block lends from those given back (smaller ones are malloc's). Not
/// larger: a fit's freed temporaries of a few hundred KiB at 10^3 points left glibc's heap top
/// above its trim threshold, and it gave them back to the kernel after every fit (32 page
/// faults a fit, 0.17 → 0.6–0.8 ms, depending on what else the process had freed before).
inline constexpr std::size_t kKeptBlockMinBytes = std::size_t{64} << 10;

/// The size of a transparent huge page on x86-64 and most arm64 kernels.
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// From this size on, a new block starts on a huge page boundary and is rounded up to whole huge
/// pages, so that every page of it can be one: a fresh 4 KiB page cost 14 µs to fault in on the
/// measuring VM (a 2 MiB one 140 µs), and at 2·10^5 points a fit's arrays of 1.6–3.2 MB, each
/// under two huge pages, took half of a one-shot process's 10^4 page faults.
inline constexpr std::size_t kAlignedBlockMinBytes = std::size_t{1} << 20;

struct FreeBlock {
  void operator()(std::byte* p) const noexcept;
};

/// Raw memory of one fit (min-energy's arenas, its Scratch arrays and BlockVectors).
struct Block {
  std::unique_ptr<std::byte[], FreeBlock> data;
  std::size_t size = 0;  // usable bytes (at least those asked for)
};

/// A block of at least `bytes`, advised for huge pages: the smallest large enough of those this
/// thread gave back (its pages are mapped already) if it is at most twice the size asked for,
/// else a new one (uninitialized either way; from kAlignedBlockMinBytes on, whole huge pages).
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
    give_block(
        {std::unique_ptr<std::byte[], FreeBlock>(reinterpret_cast<std::byte*>(p)), n * sizeof(T)});
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

/// reserve_huge for n elements about to be appended one by one: the new storage is mapped in
/// as well (push_back would take its pages one fault at a time).
template <typename T, typename A>
void reserve_to_fill(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) {
    reserve_huge(v, n);
    prefault(v.data() + v.size(), (n - v.size()) * sizeof(T));
  }
}

/// v.resize(n), new storage advised and mapped in before anything touches it (reserve does not).
template <typename T, typename A>
void resize_huge(std::vector<T, A>& v, std::size_t n) {
  reserve_to_fill(v, n);
  v.resize(n);
}

/// v.assign(n, value), advised as resize_huge.
template <typename T, typename A>
void assign_huge(std::vector<T, A>& v, std::size_t n, const T& value) {
  if (n > v.capacity()) {
    std::vector<T, A>(v.get_allocator()).swap(v);  // no copy of the old contents
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
    prefault(v.data(), n * sizeof(T));
  }
  v.assign(n, value);
}

}  // namespace fairspline::detail
