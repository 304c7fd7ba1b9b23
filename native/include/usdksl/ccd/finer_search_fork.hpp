#pragma once
/// @file finer_search_fork.hpp
/// @brief What a root search leaves for the same search at a finer
///        tolerance: the point where the two part.

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief One (t,u,v) box of the root search (t: fraction of the step).
struct ParameterBox {
    double t_lo, t_hi, u_lo, u_hi, v_lo, v_hi;
    int32_t depth;
    /// Set on a box clipped to within tolerance: it answers if its own
    /// corners do not exclude it.
    bool final_check = false;
};

/// @brief Where a root search first splits differently from the same search
///        (same function, thickness, t_max and iteration cap) at the finer
///        tolerance `finer_tolerance`. The tolerances only decide which
///        parameters a box may still split along, so up to that box both
///        searches take the same steps: the finer one can go on from there
///        (resume_finer_search), and a search that never got there gives
///        the finer search's answer itself.
struct FinerSearchFork {
    /// @brief Input: the finer tolerance (interval fraction).
    double finer_tolerance = 0.0;
    /// @brief Output: the searches parted; box, heap and iterations are set.
    bool diverged = false;
    /// @brief The box both searches took when they parted, the boxes still
    ///        queued (heap order) and the boxes examined before it.
    ParameterBox box{};
    std::vector<ParameterBox> heap;
    int64_t iterations = 0;
};

} // namespace usdksl
