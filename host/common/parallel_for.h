// The one parallel loop of the host code: indices handed out in order through an atomic counter to a few
// std::threads, the calling thread among them, so that uneven work balances itself.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace vkrt {

// `requested` threads, or with 0 (or less) all hardware threads; at least 1.
inline unsigned threadCount(int requested) {
    if (requested > 0) return static_cast<unsigned>(requested);
    return std::max(1u, std::thread::hardware_concurrency());
}

// Calls body(index, worker) for every index in [0, count), on at most `threads` threads. `worker` in
// [0, threads) names the thread that runs the call, for per-thread state such as counters. Returns when
// every call has returned; the body must not throw.
template <typename Body>
void parallelFor(size_t count, unsigned threads, Body&& body) {
    threads = static_cast<unsigned>(std::clamp<size_t>(count, 1, std::max(1u, threads)));
    std::atomic<size_t> next{0};
    auto work = [&](unsigned worker) {
        for (size_t index = next++; index < count; index = next++) body(index, worker);
    };
    std::vector<std::jthread> pool;
    for (unsigned worker = 1; worker < threads; ++worker) pool.emplace_back(work, worker);
    work(0);
}

}  // namespace vkrt
