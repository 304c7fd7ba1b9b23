#pragma once
/// @file shared_vertex_clearance.hpp
/// @brief A step-by-step certificate that two triangles of one mesh that share
///        a vertex stay out of reach, kept small: a cloth holds several such
///        pairs per triangle, and each carries its certificate for the whole
///        check.

#include "usdksl/types.hpp"

#include <array>
#include <cstdint>

namespace usdksl {

/// @brief Largest box diagonal of points within one distance of a point, in
///        multiples of that distance: 2 sqrt(3), rounded up.
constexpr double SHARED_VERTEX_BOX_DIAGONAL_PER_RADIUS = 3.5;

/// @brief A plane found for a step is proven for the pair within this many
///        times its distance from the shared vertex, so that the next steps
///        ask it at their end alone while the pair stretches no further (a
///        quarter more of the reach's size term, 1/1024 of the pair's size).
constexpr double SHARED_VERTEX_RADIUS_HEADROOM = 1.25;

/// @brief Proves, one step at a time, that no primitive pair of two triangles
///        of one mesh that share a vertex (only pairs sharing no vertex are
///        tested) comes within reach during the step (the reach of
///        PairClearance, PAIR_CLEARANCE_* constants), by one of three proofs,
///        each asked at both ends of the step:
///
///        - the plane proof, for a pair sharing exactly one vertex: a plane
///          through the shared vertex with the other two vertices of A
///          beyond the reach on one side and those of B on the other. Every
///          tested primitive holds a vertex off the plane by that much, with
///          the other primitive on the other side, and heights above a plane
///          through the moving shared vertex are linear over a linear step,
///          so it holds throughout. It turns with the pair: the last plane is
///          tried first, then one fitted to the step;
///        - the centroid proof, for any vertex-sharing pair (two triangles
///          hinged on a shared edge lie on both sides of every plane through
///          the edge): each tested primitive pair apart beyond the reach along
///          the direction between their centroids;
///        - the drift proof of PairClearance, with the shared vertex as the
///          reference (it drifts from neither triangle), from the start or,
///          for a hinged pair, from the step where it last ran out; the
///          distance at the reference is measured only when first needed.
///
///        A cloth turning as a whole keeps the plane and centroid proofs where
///        the drift proof runs out after a few steps; a cloth at rest keeps
///        whichever held last, asked at each step's end alone.
class SharedVertexClearance {
public:
    /// @brief Starts at the positions of both triangles at one instant. The
    ///        triangles must share a vertex. `magnitude`: scene units that no
    ///        absolute coordinate of the six vertices ever exceeds.
    void start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
               const std::array<Vec3, 3>& b, double magnitude);

    /// @brief True when no tested primitive pair comes within reach on the
    ///        linear step from (a0, b0) to (a1, b1): a proof holds at both
    ///        ends of the step, and so between them (heights along a plane
    ///        are linear over the step, the drift is convex). Ask it for
    ///        consecutive steps from the start, each beginning where the last
    ///        ended: a proof that held at the last one's end is asked at this
    ///        one's end alone. `ids_a`, `ids_b`: as given to start();
    ///        `contact_distance`: scene units; `tolerance`: the CCD tolerance
    ///        (fraction of a step).
    bool holds_over(const Triangle& ids_a, const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                    const Triangle& ids_b, const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                    double contact_distance, double tolerance);

    /// @brief holds_over() as far as the step's end alone answers it: the
    ///        proof that held at the last step's end, asked at this one's.
    ///        False says nothing; holds_over() then asks every proof (the
    ///        caller needs the begin positions only then).
    bool holds_at_end(const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b1);

    /// @brief After holds_over() or holds_at_end() answered true: whether a
    ///        plane through the shared vertex held, with everything of either
    ///        triangle but that vertex strictly on its own side at both ends
    ///        of the step, so that the triangles meet nowhere else (no edge of
    ///        one pierces the other, which no tested primitive pair measures).
    bool separated_by_plane() const { return plane_held_; }

    /// @brief After holds_over() or holds_at_end() answered true: how far
    ///        (scene units) the four corners other than the shared vertex may
    ///        move relative to it from the step's end, each by at most this
    ///        much over any number of further steps, with the proof that
    ///        answered still holding at each of their ends and so throughout
    ///        (holds_at_end() would answer true at each). 0 when it cannot
    ///        tell, or after an answer of false.
    double allowance() const { return allowance_; }

private:
    /// The four vertices other than the shared one (A's two, then B's),
    /// relative to it, at one instant, and the square of the largest of their
    /// distances from it (scene units).
    struct FreeCorners {
        Vec3 offset[4];
        double radius_squared;
    };
    FreeCorners free_corners(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) const;
    /// Least height of B's free corners and depth of A's along `normal`.
    static double plane_margin(const Vec3& normal, const FreeCorners& corners);
    /// The reach along a plane, times |normal|, for a pair within `radius` of
    /// its shared vertex, rounded up to single precision as it is kept.
    float plane_least(const Vec3& normal, float radius, double contact_distance, double tolerance) const;
    /// Both ends' margins along `normal` beyond `least` (a plane_least()).
    static bool plane_holds(const Vec3& normal, const FreeCorners& begin, const FreeCorners& end, float least);
    /// A plane normal fitted to the step, in single precision (not unit).
    static Vec3 fitted_normal(const FreeCorners& begin, const FreeCorners& end);
    Vec3 last_normal() const;
    /// Keeps a normal in single precision, proven for `radius` against `least`.
    void keep_plane(const Vec3& normal, float radius, float least);
    static bool primitives_apart(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                 const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                 const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1, double reach);
    double swept_reach(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                       const std::array<Vec3, 3>& b1, double contact_distance, double tolerance) const;
    void keep_drift_allowance(double drift_at_end);
    void keep_plane_allowance(double margin_at_end, double radius_at_end);
    bool drift_proof(const Triangle& ids_a, const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                     const Triangle& ids_b, const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                     double contact_distance, double tolerance);
    /// The drift proof from the pair at a, b.
    void set_drift_reference(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);
    Vec3 offset(int i) const { return Vec3(offsets_[i][0], offsets_[i][1], offsets_[i][2]); }
    double drift(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) const;
    void measure_drift_limit(const Triangle& ids_a, const Triangle& ids_b, double contact_distance, double tolerance);

    /// Positions of A's two vertices after the shared one, then B's, relative
    /// to the shared vertex, at the start, in single precision: the drift
    /// proof's reference, whose distance it measures (any reference serves).
    float offsets_[4][3];
    /// Largest drift (scene units) at which the drift proof holds; negative
    /// when it never does, NaN until measured.
    double drift_limit_ = -1.0;
    /// The last plane that held, not unit (its length is divided out); zero
    /// when there is none.
    float normal_[3] = {0.0f, 0.0f, 0.0f};
    /// The start's magnitude, rounded up to single precision (scene units).
    float magnitude_ = 0.0f;
    /// While plane_held_: the distance from the shared vertex (scene units)
    /// within which the last step's end cleared the reach, rounded up, and
    /// that reach times |normal_|, rounded up: the end cleared at least it.
    float proven_radius_ = 0.0f;
    float plane_least_ = 0.0f;
    /// allowance(), rounded down (scene units).
    float allowance_ = 0.0f;
    int8_t shared_a_ = 0, shared_b_ = 0;  // index of the shared vertex in A and in B
    /// The triangles share exactly one vertex (a shared edge lies in every
    /// plane through its ends: no plane proof).
    bool plane_possible_ = false;
    /// The drift proof held at the end of the last step asked.
    bool drift_held_ = false;
    /// The plane normal_ held at the end of the last step asked.
    bool plane_held_ = false;
    /// holds_at_end() found normal_ short of the reach at this step's end.
    bool last_fell_short_ = false;
    /// The drift proof's reference is the begin of the step asked next.
    bool drift_fresh_ = false;
};

} // namespace usdksl
