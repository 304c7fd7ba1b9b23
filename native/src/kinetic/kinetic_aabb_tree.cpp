#include "usdksl/kinetic/kinetic_aabb_tree.hpp"

#include "usdksl/constants.hpp"
#include "usdksl/flightplan/crossing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {

KineticAabbTree::KineticAabbTree(const Flightplans& plans, const std::vector<Triangle>& triangles,
                                 double t_build)
    : plans_(&plans), triangles_(&triangles) {
    std::vector<Vec3> centroids(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& tri = triangles[i];
        centroids[i] = (plans.position(tri[0], t_build) + plans.position(tri[1], t_build) +
                        plans.position(tri[2], t_build)) / 3.0;
    }
    topology_ = build_bvh_topology(centroids);
    const int32_t node_count = topology_.node_count();
    extreme_.assign(static_cast<size_t>(node_count) * BOX_SLOTS, -1);
    // Per node: the largest vertex magnitude under it, and the levels below it.
    std::vector<double> magnitude(static_cast<size_t>(node_count), 0.0);
    std::vector<int32_t> height(static_cast<size_t>(node_count), 0);
    // Children come after their parent, so a reverse sweep is bottom-up.
    for (int32_t node = node_count - 1; node >= 0; --node) {
        for (int slot = 0; slot < BOX_SLOTS; ++slot) repick(node, slot, t_build);
        if (topology_.is_leaf(node)) {
            for (int32_t v : triangles[topology_.triangle[node]]) {
                magnitude[node] = std::max(magnitude[node], plans.vertex_magnitude(v));
            }
        } else {
            const int32_t l = topology_.left[node], r = topology_.right[node];
            magnitude[node] = std::max(magnitude[l], magnitude[r]);
            height[node] = 1 + std::max(height[l], height[r]);
        }
    }
    // A stored side lags the true extreme by at most one certificate tolerance
    // per level (each bounded by this node's magnitude); two levels spare.
    box_margin_.resize(static_cast<size_t>(node_count));
    for (int32_t node = 0; node < node_count; ++node) {
        box_margin_[node] =
            magnitude[node] * (KINETIC_ORDER_TOLERANCE * (height[node] + 2) + BOX_PADDING);
    }
}

int KineticAabbTree::candidates(int32_t node, int slot, std::array<int32_t, 3>& out) const {
    if (topology_.is_leaf(node)) {
        const Triangle& tri = (*triangles_)[topology_.triangle[node]];
        out = {tri[0], tri[1], tri[2]};
        return 3;
    }
    out[0] = extreme(topology_.left[node], slot);
    out[1] = extreme(topology_.right[node], slot);
    return 2;
}

bool KineticAabbTree::better(int32_t candidate, int32_t incumbent, int slot, double t) const {
    if (candidate == incumbent) return false;
    const int axis = slot_axis(slot);
    const double sign = slot_is_max(slot) ? 1.0 : -1.0;
    const double c = sign * plans_->coord(candidate, axis, t);
    const double i = sign * plans_->coord(incumbent, axis, t);
    if (c != i) return c > i;
    // Equal now: whoever moves outward over the next piece wins, then the lower index.
    const double ahead = std::min(plans_->next_breakpoint(candidate, t), plans_->next_breakpoint(incumbent, t));
    if (std::isfinite(ahead)) {
        const double ca = sign * plans_->coord(candidate, axis, ahead);
        const double ia = sign * plans_->coord(incumbent, axis, ahead);
        if (ca != ia) return ca > ia;
    }
    return candidate < incumbent;
}

bool KineticAabbTree::repick(int32_t node, int slot, double t) {
    std::array<int32_t, 3> cand{};
    const int count = candidates(node, slot, cand);
    int32_t best = cand[0];
    for (int i = 1; i < count; ++i) {
        if (better(cand[i], best, slot, t)) best = cand[i];
    }
    int32_t& stored = extreme_[node * BOX_SLOTS + slot];
    const bool changed = stored != best;
    stored = best;
    return changed;
}

double KineticAabbTree::certificate_failure(int32_t node, int slot, double t, double t_limit) const {
    std::array<int32_t, 3> cand{};
    const int count = candidates(node, slot, cand);
    const int32_t winner = extreme(node, slot);
    const int axis = slot_axis(slot);
    double failure = std::numeric_limits<double>::infinity();
    for (int i = 0; i < count; ++i) {
        if (cand[i] == winner) continue;
        // Gap that stays >= 0 while the winner leads by at least -order_tolerance.
        const double order_tolerance =
            KINETIC_ORDER_TOLERANCE * std::max(plans_->vertex_magnitude(winner), plans_->vertex_magnitude(cand[i]));
        const AxisGap gap = slot_is_max(slot)
                                ? AxisGap{plans_, winner, plans_, cand[i], axis, order_tolerance}
                                : AxisGap{plans_, cand[i], plans_, winner, axis, order_tolerance};
        const CrossingTime crossing =
            first_gap_change(gap, GapChange::DropsBelowZero, t, std::min(failure, t_limit), KINETIC_SEARCH_PIECES);
        failure = std::min(failure, crossing.time);
    }
    // An event must move time forward, or a tie could fire forever.
    if (failure <= t) failure = std::nextafter(t, std::numeric_limits<double>::infinity());
    return failure;
}

} // namespace usdksl
