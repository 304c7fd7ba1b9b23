#pragma once
/// @file triangle_pair.hpp
/// @brief The narrow phase every method shares: two moving triangles over one
///        linear step, and two triangles at one instant.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/finer_search_fork.hpp"
#include "usdksl/ccd/vertex_face_memo.hpp"
#include "usdksl/narrow_phase/feature.hpp"
#include "usdksl/narrow_phase/triangle_pair_contact.hpp"
#include "usdksl/types.hpp"

#include <array>
#include <cstdint>

namespace usdksl {

/// @brief Vertex ids and positions of one triangle at the start and end of a step.
struct MovingTriangle {
    /// @brief Vertex ids; used only to skip primitive pairs that share a vertex
    ///        (meaningful when both triangles come from the same mesh).
    Triangle ids;
    std::array<Vec3, 3> t0;
    std::array<Vec3, 3> t1;
};

/// @brief What triangle_pair_ccd at one tolerance keeps for
///        finer_triangle_pair_ccd of the same pair on the same step: per
///        primitive query its t_max, its answer and where its search would
///        part from the finer one (FinerSearchFork). Reused from call to
///        call (one per thread).
class FinerReplay {
public:
    /// @brief finer_tolerance: the finer search's tolerance (interval fraction).
    explicit FinerReplay(double finer_tolerance) : finer_tolerance_(finer_tolerance) {}

    struct Record {
        bool asked = false;
        /// False when the answer came from a memo, without a fork.
        bool known = false;
        double t_max = 1.0;
        CCDResult result;
        FinerSearchFork fork;
    };

    /// @brief Forgets the last call; `settings` are the coarser search's.
    void start(const CCDSettings& settings);
    /// @brief The fork for primitive query `index` (see triangle_pair_ccd), asked up to t_max.
    FinerSearchFork* fork_for(int index, double t_max);
    /// @brief Keeps query `index`'s answer; `reused`: it came from a memo.
    void keep(int index, const CCDResult& result, bool reused);
    /// @brief The kept query `index` when it was asked up to the same t_max
    ///        and its fork was recorded for `finer` (same thickness and
    ///        iteration cap, finer_tolerance); else nullptr.
    const Record* record_for(int index, double t_max, const CCDSettings& finer) const;

private:
    double finer_tolerance_;
    CCDSettings settings_;
    std::array<Record, 15> records_;
};

/// @brief Earliest contact over one linear step between triangles A and B:
///        the minimum over their 6 vertex-face and 9 edge-edge primitive pairs.
///        When `same_mesh` is true, primitive pairs that share a vertex id are
///        never tested. Conservative: never misses a contact. With a `memo`,
///        vertex-face queries asked recently with the same inputs are answered
///        from it: the same answer bit for bit, at the cost of a lookup.
///        With a `replay`, what finer_triangle_pair_ccd needs is kept there.
TrianglePairContact triangle_pair_ccd(const MovingTriangle& a, const MovingTriangle& b,
                                      bool same_mesh, const CCDSettings& settings,
                                      VertexFaceMemo* memo = nullptr, FinerReplay* replay = nullptr);

/// @brief Root-search boxes (CCDResult::iterations) a finer vertex-face
///        answer must have cost before finer_triangle_pair_ccd keeps it in
///        its memo: cheaper answers (most misses end on their first box) are
///        recomputed rather than evict costly ones (a speed setting, no
///        effect on answers).
constexpr int64_t FINER_MEMO_MIN_ITERATIONS = 4;

/// @brief triangle_pair_ccd(a, b, same_mesh, finer_settings), bit for bit,
///        for a `replay` that the last triangle_pair_ccd of the same a, b and
///        same_mesh filled at a coarser tolerance (same thickness and
///        iteration cap): a primitive query asked there up to the same t_max
///        takes its answer from the coarser search when the two searches
///        never parted, else goes on from where they parted; the rest are
///        searched afresh. With a `memo` (for finer answers only), a
///        vertex-face query that is not answered by the replay is looked up
///        there first, and a costly answer is kept: the coarser search took
///        a vertex asked again against the same face (once per triangle
///        around the vertex) from its own memo, without a fork, so without
///        this memo the finer search would run afresh for every repeat.
TrianglePairContact finer_triangle_pair_ccd(const MovingTriangle& a, const MovingTriangle& b, bool same_mesh,
                                            const CCDSettings& finer_settings, const FinerReplay& replay,
                                            VertexFaceMemo* memo = nullptr);

/// @brief True when triangles A and B (positions at one instant) touch or
///        intersect (within settings.thickness), considering only primitives
///        that share no vertex id when `same_mesh` is true: vertex-face and
///        edge-edge distances, and edges piercing the other triangle.
bool triangle_pair_intersect_static(const Triangle& ids_a, const std::array<Vec3, 3>& a,
                                    const Triangle& ids_b, const std::array<Vec3, 3>& b,
                                    bool same_mesh, double thickness);

/// @brief True when an edge of triangle A that shares no vertex id with B
///        meets closed triangle B (positions at one instant, exact test): the
///        piercing the static test reports, which no distance between
///        primitive pairs shows.
bool edge_pierces_triangle(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                           const std::array<Vec3, 3>& b);

} // namespace usdksl
