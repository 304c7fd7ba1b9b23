#pragma once
/// @file window_schedule.hpp
/// @brief Hands the time windows of one check to threads as they come free,
///        cutting a running window short where a thread would otherwise idle.

#include "time_windows.hpp"

#include "usdksl/scene/contact.hpp"
#include "usdksl/scene/counters.hpp"
#include "usdksl/scene/window_stop.hpp"

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace usdksl {

/// @brief One time window of a check and what checking it found.
struct ScheduledWindow {
    ScheduledWindow(double window_begin, double window_end)
        : begin(window_begin), end(window_end), stop(window_begin, window_end), progress_time(window_begin) {}

    double begin;  ///< time code
    double end;    ///< planned end (time code); lowered when a thread takes the rest
    WindowStop stop;
    bool started = false;
    bool finished = false;
    std::vector<Contact> candidates;
    Counters counters;
    /// Progress reports (guarded by the progress's own lock): time code reached, contacts so far.
    double progress_time;
    int64_t progress_contacts = 0;
};

/// @brief The windows of one check: first the planned ones, in order; once
///        none is left, a thread that comes free takes the later half of the
///        running window with the most sample steps still ahead, which is told
///        to stop where that half begins (WindowStop). Contacts cluster in time
///        (a cloth twisting ever tighter costs more per step at the end), which
///        planned sizes cannot know; many small planned windows would pay a
///        set-up each (a fresh front). So a check plans one window per thread
///        and cuts only when a thread would idle, and only a window with at
///        least 2 x MIN_SAMPLE_STEPS_PER_CUT sample steps ahead, and as many
///        flightplan steps (WindowCuts::keeping_flightplan_steps): a window
///        pays its set-up whatever its length, and its work follows the
///        steps of the flightplans, not the samples they merged.
class WindowSchedule {
public:
    /// @param cuttable whether the method honours WindowStop; when not,
    ///        windows run to their planned end and are never cut.
    WindowSchedule(const WindowCuts& cuts, const std::vector<TimeWindow>& planned, bool cuttable);

    /// @brief The next window to check (marked started), or nullptr when
    ///        nothing is left to hand out.
    ScheduledWindow* next();
    /// @brief Marks a window checked: its stop.reached is the end it covered.
    void finish(ScheduledWindow& window);
    /// @brief Hands out nothing more (a stop request or a failure).
    void cancel();

    /// @brief Calls `visit(window)` for every window, under the schedule's
    ///        lock (windows may be added meanwhile by other threads).
    template <typename Visit>
    void for_each(Visit visit) const {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& window : windows_) visit(*window);
    }
    /// @brief Every window, ordered by begin; call after every thread is done.
    std::vector<ScheduledWindow*> in_time_order() const;
    /// @brief True while some window handed out is not finished (never
    ///        once cancelled).
    bool any_running() const;
    /// @brief Windows handed out by cutting a running one.
    int64_t cuts_made() const { return cuts_made_; }

private:
    ScheduledWindow* cut_running_window();

    const WindowCuts& cuts_;
    const bool cuttable_;
    mutable std::mutex mutex_;
    std::vector<std::unique_ptr<ScheduledWindow>> windows_;  // the planned ones first, then those cut off
    const size_t planned_;
    size_t next_planned_ = 0;
    bool cancelled_ = false;
    int64_t cuts_made_ = 0;
};

} // namespace usdksl
