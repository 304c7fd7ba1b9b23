#include "usdksl/scene/window_findings.hpp"

namespace usdksl {

int32_t WindowFindings::join(double begin) {
    std::lock_guard<std::mutex> lock(mutex_);
    begins_.push_back(begin);
    keys_.emplace_back();
    return static_cast<int32_t>(begins_.size()) - 1;
}

void WindowFindings::publish(int32_t slot, const std::vector<uint64_t>& keys) {
    if (keys.empty()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<uint64_t>& found = keys_[static_cast<size_t>(slot)];
    found.insert(found.end(), keys.begin(), keys.end());
}

} // namespace usdksl
