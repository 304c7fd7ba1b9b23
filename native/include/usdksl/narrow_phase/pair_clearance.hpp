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

/// @brief How far (in multiples of the contact distance, Euclidean) the narrow
///        phase may report a contact, beyond the box-size and rounding slack
///        the other terms cover. One, because it decides Euclidean distance:
///        a per-axis cube would reach sqrt(3) times as far, at its corners.
constexpr double PAIR_CLEARANCE_CONTACT_REACH = 1.0;

/// @brief Rounding allowance relative to the largest absolute coordinate seen.
constexpr double PAIR_CLEARANCE_ROUNDING = 1e-9;

/// @brief How fast the reach grows with the drift, in multiples of the size
///        fraction: a drift d can widen the six vertices' box diagonal by 2 d.
constexpr double PAIR_CLEARANCE_DRIFT_GROWTH = 2.0;

/// @brief How much the six vertices' box diagonal can grow, in multiples of
///        the largest displacement of a vertex relative to the reference
///        vertex: each axis's extent by twice that, so the diagonal by
///        2 sqrt(3), rounded up.
constexpr double PAIR_CLEARANCE_BOX_GROWTH = 3.5;

/// @brief Most steps a pair waits, after a clearance certificate failed at
///        once, before it tries another.
constexpr int32_t CLEARANCE_MAX_BACKOFF_STEPS = 16;

/// @brief Smallest distance (scene units) between the primitive pairs of two
///        triangles that the narrow phase tests: vertex-face and edge-edge,
///        without those sharing a vertex when both are of one mesh. Given
///        `within` (scene units, > 0), it may stop at the first pair it
///        finds no farther than that and return that pair's distance: the
///        answer is then <= within whenever the smallest is, and the
///        smallest whenever it is not.
double tested_primitive_distance(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                                 const std::array<Vec3, 3>& b, bool same_mesh, double within = 0.0);

/// @brief Widest gap (scene units) between the projections of two triangles
///        on an axis across one of their edges in its triangle's plane: a
///        lower bound of the distance between any point of one and any
///        point of the other (which parts triangles of one flat sheet); -inf
///        when both are degenerate.
double in_plane_gap(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

/// @brief True when two triangles that move linearly over a step (corners
///        a0, b0 at its begin, a1, b1 at its end) stay more than `reach`
///        (scene units) apart throughout it, as seen along one axis: either
///        triangle's normal at either end, or an axis across one of its
///        edges in its plane at the begin. Along a unit axis, every point of
///        a moving triangle projects between the least and the most of its
///        corners' projections at the two ends.
bool swept_apart(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                 const std::array<Vec3, 3>& b1, double reach);

/// @brief Fraction of the pair's size a certified gap must exceed beyond the
///        contact reach, for a CCD tolerance (interval fraction).
double clearance_size_fraction(double tolerance);

/// @brief Distance (scene units) a tested primitive pair must stay beyond for
///        a clearance certificate to hold: the contact reach, the size margin
///        of a pair whose box diagonal was `diameter` at the start and has
///        since drifted by `drift`, and the rounding of coordinates up to
///        `magnitude` (all scene units).
double clearance_reach(double contact_distance, double size_fraction, double diameter, double drift,
                       double magnitude);

/// @brief Diagonal (scene units) of the axis-aligned box of six vertices: at
///        least their diameter.
double pair_box_diagonal(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

/// @brief Proves that no primitive pair of two triangles that the narrow phase
///        tests (vertex-face and edge-edge pairs, without those sharing a
///        vertex when both triangles are of one mesh) comes within reach
///        between the certificate's start and a later time. The distance of
///        every such pair at the start bounds it from below later, minus the
///        drift: the largest displacement of A's vertices relative to a
///        reference vertex plus that of B's, since the start (convex
///        combinations move no farther than their corners; any reference
///        moving with both cancels out of their difference). The reference
///        is a vertex the triangles share when they share one (it then
///        drifts from neither), else A's first. Positions are piecewise
///        linear between breakpoints, so the drift's maximum over a step is
///        at one of its ends.
///
///        Triangles that share no vertex also get a separating plane, the
///        plane of either triangle that leaves the wider gap: while every
///        vertex of B stays on its side by more than the reach, no point of B
///        comes within reach of A, however far the two slide along the plane
///        (cards on a pile, cloth on a body). Along a fixed direction the gap
///        is the smallest of B's heights minus the largest of A's, concave
///        across a step, so it too is smallest at a step's ends. The pair is
///        cleared while either proof holds.
class PairClearance {
public:
    /// @brief Starts at the positions of both triangles at one instant.
    ///        `magnitude`: scene units that no coordinate of the six vertices
    ///        exceeds while the certificate is asked (such as the largest
    ///        their flightplans reach), for the rounding allowance.
    void start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
               const std::array<Vec3, 3>& b, bool same_mesh, double contact_distance, double tolerance,
               double magnitude);

    /// @brief Extends the certificate to positions at a later breakpoint (with
    ///        every earlier breakpoint since the start given before); true
    ///        while no tested primitive pair can have come within reach.
    bool holds_at(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

    /// @brief True while the separating plane proof holds (every vertex of B
    ///        beyond the reach on its side of the plane, A on the other): the
    ///        closed triangles then neither touch nor pierce each other.
    bool separated_by_plane() const { return plane_holds_; }

    /// @brief The contact distance (scene units) the certificate was started for.
    double contact_distance() const { return contact_distance_; }

private:
    /// Contact distance plus the narrow phase's margin for the six vertices'
    /// size (their box diagonal at the start, grown by what the drift so far
    /// can add to it) and rounding.
    double plane_reach() const;

    /// Smallest tested primitive distance at the start, measured only when
    /// the plane no longer clears the pair (most pairs the plane clears never
    /// need it); stops early at a pair within `within` (see tested_primitive_distance).
    void measure_distance(double within);

    /// A lower bound (scene units; 0 or less when it proves nothing) of
    /// every tested primitive distance at the start, at a fraction of the
    /// cost: the wider of start's plane gap and in_plane_gap().
    double separating_gap() const;

    Triangle ids_a_{}, ids_b_{};
    bool same_mesh_ = false;
    std::array<Vec3, 6> start_;           // A's then B's vertices at the start
    int reference_ = 0;                   // A's vertex that displacements are measured against
    bool distance_known_ = false;
    bool bound_known_ = false;            // distance_ holds separating_gap() until the distance is known
    double distance_ = 0.0;               // smallest tested primitive distance at the start (or a lower bound)
    double start_plane_gap_ = 0.0;        // widest plane gap at the start (-inf without a plane)
    double diameter_ = 0.0;               // at least that of the six vertices at the start
    double contact_distance_ = 0.0;       // scene units
    double size_fraction_ = 0.0;
    double magnitude_ = 0.0;              // no coordinate exceeds it
    double drift_ = 0.0;
    Vec3 normal_ = Vec3::Zero();  // unit; B lies above A along it while plane_holds_
    bool plane_holds_ = false;
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
