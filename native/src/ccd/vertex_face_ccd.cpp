/// @file vertex_face_ccd.cpp
/// @brief Vertex-face CCD as a multilinear root search over (t, u, v).

#include "usdksl/ccd/vertex_face_ccd.hpp"

#include "inclusion_root_finder.hpp"

namespace usdksl {

CCDResult vertex_face_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                          const CCDSettings& settings, double t_max) {
    const MultilinearDistance f{{p_t0, a_t0, b_t0, c_t0}, {p_t1, a_t1, b_t1, c_t1},
                                PrimitivePairKind::VertexFace};
    return find_earliest_root(f, settings, t_max);
}

CCDResult vertex_face_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                          const CCDSettings& settings) {
    return vertex_face_ccd(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, 1.0);
}

CCDResult vertex_face_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                          const CCDSettings& settings, double t_max, FinerSearchFork& fork) {
    const MultilinearDistance f{{p_t0, a_t0, b_t0, c_t0}, {p_t1, a_t1, b_t1, c_t1},
                                PrimitivePairKind::VertexFace};
    return find_earliest_root(f, settings, t_max, &fork);
}

CCDResult vertex_face_ccd_resumed(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                  const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                  const CCDSettings& finer_settings, double t_max, const FinerSearchFork& fork) {
    const MultilinearDistance f{{p_t0, a_t0, b_t0, c_t0}, {p_t1, a_t1, b_t1, c_t1},
                                PrimitivePairKind::VertexFace};
    return resume_finer_search(f, finer_settings, t_max, fork);
}

} // namespace usdksl
