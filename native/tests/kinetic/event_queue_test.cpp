/// @file event_queue_test.cpp
/// @brief The event queue pops in (time, handle) order whatever the push order.

#include "usdksl/kinetic/event_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <utility>
#include <vector>

using usdksl::EventQueue;

namespace {

std::vector<int64_t> drain(EventQueue& queue) {
    std::vector<int64_t> order;
    while (!queue.empty()) order.push_back(queue.pop());
    return order;
}

} // namespace

TEST(EventQueue, PopsByTimeThenHandle) {
    EventQueue queue;
    queue.schedule(7, 2.0);
    queue.schedule(3, 1.0);
    queue.schedule(5, 1.0);
    queue.schedule(1, 3.0);
    EXPECT_DOUBLE_EQ(queue.top_time(), 1.0);
    EXPECT_EQ(drain(queue), (std::vector<int64_t>{3, 5, 7, 1}));
    EXPECT_TRUE(std::isinf(queue.top_time()));
}

TEST(EventQueue, TiesPopInHandleOrderForEveryPushOrder) {
    std::vector<int64_t> handles{9, 2, 14, 0, 5, 11};
    std::sort(handles.begin(), handles.end());
    const std::vector<int64_t> expected = handles;
    do {
        EventQueue queue;
        for (int64_t h : handles) queue.schedule(h, 4.5);
        ASSERT_EQ(drain(queue), expected);
    } while (std::next_permutation(handles.begin(), handles.end()));
}

TEST(EventQueue, RescheduleMovesTheOneEventOfAHandle) {
    EventQueue queue;
    queue.schedule(1, 5.0);
    queue.schedule(2, 3.0);
    queue.schedule(1, 1.0);  // earlier
    queue.schedule(2, 9.0);  // later
    EXPECT_EQ(drain(queue), (std::vector<int64_t>{1, 2}));
}

TEST(EventQueue, CancelAndInfiniteTimeRemove) {
    EventQueue queue;
    queue.schedule(1, 1.0);
    queue.schedule(2, 2.0);
    queue.schedule(3, 3.0);
    queue.cancel(2);
    queue.schedule(3, std::numeric_limits<double>::infinity());
    queue.cancel(42);  // never scheduled: nothing happens
    EXPECT_EQ(drain(queue), (std::vector<int64_t>{1}));
}

TEST(EventQueue, MatchesASortedReferenceOnRandomOperations) {
    std::mt19937 random(12345);
    std::uniform_int_distribution<int> handle(0, 63);
    std::uniform_int_distribution<int> time(0, 20);  // many ties
    std::uniform_int_distribution<int> operation(0, 9);
    EventQueue queue;
    std::vector<double> reference(64, std::numeric_limits<double>::infinity());
    for (int step = 0; step < 20000; ++step) {
        const int op = operation(random);
        const int h = handle(random);
        if (op < 6) {
            const double t = time(random);
            queue.schedule(h, t);
            reference[h] = t;
        } else if (op < 8) {
            queue.cancel(h);
            reference[h] = std::numeric_limits<double>::infinity();
        } else if (!queue.empty()) {
            int64_t best = -1;
            for (int64_t i = 0; i < 64; ++i) {
                if (std::isfinite(reference[i]) && (best < 0 || reference[i] < reference[best])) best = i;
            }
            ASSERT_EQ(queue.top_time(), reference[best]);
            ASSERT_EQ(queue.pop(), best);
            reference[best] = std::numeric_limits<double>::infinity();
        }
    }
}
