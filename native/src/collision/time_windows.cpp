#include "time_windows.hpp"

#include "usdksl/broad_phase/sample_times.hpp"

#include <algorithm>

namespace usdksl {

WindowCuts::WindowCuts(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                       double t_begin, double t_end)
    : scene_(scene), times_(merged_sample_times(scene, mesh_pairs, t_begin, t_end)) {
    std::vector<bool> used(scene.meshes.size(), false);
    for (const auto& [a, b] : mesh_pairs) used[a] = used[b] = true;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (used[m]) used_meshes_.push_back(static_cast<int32_t>(m));
    }
}

std::vector<int64_t> WindowCuts::breakpoints_at(int64_t first, int64_t last) const {
    std::vector<int64_t> count(static_cast<size_t>(last - first + 1), 0);
    for (const int32_t m : used_meshes_) {
        const Flightplans& plans = scene_.plans[static_cast<size_t>(m)];
        for (int32_t v = 0; v < plans.vertex_count(); ++v) {
            // Both lists are sorted: walk v's breakpoints in [times_[first], times_[last]] beside the times.
            int64_t k = plans.peek_segment(v, times_[first]);
            if (plans.key_time(v, k) < times_[first]) ++k;
            int64_t i = first;
            for (; k < plans.key_end(v) && plans.key_time(v, k) <= times_[last]; ++k) {
                while (times_[i] < plans.key_time(v, k)) ++i;
                if (times_[i] == plans.key_time(v, k)) ++count[static_cast<size_t>(i - first)];
            }
        }
    }
    return count;
}

std::pair<int64_t, int64_t> WindowCuts::keeping_flightplan_steps(int64_t first, int64_t last, int64_t steps) const {
    // Breakpoints are counted from each end outward, in chunks that double,
    // as far as the steps reach: a cut near the end of a long window counts
    // only those it needs.
    const auto walk = [&](int64_t from, int64_t direction) {
        int64_t at = from, seen = 0;
        for (int64_t chunk = 4 * steps; seen < steps && at != (direction > 0 ? last : first); chunk *= 2) {
            const int64_t begin = direction > 0 ? at + 1 : std::max(first + 1, at - chunk + 1);
            const int64_t end = direction > 0 ? std::min(last, at + chunk) : at;
            const std::vector<int64_t> breaks = breakpoints_at(begin, end);
            for (; seen < steps && at != (direction > 0 ? end : begin - 1); at += direction) {
                const int64_t i = direction > 0 ? at + 1 : at;
                seen += i == last || breaks[static_cast<size_t>(i - begin)] > 0 ? 1 : 0;
            }
        }
        return at;
    };
    return {walk(first, 1), walk(last, -1)};
}

int64_t WindowCuts::index_at_or_after(double t) const {
    return std::lower_bound(times_.begin(), times_.end(), t) - times_.begin();
}

int64_t WindowCuts::best_cut(int64_t ideal, int64_t reach, int64_t lo, int64_t hi) const {
    const int64_t first = std::max(lo, ideal - reach), last = std::min(hi, ideal + reach);
    if (first > last) return -1;
    const std::vector<int64_t> shared = breakpoints_at(first, last);
    const auto at = [&](int64_t j) { return shared[static_cast<size_t>(j - first)]; };
    const auto distance = [&](int64_t j) { return j > ideal ? j - ideal : ideal - j; };
    int64_t best = -1;
    for (int64_t i = first; i <= last; ++i) {
        if (best < 0 || at(i) > at(best) || (at(i) == at(best) && distance(i) < distance(best))) best = i;
    }
    return best;
}

std::vector<TimeWindow> split_into_windows(const WindowCuts& cuts, int32_t count, WindowSizes sizes) {
    const std::vector<double>& times = cuts.times();
    // times holds t_begin, t_end and every sample strictly between them.
    const int64_t steps = cuts.steps();
    const int64_t inner = steps - 1;
    // Window w (from 0) weighs one share (equal sizes), or count - w shares
    // (falling sizes: the windows are handed out in order, so the thread that
    // takes the last one ends soon after the others). A share spans at least
    // MIN_SAMPLE_STEPS_PER_WINDOW steps, so the total weight may be at most
    // steps / MIN_SAMPLE_STEPS_PER_WINDOW.
    const auto total_weight = [&](int32_t n) {
        return sizes == WindowSizes::Equal ? static_cast<int64_t>(n) : static_cast<int64_t>(n) * (n + 1) / 2;
    };
    while (count > 1 && total_weight(count) * MIN_SAMPLE_STEPS_PER_WINDOW > steps) --count;
    if (count <= 1) return {TimeWindow{times.front(), times.back()}};
    const auto cut_before = [&](int32_t w) {  // ideal sample index where window w begins
        const double weight_before = sizes == WindowSizes::Equal
                                         ? static_cast<double>(w)
                                         : static_cast<double>(w) * count - static_cast<double>(w) * (w - 1) / 2.0;
        return weight_before / static_cast<double>(total_weight(count)) * static_cast<double>(steps);
    };
    std::vector<TimeWindow> windows;
    int64_t previous = 0;
    for (int32_t w = 1; w < count; ++w) {
        const int64_t ideal = static_cast<int64_t>(cut_before(w) + 0.5);
        // Near the ideal cut, a quarter of the smaller neighbouring window either way.
        const int64_t reach = static_cast<int64_t>((cut_before(w + 1) - cut_before(w)) / 4);
        const int64_t best = cuts.best_cut(ideal, reach, previous + 1, inner);
        if (best < 0) continue;
        windows.push_back({times[previous], times[best]});
        previous = best;
    }
    windows.push_back({times[previous], times.back()});
    return windows;
}

} // namespace usdksl
