#pragma once
/// @file chunked_vector.hpp
/// @brief A vector that grows by fixed-size chunks: no slack beyond one chunk
///        and no copy on growth, so a separation list of millions of entries
///        never holds its old and new arrays at once (a std::vector doubling
///        peaks at three times its contents while it copies).

#include "usdksl/huge_page_allocator.hpp"

#include <cstddef>
#include <new>
#include <type_traits>
#include <vector>

namespace usdksl {

/// @brief Bytes of one chunk: a whole number of huge pages, so that each
///        chunk of a large front lies on huge pages it fills.
constexpr size_t CHUNKED_VECTOR_CHUNK_BYTES = HUGE_PAGE_MIN_BLOCK_BYTES;

/// @brief Elements indexed 0..size()-1 in chunks of CHUNKED_VECTOR_CHUNK_BYTES;
///        references stay valid while it grows. An element is constructed
///        when appended (a chunk's untouched tail costs no memory).
template <typename T>
class ChunkedVector {
    // Chunks are freed without running element destructors.
    static_assert(std::is_trivially_destructible_v<T>, "ChunkedVector holds trivially destructible elements");

public:
    static constexpr size_t kChunkSize = CHUNKED_VECTOR_CHUNK_BYTES / sizeof(T);

    ChunkedVector() = default;
    ChunkedVector(const ChunkedVector&) = delete;
    ChunkedVector& operator=(const ChunkedVector&) = delete;
    ~ChunkedVector() {
        for (T* chunk : chunks_) free_maybe_huge(chunk, kChunkSize * sizeof(T));
    }

    size_t size() const { return size_; }

    T& operator[](size_t i) { return chunks_[i / kChunkSize][i % kChunkSize]; }
    const T& operator[](size_t i) const { return chunks_[i / kChunkSize][i % kChunkSize]; }

    /// @brief Appends a value-initialized element and returns it.
    T& emplace_back() {
        if (size_ == chunks_.size() * kChunkSize) {
            chunks_.push_back(static_cast<T*>(allocate_maybe_huge(kChunkSize * sizeof(T))));
        }
        T* slot = &chunks_[size_ / kChunkSize][size_ % kChunkSize];
        ++size_;
        return *new (slot) T{};
    }

private:
    std::vector<T*> chunks_;
    size_t size_ = 0;
};

} // namespace usdksl
