#pragma once
/// @file window_stop.hpp
/// @brief How another thread cuts a running time window short: it lowers the
///        window's end, and the method publishes how far it got, so the
///        later part can be checked elsewhere at the same time.

#include <atomic>

namespace usdksl {

/// @brief Shared between the thread that checks one time window and the
///        threads that may take over the later part of it.
///
/// A method that honours it (KSL, swept, discrete) looks at `stop_at` before
/// each step after the first and stops before a step that begins at or after
/// it; after each step it stores in `reached` the end of that step. Brute
/// force cannot stop early and stores its range's end when done. Every
/// contact that first touches before `reached` is then among its candidates,
/// so a run over [begin, reached] merged with one over [stop_at, end] (stop_at
/// <= reached, earliest contact per triangle pair) equals a run over
/// [begin, end]. Times are time codes.
struct WindowStop {
    /// @brief The window may end at the first step boundary at or after this
    ///        time code; lowered only, by the thread that takes the rest.
    std::atomic<double> stop_at;
    /// @brief Every step of the window ending at or before this time code is
    ///        done; when the method returns, the end of the window it covered.
    std::atomic<double> reached;

    WindowStop(double begin, double end) : stop_at(end), reached(begin) {}

    /// @brief True when a step beginning at `step_begin` (time codes) lies
    ///        beyond the window's current end.
    bool stops_before(double step_begin) const { return step_begin >= stop_at.load(std::memory_order_acquire); }

    /// @brief Publishes that every step ending at or before `t` is done.
    void reach(double t) { reached.store(t, std::memory_order_release); }
};

} // namespace usdksl
