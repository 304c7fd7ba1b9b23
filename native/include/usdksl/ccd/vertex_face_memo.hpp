#pragma once
/// @file vertex_face_memo.hpp
/// @brief Answers of recent vertex-face queries, kept so that a query asked
///        again with exactly the same inputs costs a lookup.
///
/// The narrow phase asks the same vertex against the same face once for
/// every triangle that contains the vertex (about six on a cloth), on the
/// same step: 57% of the vertex-face queries of a 10k-face generated
/// tablecloth, 44% at 100k faces. vertex_face_ccd is a pure function of its
/// eight points, its settings and t_max (the root search's first box is
/// [0, t_max], so t_max changes the subdivision and the last bits of the
/// answer), so the memo is keyed on the bit patterns of all of them and
/// gives back exactly what the query would compute: answers never depend on
/// what the memo holds. Edge-edge queries are not kept: neighbouring
/// triangles list a shared edge in opposite directions, and the search is
/// not symmetric under that, so their repeats are never bit-identical.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/finer_search_fork.hpp"
#include "usdksl/types.hpp"

#include <cstdint>
#include <memory>

namespace usdksl {

/// @brief Number of answers one memo keeps (4-way set associative, least
///        recently used out), about 1.1 MB. A tablecloth's repeats come close
///        together in the order the kinetic separation lists ask them: 4096
///        answers catch 89% of the repeats an unbounded memo catches on the
///        10k-face tablecloth (93% of their root-search iterations), 81% at
///        100k faces (78%); 16384 would add 1 to 3 points.
constexpr int32_t VERTEX_FACE_MEMO_ENTRIES = 4096;

/// @brief A bounded memo of vertex_face_ccd answers. Not thread-safe: one per
///        thread (each TrianglePairTester owns one). Storage is allocated on
///        first use.
class VertexFaceMemo {
public:
    VertexFaceMemo();
    ~VertexFaceMemo();
    VertexFaceMemo(const VertexFaceMemo&) = delete;
    VertexFaceMemo& operator=(const VertexFaceMemo&) = delete;

    /// @brief vertex_face_ccd(p_t0, ..., c_t1, settings, t_max), from the
    ///        memo when these exact inputs were asked recently (then
    ///        `reused` is set true and `fork` left as it is), else computed
    ///        (filling `fork` when given) and kept.
    CCDResult vertex_face_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                              const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                              const CCDSettings& settings, double t_max, bool& reused,
                              FinerSearchFork* fork = nullptr);

    /// @brief The kept answer of vertex_face_ccd(p_t0, ..., c_t1, settings,
    ///        t_max) when these exact inputs were kept recently, else nullptr.
    ///        The pointer is valid until the next call on this memo.
    const CCDResult* find(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                          const CCDSettings& settings, double t_max);

    /// @brief Keeps `result` as the answer of vertex_face_ccd(p_t0, ...,
    ///        c_t1, settings, t_max); the caller vouches that it is exactly
    ///        that answer (however it was worked out).
    void keep(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0, const Vec3& p_t1,
              const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1, const CCDSettings& settings, double t_max,
              const CCDResult& result);

private:
    struct Storage;
    struct Slot;
    /// The slot of these inputs: the way that holds them (found) or the
    /// least recently used way of their set (to be filled).
    Slot slot_for(const Vec3* const points[8], const CCDSettings& settings, double t_max);
    /// Stores `result` in `slot` as its most recently used way.
    void fill(Slot& slot, const CCDResult& result);
    std::unique_ptr<Storage> storage_;
};

} // namespace usdksl
