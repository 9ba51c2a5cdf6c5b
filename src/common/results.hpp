// Results handed to Python: the memory of a new array the kernels write, and a vector given
// over as it is. Shared by every module (nanobind).
//
// A large result (16 MB and more: a 1024 x 1024 RGB float64 image is 25 MB) is 2 MB aligned
// and advised for transparent huge pages, as numpy advises its own large arrays, where the
// kernel gives huge pages only to memory that asks (transparent_hugepage = madvise). With
// 4 KB pages a new image is mapped afresh and first touched page by page whenever malloc has
// no freed block of its size at hand (a 2048 x 2048 image, 100 MB, always: above glibc's
// 32 MB mmap threshold): 25,600 page faults, as many unmaps when freed. Measured on
// catmull's renders of the benchmark scenes: 2048 x 2048 102 -> 64 ms; 1024 x 1024
// interleaved with other methods (bench_methods) 42 -> 32 ms. Below 16 MB malloc hands back
// the block a render just freed, already mapped (huge pages measured 1% slower at 512 x 512),
// and a kernel's temporaries stay with malloc for the same reason.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <utility>
#include <vector>

namespace aaeval::results {

namespace nb = nanobind;

inline constexpr size_t HUGE_PAGE = size_t(2) << 20;
inline constexpr size_t HUGE_FROM = size_t(16) << 20;

// Memory for `count` values of T (at least one), zeroed if asked; freed with std::free.
template <class T>
T* allocate(size_t count, bool zeroed) {
    size_t bytes = (count > 0 ? count : 1) * sizeof(T);
    void* p = nullptr;
    if (bytes >= HUGE_FROM) {
        bytes = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;  // aligned_alloc wants a multiple
        p = std::aligned_alloc(HUGE_PAGE, bytes);
#if defined(MADV_HUGEPAGE)
        if (p != nullptr) madvise(p, bytes, MADV_HUGEPAGE);  // advice only: its failure changes nothing
#endif
    } else {
        p = std::malloc(bytes);
    }
    if (p == nullptr) throw std::bad_alloc();  // nanobind raises MemoryError
    if (zeroed) std::memset(p, 0, bytes);
    return static_cast<T*>(p);
}

// A new numpy array of the given shape owning memory from allocate(); `data` points at it.
template <class T>
nb::ndarray<nb::numpy, T> new_array(const std::vector<size_t>& shape, T*& data, bool zeroed) {
    size_t count = 1;
    for (size_t e : shape) count *= e;
    data = allocate<T>(count, zeroed);
    nb::capsule owner(data, [](void* p) noexcept { std::free(p); });
    return nb::ndarray<nb::numpy, T>(data, shape.size(), shape.data(), owner);
}

// A numpy array owning the vector's data (moved, not copied).
template <class T>
nb::ndarray<nb::numpy, T> from_vector(std::vector<T>&& v, const std::vector<size_t>& shape) {
    if (v.empty()) v.reserve(1);  // a real pointer even when empty
    auto* owned = new std::vector<T>(std::move(v));
    nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return nb::ndarray<nb::numpy, T>(owned->data(), shape.size(), shape.data(), owner);
}

}  // namespace aaeval::results
