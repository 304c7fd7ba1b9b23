#pragma once
/// @file contact.hpp
/// @brief A first contact between two triangles.

#include "usdksl/narrow_phase/feature.hpp"
#include "usdksl/narrow_phase/triangle_pair_contact.hpp"

#include <cstdint>
#include <tuple>

namespace usdksl {

/// @brief A candidate's confirming answer, worked out where the candidate was
///        found (see TrianglePairTester::carry_confirmations): the finer
///        triangle-pair test of the raw step [begin, end) (time codes), as
///        the raw-sample confirmation would compute it.
struct CarriedConfirmation {
    double begin = 0.0;
    double end = 0.0;
    TrianglePairContact answer;
    bool known = false;
};

/// @brief First contact of one triangle pair. For self contacts mesh_a == mesh_b
///        and tri_a < tri_b; for inter contacts mesh_a < mesh_b.
struct Contact {
    /// @brief Time of first contact in time codes (conservative: never late by
    ///        more than nothing, early by at most the CCD tolerance of its step).
    double time = 0.0;
    int32_t mesh_a = 0;
    int32_t tri_a = 0;
    int32_t mesh_b = 0;
    int32_t tri_b = 0;
    ContactFeature feature = ContactFeature::VertexFace;
    /// @brief True when the narrow phase hit its iteration cap (counted as contact).
    bool undecided = false;
    /// @brief Internal to candidates: their confirming answer on their step, when known.
    CarriedConfirmation carried;
};

/// @brief Total order used for every contact list: time, then ids.
inline bool contact_before(const Contact& x, const Contact& y) {
    return std::tie(x.time, x.mesh_a, x.tri_a, x.mesh_b, x.tri_b) <
           std::tie(y.time, y.mesh_a, y.tri_a, y.mesh_b, y.tri_b);
}

} // namespace usdksl
