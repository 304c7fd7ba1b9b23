#pragma once
/// @file event_queue.hpp
/// @brief An indexed binary min-heap of events keyed by (time, handle).

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace usdksl {

/// @brief Each handle (a small integer naming who owns the event) has at most
///        one pending event. Equal times pop in handle order, so a run is
///        deterministic whatever order events were pushed in.
class EventQueue {
public:
    /// @brief Schedules (or reschedules) handle's event at time code `time`;
    ///        an infinite time removes it.
    void schedule(int64_t handle, double time);
    /// @brief Removes handle's pending event, if any.
    void cancel(int64_t handle);
    bool empty() const { return heap_.empty(); }
    /// @brief Time code of the earliest event (+inf when empty).
    double top_time() const { return heap_.empty() ? std::numeric_limits<double>::infinity() : heap_[0].time; }
    /// @brief Removes and returns the earliest event's handle.
    int64_t pop();

private:
    /// Keys live in the heap itself, so sifting reads no other array.
    struct Event {
        double time;
        int64_t handle;
    };
    static bool before(const Event& a, const Event& b) {
        return a.time < b.time || (a.time == b.time && a.handle < b.handle);
    }
    void ensure(int64_t handle);
    void place(size_t index, const Event& event);
    void sift_up(size_t index);
    void sift_down(size_t index);

    std::vector<Event> heap_;
    std::vector<int64_t> position_;  // -1 when not queued
};

} // namespace usdksl
