#include "usdksl/narrow_phase/pair_clearance.hpp"

#include "usdksl/geometry/primitive_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

bool holds_vertex(const Triangle& ids, int32_t v) { return ids[0] == v || ids[1] == v || ids[2] == v; }

bool edges_share_vertex(int32_t e0, int32_t e1, int32_t f0, int32_t f1) {
    return e0 == f0 || e0 == f1 || e1 == f0 || e1 == f1;
}

double largest_coordinate(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    double m = 0.0;
    for (int i = 0; i < 3; ++i) m = std::max({m, a[i].cwiseAbs().maxCoeff(), b[i].cwiseAbs().maxCoeff()});
    return m;
}

} // namespace

void PairClearance::start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                          const std::array<Vec3, 3>& b, bool same_mesh, double contact_distance, double tolerance) {
    double squared = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (!(same_mesh && holds_vertex(ids_b, ids_a[i])))
            squared = std::min(squared, point_triangle_distance_squared(a[i], b[0], b[1], b[2]));
        if (!(same_mesh && holds_vertex(ids_a, ids_b[i])))
            squared = std::min(squared, point_triangle_distance_squared(b[i], a[0], a[1], a[2]));
    }
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3;
            if (same_mesh && edges_share_vertex(ids_a[i], ids_a[i1], ids_b[j], ids_b[j1])) continue;
            squared = std::min(squared, segment_segment_distance_squared(a[i], a[i1], b[j], b[j1]));
        }
    }
    distance_ = std::sqrt(squared);
    diameter_ = 0.0;
    for (int i = 0; i < 6; ++i) {
        const Vec3& p = i < 3 ? a[i] : b[i - 3];
        relative_start_[i] = p - a[0];
        for (int j = 0; j < i; ++j) diameter_ = std::max(diameter_, (p - (j < 3 ? a[j] : b[j - 3])).norm());
    }
    contact_distance_ = contact_distance;
    size_fraction_ = std::max(PAIR_CLEARANCE_SIZE_FRACTION, PAIR_CLEARANCE_TOLERANCE_FACTOR * tolerance);
    magnitude_ = largest_coordinate(a, b);
    drift_ = 0.0;
}

bool PairClearance::holds_at(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    double drift_a = 0.0, drift_b = 0.0;
    for (int i = 1; i < 3; ++i) drift_a = std::max(drift_a, ((a[i] - a[0]) - relative_start_[i]).norm());
    for (int j = 0; j < 3; ++j) drift_b = std::max(drift_b, ((b[j] - a[0]) - relative_start_[3 + j]).norm());
    drift_ = std::max(drift_, drift_a + drift_b);
    magnitude_ = std::max(magnitude_, largest_coordinate(a, b));
    const double reach = contact_distance_ + size_fraction_ * (diameter_ + 2.0 * drift_) +
                         PAIR_CLEARANCE_ROUNDING * magnitude_;
    return distance_ - drift_ > reach;
}

} // namespace usdksl
