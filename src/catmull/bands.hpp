// Bands of rows on a pool of C++ threads. The image is cut into bands of BAND_ROWS rows, each
// run from its own first row, so bands are independent and the result is the same, bit for
// bit, on any number of threads. The threads are made for one call and joined before it
// returns: nothing outlives the call (a forked child starts clean).
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace aaeval::catmull {

inline constexpr int64_t BAND_ROWS = 32;

// The order threads take n bands in: the image cut into `threads` runs of bands, one band
// from each in turn, so that threads write far-apart memory (neighbouring bands share the
// 2 MB pages of a new image: two threads first touching one at the same time both zero it).
inline std::vector<int64_t> far_apart(int64_t n, int64_t threads) {
    const int64_t run = (n + threads - 1) / threads;
    std::vector<int64_t> order;
    order.reserve(size_t(n));
    for (int64_t i = 0; i < run; ++i)
        for (int64_t k = 0; k < threads; ++k)
            if (k * run + i < n) order.push_back(k * run + i);
    return order;
}

// band(index, row0, row1) for every band of rows, on `threads` threads (at most one per band).
template <class F>
inline void run_bands(int64_t height, int64_t threads, F&& band) {
    const int64_t n = (height + BAND_ROWS - 1) / BAND_ROWS;
    auto rows = [&](int64_t i, int64_t& r0, int64_t& r1) {
        r0 = i * BAND_ROWS;
        r1 = r0 + BAND_ROWS < height ? r0 + BAND_ROWS : height;
    };
    if (threads > n) threads = n;
    if (threads <= 1) {
        for (int64_t i = 0; i < n; ++i) {
            int64_t r0, r1;
            rows(i, r0, r1);
            band(i, r0, r1);
        }
        return;
    }
    const std::vector<int64_t> order = far_apart(n, threads);
    std::atomic<int64_t> next{0};
    std::exception_ptr error;
    std::mutex error_lock;
    auto worker = [&]() {
        for (;;) {
            const int64_t t = next.fetch_add(1);
            if (t >= n) return;
            try {
                int64_t r0, r1;
                rows(order[size_t(t)], r0, r1);
                band(order[size_t(t)], r0, r1);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_lock);
                if (!error) error = std::current_exception();
                next.store(n);
            }
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(size_t(threads - 1));
    for (int64_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace aaeval::catmull
