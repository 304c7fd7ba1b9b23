#include "shared_breakpoints.hpp"

#include "chord_deviation.hpp"

#include "usdksl/constants.hpp"

#include <algorithm>

namespace usdksl {

int64_t preferred_break(const int64_t* popularity, int64_t anchor, int64_t k) {
    if (popularity == nullptr) return k;
    int64_t most = 0;
    for (int64_t j = anchor + 1; j <= k; ++j) most = std::max(most, popularity[j]);
    const double needed = PREFERRED_BREAK_SHARE * static_cast<double>(most);
    for (int64_t j = k; j > anchor; --j) {
        if (static_cast<double>(popularity[j]) >= needed) return j;
    }
    return k;
}

RunEnd aligned_run_end(const MeshAnimation& mesh, int32_t v, int64_t anchor, int64_t k, const int64_t* popularity) {
    const int64_t j = preferred_break(popularity, anchor, k);
    if (j != k) {
        // A shorter run is not on its own chord just because the longer one
        // was on its chord: its deviation is measured for that run alone.
        const double deviation = run_deviation(mesh, v, anchor, j);
        if (deviation <= FLIGHTPLAN_COLLINEAR_TOLERANCE * run_magnitude(mesh, v, anchor, j)) return {j, deviation};
    }
    return {k, run_deviation(mesh, v, anchor, k)};
}

size_t first_unpreferred_break(const std::vector<int64_t>& kept, int64_t sample_count, const int64_t* popularity) {
    for (size_t i = 1; i < kept.size(); ++i) {
        if (kept[i] + 1 >= sample_count) break;  // the last sample: kept, not a break
        if (preferred_break(popularity, kept[i - 1], kept[i]) != kept[i]) return i;
    }
    return kept.size();
}

} // namespace usdksl
