// Work split over the hardware threads. Every user writes each result to its own slot (or reduces per chunk and
// combines the chunks in order), so the output does not depend on how many threads ran: tests compare a run on
// one thread with a run on several (setWorkerThreads).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace ink {

inline std::atomic<unsigned> gWorkerThreads{0};

// The threads parallel work uses: all hardware threads, or what setWorkerThreads asked for.
inline unsigned workerThreads() {
    unsigned asked = gWorkerThreads.load(std::memory_order_relaxed);
    return asked ? asked : std::max(1u, std::thread::hardware_concurrency());
}

// 0: all hardware threads (the default). For tests of determinism and for measuring.
inline void setWorkerThreads(unsigned threads) { gWorkerThreads.store(threads, std::memory_order_relaxed); }

// body(begin, end, chunk) over [0, n) in `chunks` contiguous chunks (chunk k covers [n k / chunks, n (k+1) /
// chunks)), run on up to workerThreads() threads; returns the number of chunks, at least 1 (for n = 0, one
// empty chunk). The chunks depend on n and minChunk only, not on the threads, so per-chunk results combined in
// chunk order are the same whatever the thread count. body must not throw.
template <class Body>
size_t parallelChunks(size_t n, size_t minChunk, Body body) {
    const size_t chunks = std::clamp<size_t>(n / std::max<size_t>(minChunk, 1), 1, 64);
    const size_t threads = std::min<size_t>(workerThreads(), chunks);
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t k; (k = next++) < chunks;) body(n * k / chunks, n * (k + 1) / chunks, k);
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    return chunks;
}

}  // namespace ink
