/// @file bvh_topology_test.cpp
/// @brief The hierarchy is a proper binary tree with one triangle per leaf.

#include "usdksl/broad_phase/bvh_topology.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace usdksl;

TEST(BvhTopology, EveryTriangleInExactlyOneLeafAndLinksConsistent) {
    for (int count : {1, 2, 3, 17, 256, 1001}) {
        std::mt19937 random(count);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        std::vector<Vec3> centroids;
        for (int i = 0; i < count; ++i) centroids.emplace_back(unit(random), unit(random), 0.0);
        centroids.push_back(centroids.front());  // a duplicate centroid
        const BvhTopology topo = build_bvh_topology(centroids);
        ASSERT_EQ(topo.node_count(), 2 * static_cast<int32_t>(centroids.size()) - 1);
        std::vector<int> seen(centroids.size(), 0);
        for (int32_t node = 0; node < topo.node_count(); ++node) {
            if (topo.is_leaf(node)) {
                ++seen[topo.triangle[node]];
                EXPECT_EQ(topo.left[node], -1);
            } else {
                for (int32_t child : {topo.left[node], topo.right[node]}) {
                    ASSERT_GT(child, node) << "children come after their parent";
                    EXPECT_EQ(topo.parent[child], node);
                    EXPECT_EQ(topo.depth[child], topo.depth[node] + 1);
                    EXPECT_LE(topo.depth[child], topo.max_depth);
                }
            }
        }
        for (int s : seen) EXPECT_EQ(s, 1);
        EXPECT_EQ(topo.parent[0], -1);
    }
}

TEST(BvhTopology, DeterministicForEqualInput) {
    std::vector<Vec3> centroids(64, Vec3::Zero());  // all ties
    const BvhTopology a = build_bvh_topology(centroids), b = build_bvh_topology(centroids);
    EXPECT_EQ(a.left, b.left);
    EXPECT_EQ(a.triangle, b.triangle);
    EXPECT_TRUE(build_bvh_topology({}).node_count() == 0);
}
