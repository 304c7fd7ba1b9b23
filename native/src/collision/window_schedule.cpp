#include "window_schedule.hpp"

#include <algorithm>

namespace usdksl {

WindowSchedule::WindowSchedule(const WindowCuts& cuts, const std::vector<TimeWindow>& planned, bool cuttable)
    : cuts_(cuts), cuttable_(cuttable), planned_(planned.size()) {
    for (const TimeWindow& w : planned) windows_.push_back(std::make_unique<ScheduledWindow>(w.begin, w.end));
}

ScheduledWindow* WindowSchedule::next() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (cancelled_) return nullptr;
    if (next_planned_ < planned_) {
        ScheduledWindow* window = windows_[next_planned_++].get();
        window->started = true;
        return window;
    }
    return cuttable_ ? cut_running_window() : nullptr;
}

ScheduledWindow* WindowSchedule::cut_running_window() {
    ScheduledWindow* victim = nullptr;
    int64_t from = 0, to = 0;
    for (const auto& window : windows_) {
        if (!window->started || window->finished) continue;
        const int64_t a = cuts_.index_at_or_after(window->stop.reached.load(std::memory_order_acquire));
        const int64_t b = cuts_.index_at_or_after(window->end);
        if (b - a > to - from) {
            victim = window.get();
            from = a;
            to = b;
        }
    }
    if (!victim || to - from < 2 * MIN_SAMPLE_STEPS_PER_CUT) return nullptr;
    // Half the steps ahead each; both parts keep the minimum span, in
    // sample steps and in flightplan steps.
    const auto [lo, hi] = cuts_.keeping_flightplan_steps(from, to, MIN_SAMPLE_STEPS_PER_CUT);
    const int64_t cut = cuts_.best_cut(from + (to - from) / 2, (to - from) / 4,
                                       std::max(lo, from + MIN_SAMPLE_STEPS_PER_CUT),
                                       std::min(hi, to - MIN_SAMPLE_STEPS_PER_CUT));
    if (cut < 0) return nullptr;
    const double at = cuts_.times()[static_cast<size_t>(cut)];
    windows_.push_back(std::make_unique<ScheduledWindow>(at, victim->end));
    ScheduledWindow* taken = windows_.back().get();
    taken->started = true;
    victim->end = at;
    victim->stop.stop_at.store(at, std::memory_order_release);
    ++cuts_made_;
    return taken;
}

void WindowSchedule::finish(ScheduledWindow& window) {
    std::lock_guard<std::mutex> lock(mutex_);
    window.finished = true;
}

bool WindowSchedule::any_running() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return !cancelled_ && std::any_of(windows_.begin(), windows_.end(),
                       [](const auto& window) { return window->started && !window->finished; });
}

void WindowSchedule::cancel() {
    std::lock_guard<std::mutex> lock(mutex_);
    cancelled_ = true;
}

std::vector<ScheduledWindow*> WindowSchedule::in_time_order() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<ScheduledWindow*> ordered;
    for (const auto& window : windows_) ordered.push_back(window.get());
    std::stable_sort(ordered.begin(), ordered.end(),
                     [](const ScheduledWindow* x, const ScheduledWindow* y) { return x->begin < y->begin; });
    return ordered;
}

} // namespace usdksl
