#include "aabb_tree.hpp"

#include "usdksl/constants.hpp"

#include <utility>

namespace usdksl {

AabbTree::AabbTree(const Scene& scene, int32_t mesh, double t_build) : scene_(scene), mesh_(mesh) {
    const MeshAnimation& m = scene.meshes[mesh];
    std::vector<Vec3> centroids(m.triangles.size());
    for (size_t i = 0; i < m.triangles.size(); ++i) {
        const std::array<Vec3, 3> p = scene.triangle_at(mesh, static_cast<int32_t>(i), t_build);
        centroids[i] = (p[0] + p[1] + p[2]) / 3.0;
    }
    topology_ = build_bvh_topology(centroids);
    lower_.resize(static_cast<size_t>(topology_.node_count()));
    upper_.resize(static_cast<size_t>(topology_.node_count()));
}

void AabbTree::refit(double t0, double t1, double padding) {
    const Flightplans& plans = scene_.plans[mesh_];
    const std::vector<Triangle>& triangles = scene_.meshes[mesh_].triangles;
    // Children come after their parent, so a reverse sweep is bottom-up.
    for (int32_t node = topology_.node_count() - 1; node >= 0; --node) {
        if (topology_.is_leaf(node)) {
            const Triangle& tri = triangles[topology_.triangle[node]];
            Vec3 lo = plans.position(tri[0], t0), hi = lo;
            for (int corner = 0; corner < 3; ++corner) {
                for (double t : {t0, t1}) {
                    const Vec3 p = plans.position(tri[corner], t);
                    lo = lo.cwiseMin(p);
                    hi = hi.cwiseMax(p);
                }
            }
            // Rounding padding scales with this triangle's own coordinates only.
            const double magnitude = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
            const Vec3 pad = Vec3::Constant(padding + BOX_PADDING * magnitude);
            lower_[node] = lo - pad;
            upper_[node] = hi + pad;
        } else {
            const int32_t l = topology_.left[node], r = topology_.right[node];
            lower_[node] = lower_[l].cwiseMin(lower_[r]);
            upper_[node] = upper_[l].cwiseMax(upper_[r]);
        }
    }
}

void for_each_overlapping_leaf_pair(const AabbTree& a, const AabbTree& b, bool self, int64_t* bv_tests,
                                    const std::function<void(int32_t, int32_t)>& visit) {
    const BvhTopology& ta = a.topology();
    const BvhTopology& tb = b.topology();
    if (ta.node_count() == 0 || tb.node_count() == 0) return;
    std::vector<std::pair<int32_t, int32_t>> stack{{0, 0}};
    while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        const bool same = self && x == y;
        if (same) {
            if (!ta.is_leaf(x)) {
                const int32_t l = ta.left[x], r = ta.right[x];
                stack.push_back({l, l});
                stack.push_back({l, r});
                stack.push_back({r, r});
            }
            continue;
        }
        ++*bv_tests;
        if ((a.lower(x).array() > b.upper(y).array()).any() || (b.lower(y).array() > a.upper(x).array()).any()) {
            continue;
        }
        const bool leaf_x = ta.is_leaf(x), leaf_y = tb.is_leaf(y);
        if (leaf_x && leaf_y) {
            visit(ta.triangle[x], tb.triangle[y]);
        } else if (leaf_y || (!leaf_x && ta.depth[x] <= tb.depth[y])) {
            stack.push_back({ta.left[x], y});
            stack.push_back({ta.right[x], y});
        } else {
            stack.push_back({x, tb.left[y]});
            stack.push_back({x, tb.right[y]});
        }
    }
}

} // namespace usdksl
