#pragma once
/// @file pair_clearance.hpp
/// @brief A certificate that two triangles stay apart over several flightplan
///        steps, so their narrow phase can skip those steps (kinetic coherence
///        for leaf pairs whose boxes overlap without their triangles touching,
///        such as the neighbours of every cloth triangle).

#include "usdksl/types.hpp"

#include <array>
#include <cstdint>
#include <limits>

namespace usdksl {

/// @brief Fraction of the pair's size (diameter of its six vertices, scene
///        units) that a certified gap must exceed beyond the contact distance:
///        far above what the narrow phase's tolerance lets a miss come within
///        before it reports a contact, so a cleared step is one the narrow
///        phase would have answered "no contact" on.
constexpr double PAIR_CLEARANCE_SIZE_FRACTION = 1.0 / 1024.0;

/// @brief The same margin in multiples of the CCD tolerance (interval
///        fraction) when that is coarser: a search stopping at tolerance tau
///        can report a contact up to about 8 tau times the pair's size away.
constexpr double PAIR_CLEARANCE_TOLERANCE_FACTOR = 64.0;

/// @brief Rounding allowance relative to the largest absolute coordinate seen.
constexpr double PAIR_CLEARANCE_ROUNDING = 1e-9;

/// @brief Proves that no primitive pair of two triangles that the narrow phase
///        tests (vertex-face and edge-edge pairs, without those sharing a
///        vertex when both triangles are of one mesh) comes within reach
///        between the certificate's start and a later time. The distance of
///        every such pair at the start bounds it from below later, minus the
///        drift: the largest displacement of A's vertices relative to A's
///        first vertex plus that of B's, since the start (convex combinations
///        move no farther than their corners). Positions are piecewise linear
///        between breakpoints, so the drift's maximum over a step is at one
///        of its ends.
class PairClearance {
public:
    /// @brief Starts at the positions of both triangles at one instant.
    void start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
               const std::array<Vec3, 3>& b, bool same_mesh, double contact_distance, double tolerance);

    /// @brief Extends the certificate to positions at a later breakpoint (with
    ///        every earlier breakpoint since the start given before); true
    ///        while no tested primitive pair can have come within reach.
    bool holds_at(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

private:
    std::array<Vec3, 6> relative_start_;  // vertices minus A's first vertex at the start
    double distance_ = 0.0;               // smallest tested primitive distance at the start
    double diameter_ = 0.0;               // of the six vertices at the start
    double contact_distance_ = 0.0;
    double size_fraction_ = 0.0;
    double magnitude_ = 0.0;              // largest absolute coordinate seen
    double drift_ = 0.0;
};

/// @brief A clearance certificate with its back-off, carried over consecutive
///        calls that test one pair's consecutive steps.
struct ClearanceRun {
    PairClearance clearance;
    /// @brief Time code (a step boundary) up to which this run followed the
    ///        pair; it may only go on from there (-inf: not started).
    double valid_at = -std::numeric_limits<double>::infinity();
    bool certified = false;  ///< A certificate is running.
    bool fresh = false;      ///< It has not cleared a step yet.
    int32_t wait = 0;        ///< Steps to go before the next certificate.
    int32_t backoff = 1;     ///< Steps to wait after the next one fails at once.
};

} // namespace usdksl
