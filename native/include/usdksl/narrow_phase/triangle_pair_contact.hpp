#pragma once
/// @file triangle_pair_contact.hpp
/// @brief What the narrow phase answers for one triangle pair over one step.

#include "usdksl/narrow_phase/feature.hpp"

#include <cstdint>

namespace usdksl {

/// @brief Earliest contact of one triangle pair over one step. Ordered widest
///        first: every candidate contact carries one (CarriedConfirmation).
struct TrianglePairContact {
    /// @brief Fraction of the step in [0,1]; a conservative (early) bound.
    double toi = 1.0;
    /// @brief Number of primitive CCD queries run (counter for benchmarks).
    int32_t queries = 0;
    /// @brief Of those, vertex-face queries answered by the memo (counter for benchmarks).
    int32_t reused_queries = 0;
    bool hit = false;
    ContactFeature feature = ContactFeature::VertexFace;
    /// @brief True when any contributing primitive query hit the iteration cap.
    bool undecided = false;
};

} // namespace usdksl
