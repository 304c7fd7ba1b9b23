#include "usdksl/broad_phase/bvh_topology.hpp"

#include <algorithm>
#include <numeric>

namespace usdksl {
namespace {

struct Builder {
    const std::vector<Vec3>& centroids;
    BvhTopology& tree;
    std::vector<int32_t> order;

    int32_t add_node(int32_t parent, int32_t depth) {
        tree.left.push_back(-1);
        tree.right.push_back(-1);
        tree.parent.push_back(parent);
        tree.depth.push_back(depth);
        tree.triangle.push_back(-1);
        tree.max_depth = std::max(tree.max_depth, depth);
        return tree.node_count() - 1;
    }

    // Iterative to stay safe on very unbalanced inputs.
    void build() {
        struct Task { int32_t node, begin, end; };
        std::vector<Task> stack{{add_node(-1, 0), 0, static_cast<int32_t>(order.size())}};
        while (!stack.empty()) {
            const Task task = stack.back();
            stack.pop_back();
            if (task.end - task.begin == 1) {
                tree.triangle[task.node] = order[task.begin];
                continue;
            }
            Vec3 lo = centroids[order[task.begin]], hi = lo;
            for (int32_t i = task.begin; i < task.end; ++i) {
                lo = lo.cwiseMin(centroids[order[i]]);
                hi = hi.cwiseMax(centroids[order[i]]);
            }
            int axis = 0;
            (hi - lo).maxCoeff(&axis);
            const int32_t mid = task.begin + (task.end - task.begin) / 2;
            std::nth_element(order.begin() + task.begin, order.begin() + mid, order.begin() + task.end,
                             [&](int32_t a, int32_t b) {
                                 const double ca = centroids[a][axis], cb = centroids[b][axis];
                                 return ca < cb || (ca == cb && a < b);
                             });
            const int32_t depth = tree.depth[task.node] + 1;
            const int32_t left = add_node(task.node, depth);
            const int32_t right = add_node(task.node, depth);
            tree.left[task.node] = left;
            tree.right[task.node] = right;
            stack.push_back({right, mid, task.end});
            stack.push_back({left, task.begin, mid});
        }
    }
};

} // namespace

BvhTopology build_bvh_topology(const std::vector<Vec3>& centroids) {
    BvhTopology tree;
    if (centroids.empty()) return tree;
    Builder builder{centroids, tree, {}};
    builder.order.resize(centroids.size());
    std::iota(builder.order.begin(), builder.order.end(), 0);
    builder.build();
    return tree;
}

} // namespace usdksl
