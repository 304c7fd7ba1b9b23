#pragma once
/// @file chunked_vector.hpp
/// @brief A vector that grows by fixed-size chunks: no slack beyond one chunk
///        and no copy on growth, so a separation list of millions of entries
///        never holds its old and new arrays at once (a std::vector doubling
///        peaks at three times its contents while it copies).

#include <cstddef>
#include <memory>
#include <vector>

namespace usdksl {

/// @brief Elements indexed 0..size()-1 in chunks of 2^ChunkShift; references
///        stay valid while it grows.
template <typename T, int ChunkShift>
class ChunkedVector {
public:
    static constexpr size_t kChunkSize = size_t{1} << ChunkShift;

    size_t size() const { return size_; }

    T& operator[](size_t i) { return chunks_[i >> ChunkShift][i & (kChunkSize - 1)]; }
    const T& operator[](size_t i) const { return chunks_[i >> ChunkShift][i & (kChunkSize - 1)]; }

    /// @brief Appends a value-initialized element and returns it.
    T& emplace_back() {
        if (size_ == chunks_.size() * kChunkSize) chunks_.push_back(std::make_unique<T[]>(kChunkSize));
        T& added = (*this)[size_++];
        added = T{};
        return added;
    }

private:
    std::vector<std::unique_ptr<T[]>> chunks_;
    size_t size_ = 0;
};

} // namespace usdksl
