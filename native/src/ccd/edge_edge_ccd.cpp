/// @file edge_edge_ccd.cpp
/// @brief Edge-edge CCD as a multilinear root search over (t, u, v).

#include "usdksl/ccd/edge_edge_ccd.hpp"

#include "inclusion_root_finder.hpp"

namespace usdksl {

CCDResult edge_edge_ccd(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                        const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                        const Vec3& eb0_t1, const Vec3& eb1_t1, const CCDSettings& settings,
                        double t_max) {
    const MultilinearDistance f{{ea0_t0, ea1_t0, eb0_t0, eb1_t0}, {ea0_t1, ea1_t1, eb0_t1, eb1_t1},
                                PrimitivePairKind::EdgeEdge};
    return find_earliest_root(f, settings, t_max);
}

CCDResult edge_edge_ccd(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                        const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                        const Vec3& eb0_t1, const Vec3& eb1_t1, const CCDSettings& settings) {
    return edge_edge_ccd(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings,
                         1.0);
}

CCDResult edge_edge_ccd(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                        const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                        const Vec3& eb0_t1, const Vec3& eb1_t1, const CCDSettings& settings,
                        double t_max, FinerSearchFork& fork) {
    const MultilinearDistance f{{ea0_t0, ea1_t0, eb0_t0, eb1_t0}, {ea0_t1, ea1_t1, eb0_t1, eb1_t1},
                                PrimitivePairKind::EdgeEdge};
    return find_earliest_root(f, settings, t_max, &fork);
}

CCDResult edge_edge_ccd_resumed(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                const Vec3& eb0_t1, const Vec3& eb1_t1, const CCDSettings& finer_settings,
                                double t_max, const FinerSearchFork& fork) {
    const MultilinearDistance f{{ea0_t0, ea1_t0, eb0_t0, eb1_t0}, {ea0_t1, ea1_t1, eb0_t1, eb1_t1},
                                PrimitivePairKind::EdgeEdge};
    return resume_finer_search(f, finer_settings, t_max, fork);
}

} // namespace usdksl
