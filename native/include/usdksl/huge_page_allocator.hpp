#pragma once
/// @file huge_page_allocator.hpp
/// @brief An allocator that asks Linux for transparent huge pages on large
///        blocks: the front, its hash indexes and the found contacts of a
///        million-face check span gigabytes reached in random order, and
///        with 4 KiB pages most of those reaches miss the TLB.

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace usdksl {

/// @brief Size of a transparent huge page on x86-64 and most AArch64 kernels (bytes).
constexpr size_t HUGE_PAGE_BYTES = size_t{2} << 20;
/// @brief Blocks from this size on (bytes) are aligned to huge pages and
///        advised to use them; smaller ones come from the ordinary heap,
///        where a huge page would mostly hold memory nobody touches.
constexpr size_t HUGE_PAGE_MIN_BLOCK_BYTES = 2 * HUGE_PAGE_BYTES;

/// @brief A block of `bytes`: huge-page aligned and advised when large.
inline void* allocate_maybe_huge(size_t bytes) {
    if (bytes < HUGE_PAGE_MIN_BLOCK_BYTES) return ::operator new(bytes);
    const size_t rounded = (bytes + HUGE_PAGE_BYTES - 1) / HUGE_PAGE_BYTES * HUGE_PAGE_BYTES;
    void* block = std::aligned_alloc(HUGE_PAGE_BYTES, rounded);
    if (!block) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
    // Only advice: where the kernel has transparent huge pages off, nothing changes.
    madvise(block, rounded, MADV_HUGEPAGE);
#endif
    return block;
}

/// @brief Frees a block of allocate_maybe_huge(bytes), given the same `bytes`.
inline void free_maybe_huge(void* block, size_t bytes) noexcept {
    if (bytes < HUGE_PAGE_MIN_BLOCK_BYTES) ::operator delete(block);
    else std::free(block);
}

/// @brief std::allocator with allocate_maybe_huge underneath.
template <class T>
struct HugePageAllocator {
    using value_type = T;

    HugePageAllocator() noexcept = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(size_t n) { return static_cast<T*>(allocate_maybe_huge(n * sizeof(T))); }
    void deallocate(T* p, size_t n) noexcept { free_maybe_huge(p, n * sizeof(T)); }

    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
    template <class U>
    bool operator!=(const HugePageAllocator<U>&) const noexcept { return false; }
};

/// @brief A std::vector whose large arrays sit on huge pages.
template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

/// @brief Frees the block of a HugeArray.
template <class T>
struct HugeArrayDeleter {
    size_t bytes = 0;
    void operator()(T* block) const noexcept { free_maybe_huge(block, bytes); }
};

/// @brief A fixed-size array whose large blocks sit on huge pages.
template <class T>
using HugeArray = std::unique_ptr<T[], HugeArrayDeleter<T>>;

/// @brief An array of `count` elements left uninitialized, for arrays whose
///        every element is written once, by several threads: zeroing them
///        first would be serial work on the caller's thread.
template <class T>
HugeArray<T> make_uninitialized_huge_array(size_t count) {
    static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>);
    const size_t bytes = std::max<size_t>(count, 1) * sizeof(T);
    return HugeArray<T>(static_cast<T*>(allocate_maybe_huge(bytes)), HugeArrayDeleter<T>{bytes});
}

} // namespace usdksl
