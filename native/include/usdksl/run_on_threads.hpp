#pragma once
/// @file run_on_threads.hpp
/// @brief Work handed out to a few threads, the caller's included, with the
///        first failure rethrown on the caller's.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace usdksl {

/// @brief The FollowUp of work whose failures all count.
struct NoFollowUpFailure {};

/// @brief Runs body(item) on `workers` threads (the caller's included) for
///        every item take(item) hands out until it returns false. After an
///        exception, hand_out_no_more() is called so the other threads stop
///        taking items, and the first exception is rethrown once all are
///        done; one of type FollowUp (thrown only because another failed
///        first) is never the one reported.
template <typename Item, typename FollowUp = NoFollowUpFailure, typename Take, typename Body, typename Stop>
void run_on_threads(int32_t workers, Take take, Body body, Stop hand_out_no_more) {
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&]() {
        Item item;
        while (take(item)) {
            try {
                body(item);
            } catch (const FollowUp&) {
                hand_out_no_more();
            } catch (...) {
                std::lock_guard<std::mutex> lock(failure_mutex);
                if (!failure) failure = std::current_exception();
                hand_out_no_more();
            }
        }
    };
    std::vector<std::thread> threads;
    for (int32_t t = 1; t < workers; ++t) threads.emplace_back(work);
    work();
    for (std::thread& thread : threads) thread.join();
    if (failure) std::rethrow_exception(failure);
}

/// @brief Runs body(k) for k in [0, count) on up to `threads` threads (see
///        run_on_threads).
template <typename FollowUp = NoFollowUpFailure, typename Body>
void parallel_for(int32_t threads, int32_t count, Body body) {
    std::atomic<int32_t> next{0};
    run_on_threads<int32_t, FollowUp>(
        std::min(threads, count), [&](int32_t& k) { return (k = next++) < count; }, body, [&]() { next = count; });
}

} // namespace usdksl
