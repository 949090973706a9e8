#pragma once
/// @file bulk_memory.hpp  The allocator of the hierarchical solve's link lists: large blocks in
/// pages of 2 MiB where the kernel offers them. A refinement pass fills lists of millions of
/// links that it did not have a moment before (each round's tasks, the settled links), and
/// every 4 KiB page of them costs a page fault on its first write: in a virtual machine several
/// microseconds each, a quarter of room3's refinement. Mapped in 2 MiB-aligned pieces and
/// marked MADV_HUGEPAGE, the same memory comes in 512 times fewer faults (transparent huge
/// pages, in the kernel's "madvise" and "always" modes; elsewhere it is an ordinary mapping).

#include <cstddef>
#include <cstdint>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace radiosity::detail {

/// The size of a transparent huge page on x86-64 and most AArch64 kernels.
inline constexpr std::size_t huge_page = std::size_t{2} << 20;

/// bytes (or an address) rounded up to whole huge pages.
inline constexpr std::size_t in_huge_pages(std::size_t bytes) {
    return (bytes + huge_page - 1) / huge_page * huge_page;
}

/// A mapping of `bytes` (a multiple of huge_page) aligned to huge_page, marked for huge pages:
/// mapped one huge page larger, the ends past the alignment given back. Throws std::bad_alloc
/// when the memory cannot be had.
inline void* map_huge(std::size_t bytes) {
#if defined(__linux__)
    const std::size_t span = bytes + huge_page;
    void* p = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t aligned = in_huge_pages(at);
    if (aligned > at) munmap(p, aligned - at);
    if (const std::uintptr_t tail = at + span - (aligned + bytes); tail > 0)
        munmap(reinterpret_cast<void*>(aligned + bytes), tail);
#if defined(MADV_HUGEPAGE)
    madvise(reinterpret_cast<void*>(aligned), bytes, MADV_HUGEPAGE);  // a hint: may be refused
#endif
    return reinterpret_cast<void*>(aligned);
#else
    return ::operator new(bytes);
#endif
}

/// Gives back a mapping from map_huge(bytes).
inline void unmap_huge(void* p, std::size_t bytes) noexcept {
#if defined(__linux__)
    munmap(p, bytes);
#else
    ::operator delete(p, bytes);
#endif
}

/// The allocator of large, short-lived lists (std::vector<T, BulkAllocator<T>>): from one huge
/// page on, whole huge pages from map_huge (the last one partly unused: at most 2 MiB lost per
/// list, a few percent of lists that large); below, operator new.
template <class T>
struct BulkAllocator {
    using value_type = T;

    BulkAllocator() = default;
    /// Rebinding, as allocators must allow: every BulkAllocator is alike.
    template <class U>
    BulkAllocator(const BulkAllocator<U>&) {}

    /// Room for n elements; throws std::bad_alloc when the memory cannot be had.
    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (bytes >= huge_page) return static_cast<T*>(map_huge(in_huge_pages(bytes)));
        return static_cast<T*>(::operator new(bytes));
    }
    /// Returns memory from allocate(n) the way it came.
    void deallocate(T* p, std::size_t n) noexcept {
        const std::size_t bytes = n * sizeof(T);
        if (bytes >= huge_page) return unmap_huge(p, in_huge_pages(bytes));
        ::operator delete(p);
    }
    /// All BulkAllocators can free each other's memory.
    template <class U>
    bool operator==(const BulkAllocator<U>&) const {
        return true;
    }
};

}  // namespace radiosity::detail
