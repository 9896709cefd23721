// Buffers placed by "colour": the scratch arrays a hot loop reads and writes
// at equal indices (a pair batch's displacements and the kernel's outputs,
// a home cell's candidates and the list of those within eps) each start at
// 64 + 256 colour bytes into a 4 KiB page of their own allocation, with
// whole cache lines of padding on both sides. So two buffers of different
// colours never share a cache line with each other or with anything else
// (no false sharing between threads' scratch and shared data), and their
// elements of equal index lie at different offsets modulo 4 KiB: a load
// does not wait on an unrelated store with the same low 12 address bits
// ("4K aliasing" in Intel's optimization manual) and the streams do not
// crowd the same L1 sets. Measured on the Intel host of stop 68 (3D SPH
// sweep, N = 10648, best of 300, twelve processes each): with malloc's
// placement two systems built alike differed by 5-8 % on two threads (in
// append_near, whose loads of y waited on its stores to close); page-aligned
// buffers (one colour) were 15-30 % slower; colours with close above y
// left some processes ~30 % slower; pair_batch.hpp's colours: two threads
// 570-595 -> 525-538 us, one 1020-1054 -> 992-1005 us, alike in every process.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <vector>

namespace mollify::detail {

inline constexpr std::size_t page_bytes = 4096, colour_bytes = 256, colours = page_bytes / colour_bytes;

template <class T>
class ColouredAllocator {
public:
    using value_type = T;
    using propagate_on_container_copy_assignment = std::true_type;
    using propagate_on_container_move_assignment = std::true_type;
    using propagate_on_container_swap = std::true_type;

    explicit ColouredAllocator(std::size_t colour = 0) noexcept : colour_(colour % colours) {}
    template <class U>
    ColouredAllocator(const ColouredAllocator<U>& other) noexcept : colour_(other.colour()) {}

    std::size_t colour() const noexcept { return colour_; }

    // malloc's block, two pages longer than the data: the data at the
    // colour's offset past the leading line, which holds malloc's pointer,
    // of the block's first page boundary; more than two lines of slack after it.
    T* allocate(std::size_t n) {
        static_assert(alignof(T) <= 64);
        if (n > (SIZE_MAX - 2 * page_bytes) / sizeof(T)) throw std::bad_alloc();
        char* raw = static_cast<char*>(std::malloc(n * sizeof(T) + 2 * page_bytes));
        if (!raw) throw std::bad_alloc();
        const std::uintptr_t page = (reinterpret_cast<std::uintptr_t>(raw) + page_bytes - 1) & ~std::uintptr_t(page_bytes - 1);
        char* data = reinterpret_cast<char*>(page + 64 + colour_bytes * colour_);
        reinterpret_cast<char**>(data)[-1] = raw;
        return reinterpret_cast<T*>(data);
    }
    void deallocate(T* p, std::size_t) noexcept { std::free(reinterpret_cast<char**>(p)[-1]); }

    template <class U>
    bool operator==(const ColouredAllocator<U>& other) const noexcept {
        return colour_ == other.colour();
    }

private:
    std::size_t colour_;
};

template <class T>
using ColouredVector = std::vector<T, ColouredAllocator<T>>;

}  // namespace mollify::detail
