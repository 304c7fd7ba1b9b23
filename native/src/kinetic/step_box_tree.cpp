#include "usdksl/kinetic/step_box_tree.hpp"

#include "usdksl/constants.hpp"
#include "usdksl/single_precision.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {

StepBoxTree::StepBoxTree(const Flightplans& plans, const std::vector<Triangle>& triangles, double t_build)
    : plans_(&plans), triangles_(&triangles), fitted_end_(-std::numeric_limits<double>::infinity()) {
    std::vector<Vec3> centroids(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& tri = triangles[i];
        centroids[i] = (plans.position(tri[0], t_build) + plans.position(tri[1], t_build) +
                        plans.position(tri[2], t_build)) / 3.0;
    }
    topology_ = build_bvh_topology(centroids);
    const int32_t node_count = topology_.node_count();
    boxes_.resize(static_cast<size_t>(node_count));
    extent_.assign(static_cast<size_t>(node_count), 0.0);
    std::vector<double> magnitude(static_cast<size_t>(node_count), 0.0);
    std::vector<int32_t> height(static_cast<size_t>(node_count), 0);
    // Children come after their parent, so a reverse sweep is bottom-up.
    for (int32_t node = node_count - 1; node >= 0; --node) {
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
    box_margin_.resize(static_cast<size_t>(node_count));
    for (int32_t node = 0; node < node_count; ++node) {
        box_margin_[node] = magnitude[node] * (STEP_BOX_ROUNDING_PER_LEVEL * (height[node] + 2) + BOX_PADDING);
    }
    still_ = true;
    for (int32_t v = 0; v < plans.vertex_count() && still_; ++v) still_ = plans.key_end(v) - plans.key_begin(v) <= 1;
    begin_points_.resize(static_cast<size_t>(plans.vertex_count()) * 3);
    end_points_.resize(begin_points_.size());
}

void StepBoxTree::index_triangles_under() {
    if (!leaf_first_.empty()) return;
    const int32_t node_count = topology_.node_count();
    end_mean_normal_.assign(static_cast<size_t>(node_count), Vec3::Zero());
    end_mean_normal_fit_.assign(static_cast<size_t>(node_count), -1);
    leaf_first_.assign(static_cast<size_t>(node_count), 0);
    leaf_last_.assign(static_cast<size_t>(node_count), 0);
    leaf_triangles_.clear();
    if (node_count == 0) return;
    // Depth first, left before right: each subtree's leaves come out in one run.
    std::vector<std::pair<int32_t, bool>> stack{{0, false}};
    while (!stack.empty()) {
        const auto [node, closing] = stack.back();
        stack.pop_back();
        if (closing) {
            leaf_last_[node] = static_cast<int32_t>(leaf_triangles_.size());
            continue;
        }
        leaf_first_[node] = static_cast<int32_t>(leaf_triangles_.size());
        if (topology_.is_leaf(node)) {
            leaf_triangles_.push_back(topology_.triangle[node]);
            leaf_last_[node] = static_cast<int32_t>(leaf_triangles_.size());
            continue;
        }
        stack.push_back({node, true});
        stack.push_back({topology_.right[node], false});
        stack.push_back({topology_.left[node], false});
    }
    // Each small node's distinct vertices, found by marking them with the
    // node's id while walking its triangles' corners: once per tree, so
    // heights under a node need not walk each vertex's ~6 corners per step.
    const std::vector<Triangle>& triangles = *triangles_;
    std::vector<int32_t> seen_by(static_cast<size_t>(plans_->vertex_count()), -1);
    vertices_first_.assign(static_cast<size_t>(node_count) + 1, 0);
    node_vertices_.clear();
    for (int32_t node = 0; node < node_count; ++node) {
        vertices_first_[node] = static_cast<int32_t>(node_vertices_.size());
        const int32_t count = leaf_last_[node] - leaf_first_[node];
        if (count > NODE_PLANE_MAX_TRIANGLES) continue;
        if (topology_.is_leaf(node)) {
            // A leaf's list is its triangle, unless the triangle repeats a vertex.
            const Triangle& t = triangles[static_cast<size_t>(topology_.triangle[node])];
            if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) continue;
        }
        const size_t begin = node_vertices_.size();
        for (int32_t i = leaf_first_[node]; i < leaf_last_[node]; ++i) {
            for (int32_t v : triangles[static_cast<size_t>(leaf_triangles_[static_cast<size_t>(i)])]) {
                int32_t& mark = seen_by[static_cast<size_t>(v)];
                if (mark == node) continue;
                mark = node;
                node_vertices_.push_back(v);
            }
        }
        // Ascending: the positions they read lie in memory order.
        std::sort(node_vertices_.begin() + static_cast<std::ptrdiff_t>(begin), node_vertices_.end());
    }
    vertices_first_[static_cast<size_t>(node_count)] = static_cast<int32_t>(node_vertices_.size());
    node_vertices_.shrink_to_fit();
}

const Vec3& StepBoxTree::end_mean_normal(int32_t node) const {
    Vec3& normal = end_mean_normal_[static_cast<size_t>(node)];
    int64_t& fit = end_mean_normal_fit_[static_cast<size_t>(node)];
    if (fit == fits_) return normal;
    const auto [first, last] = triangles_under(node);
    const double* points = end_points();
    const auto at = [&](int32_t v) { return Eigen::Map<const Vec3>(points + 3 * static_cast<size_t>(v)); };
    Vec3 sum = Vec3::Zero();
    for (const int32_t* t = first; t != last; ++t) {
        const Triangle& ids = (*triangles_)[static_cast<size_t>(*t)];
        sum += (at(ids[1]) - at(ids[0])).cross(at(ids[2]) - at(ids[0]));
    }
    const double length = sum.norm();
    normal = length > 0.0 ? Vec3(sum / length) : Vec3::Zero();
    fit = fits_;
    return normal;
}

void StepBoxTree::fit(double t0, double t1) {
    if (still_ && fitted_) return;
    const Flightplans& plans = *plans_;
    const int32_t n = plans.vertex_count();
    if (fitted_ && t0 == fitted_end_) {
        std::swap(begin_points_, end_points_);
    } else {
        for (int32_t v = 0; v < n; ++v) {
            const int64_t k = plans.segment_of(v, t0);
            for (int axis = 0; axis < 3; ++axis) begin_points_[3 * v + axis] = plans.coord_in_segment(v, k, axis, t0);
        }
    }
    for (int32_t v = 0; v < n; ++v) {
        const int64_t k = plans.segment_of(v, t1);
        for (int axis = 0; axis < 3; ++axis) end_points_[3 * v + axis] = plans.coord_in_segment(v, k, axis, t1);
    }
    fitted_ = true;
    fitted_end_ = t1;
    ++fits_;
    const std::vector<Triangle>& triangles = *triangles_;
    for (int32_t node = topology_.node_count() - 1; node >= 0; --node) {
        StepBox& box = boxes_[node];
        if (topology_.is_leaf(node)) {
            const Triangle& tri = triangles[topology_.triangle[node]];
            for (int end = 0; end < 2; ++end) {
                const HugeVector<double>& points = end == 0 ? begin_points_ : end_points_;
                for (int axis = 0; axis < 3; ++axis) {
                    const double x = points[3 * tri[0] + axis], y = points[3 * tri[1] + axis],
                                 z = points[3 * tri[2] + axis];
                    box.lo[end][axis] = std::min({x, y, z});
                    box.hi[end][axis] = std::max({x, y, z});
                }
            }
        } else {
            const StepBox& l = boxes_[topology_.left[node]];
            const StepBox& r = boxes_[topology_.right[node]];
            for (int end = 0; end < 2; ++end) {
                for (int axis = 0; axis < 3; ++axis) {
                    box.lo[end][axis] = std::min(l.lo[end][axis], r.lo[end][axis]);
                    box.hi[end][axis] = std::max(l.hi[end][axis], r.hi[end][axis]);
                }
            }
        }
        extent_[node] = std::max({box.hi[0][0] - box.lo[0][0], box.hi[0][1] - box.lo[0][1],
                                  box.hi[0][2] - box.lo[0][2]});
        // Grown by the rounding margin here, so overlap tests need only the pair's contact distance.
        const double margin = box_margin_[node];
        for (int end = 0; end < 2; ++end) {
            for (int axis = 0; axis < 3; ++axis) {
                box.lo[end][axis] -= margin;
                box.hi[end][axis] += margin;
            }
        }
    }
}

namespace {

/// The shift whose interval along each axis holds [low, high] (scene units),
/// widened for the rounding of the displacements and of single precision.
NodeShift enclosing_shift(const double low[3], const double high[3]) {
    NodeShift shift;
    double radius = 0.0, scale = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        shift.center[axis] = static_cast<float>(0.5 * (low[axis] + high[axis]));
        const double center = shift.center[axis];
        radius = std::max({radius, high[axis] - center, center - low[axis]});
        scale = std::max({scale, std::abs(low[axis]), std::abs(high[axis])});
    }
    radius += NODE_TRAVEL_ROUNDING * scale;
    shift.radius = float_at_least(radius);
    return shift;
}

} // namespace

void StepBoxTree::record_travel(int64_t step, double t0, double t1) {
    if (still_) return;
    const Flightplans& plans = *plans_;
    const int32_t n = plans.vertex_count();
    const int32_t node_count = topology_.node_count();
    if (node_shift_.empty()) {
        node_shift_.assign(static_cast<size_t>(node_count) * NODE_TRAVEL_AHEAD_STEPS, NodeShift{});
        ahead_points_.resize(static_cast<size_t>(n) * 3);
        ahead_moved_.resize(static_cast<size_t>(n) * 3);
        ahead_segment_.resize(static_cast<size_t>(n));
        for (int32_t v = 0; v < n; ++v) ahead_segment_[static_cast<size_t>(v)] = plans.key_begin(v);
    }
    // Its own cursors: the fitted step's lie behind.
    const auto position = [&](int32_t v, double t, double* out) {
        int64_t& k = ahead_segment_[static_cast<size_t>(v)];
        k = plans.advance_segment(v, k, t);
        for (int axis = 0; axis < 3; ++axis) out[axis] = plans.coord_in_segment(v, k, axis, t);
    };
    if (t0 != ahead_end_) {
        for (int32_t v = 0; v < n; ++v) position(v, t0, &ahead_points_[3 * static_cast<size_t>(v)]);
    }
    // Per vertex, its displacement (linear over the step: end minus begin).
    std::vector<double>& moved = ahead_moved_;
    for (int32_t v = 0; v < n; ++v) {
        double at_end[3];
        position(v, t1, at_end);
        double* at_begin = &ahead_points_[3 * static_cast<size_t>(v)];
        for (int axis = 0; axis < 3; ++axis) {
            moved[3 * static_cast<size_t>(v) + axis] = at_end[axis] - at_begin[axis];
            at_begin[axis] = at_end[axis];
        }
    }
    ahead_end_ = t1;
    const size_t slot = static_cast<size_t>(step % NODE_TRAVEL_AHEAD_STEPS);
    const auto stored = [&](int32_t node) -> NodeShift& {
        return node_shift_[static_cast<size_t>(node) * NODE_TRAVEL_AHEAD_STEPS + slot];
    };
    // Children come after their parent, so a reverse sweep is bottom-up.
    for (int32_t node = node_count - 1; node >= 0; --node) {
        double low[3], high[3];
        if (topology_.is_leaf(node)) {
            const Triangle& tri = (*triangles_)[topology_.triangle[node]];
            for (int axis = 0; axis < 3; ++axis) {
                const double x = moved[3 * static_cast<size_t>(tri[0]) + axis],
                             y = moved[3 * static_cast<size_t>(tri[1]) + axis],
                             z = moved[3 * static_cast<size_t>(tri[2]) + axis];
                low[axis] = std::min({x, y, z});
                high[axis] = std::max({x, y, z});
            }
        } else {
            const NodeShift& l = stored(topology_.left[node]);
            const NodeShift& r = stored(topology_.right[node]);
            for (int axis = 0; axis < 3; ++axis) {
                low[axis] = std::min(static_cast<double>(l.center[axis]) - l.radius,
                                     static_cast<double>(r.center[axis]) - r.radius);
                high[axis] = std::max(static_cast<double>(l.center[axis]) + l.radius,
                                      static_cast<double>(r.center[axis]) + r.radius);
            }
        }
        stored(node) = enclosing_shift(low, high);
    }
}

} // namespace usdksl
