#include "usdksl/broad_phase/sample_times.hpp"

#include <algorithm>

namespace usdksl {

std::vector<double> merged_sample_times(const Scene& scene,
                                        const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                        double t_begin, double t_end) {
    std::vector<bool> used(scene.meshes.size(), false);
    for (const auto& [a, b] : mesh_pairs) used[a] = used[b] = true;
    std::vector<double> times{t_begin, t_end};
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (!used[m]) continue;
        for (double t : scene.meshes[m].times) {
            if (t > t_begin && t < t_end) times.push_back(t);
        }
    }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    return times;
}

} // namespace usdksl
