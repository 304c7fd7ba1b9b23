#pragma once
/// @file window_findings.hpp
/// @brief Triangle pairs that the time windows of one check have found,
///        passed between windows checked at the same time, so that a window
///        does not go on testing a pair an earlier window has found already.

#include <cstdint>
#include <mutex>
#include <vector>

namespace usdksl {

/// @brief The found triangle pairs (TrianglePairTester keys) of every window
///        of one check, each window's in the order it published them.
///
/// A window that begins later need not test a pair that a window beginning
/// earlier found: the earlier window's candidate, confirmed on the raw
/// samples up to the end of the whole check, gives the pair's first contact
/// at or after that earlier begin, which no later window can undercut. Which
/// pairs a window skips depends on how far the others got, so only the work
/// depends on timing, never the answer. Thread-safe; windows publish and
/// collect once per step, so one lock is enough.
class WindowFindings {
public:
    /// @brief Registers a window that begins at `begin` (time code) and
    ///        returns its slot.
    int32_t join(double begin);

    /// @brief Appends `keys` to what the window in `slot` has found.
    void publish(int32_t slot, const std::vector<uint64_t>& keys);

    /// @brief Calls `take(key)` for every key published, since the last call
    ///        with these `cursors` (one per slot, grown as windows join), by
    ///        a window that begins before the window in `slot`.
    template <typename Take>
    void collect_earlier(int32_t slot, std::vector<size_t>& cursors, Take take) const {
        std::lock_guard<std::mutex> lock(mutex_);
        cursors.resize(keys_.size(), 0);
        for (size_t other = 0; other < keys_.size(); ++other) {
            if (!(begins_[other] < begins_[static_cast<size_t>(slot)])) continue;
            const std::vector<uint64_t>& found = keys_[other];
            for (size_t i = cursors[other]; i < found.size(); ++i) take(found[i]);
            cursors[other] = found.size();
        }
    }

private:
    mutable std::mutex mutex_;
    std::vector<double> begins_;                // per slot, time code
    std::vector<std::vector<uint64_t>> keys_;   // per slot
};

} // namespace usdksl
