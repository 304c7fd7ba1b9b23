#include "usdksl/kinetic/event_queue.hpp"

#include <cmath>

namespace usdksl {

void EventQueue::ensure(int64_t handle) {
    if (handle >= static_cast<int64_t>(position_.size())) position_.resize(static_cast<size_t>(handle) + 1, -1);
}

void EventQueue::place(size_t index, const Event& event) {
    heap_[index] = event;
    position_[event.handle] = static_cast<int64_t>(index);
}

void EventQueue::sift_up(size_t index) {
    const Event event = heap_[index];
    while (index > 0) {
        const size_t parent = (index - 1) / 2;
        if (!before(event, heap_[parent])) break;
        place(index, heap_[parent]);
        index = parent;
    }
    place(index, event);
}

void EventQueue::sift_down(size_t index) {
    const Event event = heap_[index];
    const size_t n = heap_.size();
    while (true) {
        size_t child = 2 * index + 1;
        if (child >= n) break;
        if (child + 1 < n && before(heap_[child + 1], heap_[child])) ++child;
        if (!before(heap_[child], event)) break;
        place(index, heap_[child]);
        index = child;
    }
    place(index, event);
}

void EventQueue::schedule(int64_t handle, double time) {
    if (std::isinf(time)) {
        cancel(handle);
        return;
    }
    ensure(handle);
    if (position_[handle] < 0) {
        heap_.push_back({time, handle});
        position_[handle] = static_cast<int64_t>(heap_.size()) - 1;
        sift_up(heap_.size() - 1);
    } else {
        const size_t index = static_cast<size_t>(position_[handle]);
        const double old = heap_[index].time;
        heap_[index].time = time;
        if (time < old) sift_up(index);
        else sift_down(index);
    }
}

void EventQueue::cancel(int64_t handle) {
    if (handle >= static_cast<int64_t>(position_.size()) || position_[handle] < 0) return;
    const size_t index = static_cast<size_t>(position_[handle]);
    position_[handle] = -1;
    const Event last = heap_.back();
    heap_.pop_back();
    if (index < heap_.size()) {
        place(index, last);
        sift_up(index);
        sift_down(static_cast<size_t>(position_[last.handle]));
    }
}

int64_t EventQueue::pop() {
    const int64_t handle = heap_[0].handle;
    cancel(handle);
    return handle;
}

} // namespace usdksl
