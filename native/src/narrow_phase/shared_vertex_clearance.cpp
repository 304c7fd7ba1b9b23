#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"

#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <algorithm>
#include <cmath>

namespace usdksl {

void SharedVertexClearance::start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                                  const std::array<Vec3, 3>& b, double contact_distance, double tolerance,
                                  double magnitude) {
    drift_limit_ = -1.0;
    shared_a_ = shared_b_ = -1;
    for (int i = 0; i < 3 && shared_a_ < 0; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (ids_a[i] == ids_b[j]) {
                shared_a_ = static_cast<int8_t>(i);
                shared_b_ = static_cast<int8_t>(j);
                break;
            }
        }
    }
    if (shared_a_ < 0) return;  // not a vertex-sharing pair: the proof never holds
    const Vec3& reference = a[shared_a_];
    offsets_ = {a[(shared_a_ + 1) % 3] - reference, a[(shared_a_ + 2) % 3] - reference,
                b[(shared_b_ + 1) % 3] - reference, b[(shared_b_ + 2) % 3] - reference};
    // PairClearance's drift proof holds while distance - drift > reach(drift),
    // reach growing by the size fraction times the drift growth: solved for the drift.
    const double size_fraction = clearance_size_fraction(tolerance);
    const double reach = clearance_reach(contact_distance, size_fraction, pair_box_diagonal(a, b), 0.0, magnitude);
    const double distance = tested_primitive_distance(ids_a, a, ids_b, b, true);
    drift_limit_ = (distance - reach) / (1.0 + PAIR_CLEARANCE_DRIFT_GROWTH * size_fraction);
}

bool SharedVertexClearance::holds_at(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) const {
    if (!(drift_limit_ > 0.0)) return false;
    // The shared vertex is one point of both triangles: its position in b is the same as in a.
    const Vec3& reference = a[shared_a_];
    const double squared_a = std::max((a[(shared_a_ + 1) % 3] - reference - offsets_[0]).squaredNorm(),
                                      (a[(shared_a_ + 2) % 3] - reference - offsets_[1]).squaredNorm());
    const double squared_b = std::max((b[(shared_b_ + 1) % 3] - reference - offsets_[2]).squaredNorm(),
                                      (b[(shared_b_ + 2) % 3] - reference - offsets_[3]).squaredNorm());
    return std::sqrt(squared_a) + std::sqrt(squared_b) < drift_limit_;
}

} // namespace usdksl
