/// @file vertex_face_memo.cpp
/// @brief Set-associative memo of vertex-face answers keyed on exact bits.

#include "usdksl/ccd/vertex_face_memo.hpp"

#include "usdksl/ccd/vertex_face_ccd.hpp"

#include <cstring>
#include <vector>

namespace usdksl {
namespace {

constexpr int WAYS = 4;
constexpr int SETS = VERTEX_FACE_MEMO_ENTRIES / WAYS;
static_assert(SETS > 0 && (SETS & (SETS - 1)) == 0, "the set count must be a power of two");

/// Bit patterns of every input the answer depends on: the eight points,
/// t_max and the settings. Equal words mean the same function call (a
/// different zero sign or NaN payload only costs a recomputation).
constexpr int KEY_WORDS = 8 * 3 + 4;
struct Key {
    uint64_t word[KEY_WORDS];
    bool operator==(const Key& other) const { return std::memcmp(word, other.word, sizeof word) == 0; }
};

uint64_t bits_of(double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
}

/// Four independent multiply-xorshift lanes (short dependency chains), folded at the end.
uint64_t hash_of(const Key& key) {
    constexpr uint64_t MULTIPLIER = 0x9E3779B97F4A7C15ull;
    uint64_t lane[4] = {0x243F6A8885A308D3ull, 0x13198A2E03707344ull, 0xA4093822299F31D0ull, 0x082EFA98EC4E6C89ull};
    for (int i = 0; i < KEY_WORDS; ++i) {
        uint64_t& h = lane[i & 3];
        h = (h ^ key.word[i]) * MULTIPLIER;
        h ^= h >> 29;
    }
    uint64_t h = lane[0];
    for (int i = 1; i < 4; ++i) h = (h ^ (lane[i] + (h >> 31))) * MULTIPLIER;
    return h ^ (h >> 32);
}

/// One set's bookkeeping in one cache line: the hashes and last-use stamps
/// of its ways (stamp 0: empty).
struct SetHeader {
    uint64_t hash[WAYS];
    uint64_t stamp[WAYS];
};

struct Entry {
    Key key;
    CCDResult result;
};

} // namespace

struct VertexFaceMemo::Storage {
    std::vector<SetHeader> headers = std::vector<SetHeader>(SETS, SetHeader{});
    std::vector<Entry> entries = std::vector<Entry>(static_cast<size_t>(SETS) * WAYS);
    uint64_t clock = 0;
};

VertexFaceMemo::VertexFaceMemo() = default;
VertexFaceMemo::~VertexFaceMemo() = default;

struct VertexFaceMemo::Slot {
    Key key;
    uint64_t hash;
    SetHeader* header;
    Entry* entry;
    int way;
    bool found;
};

VertexFaceMemo::Slot VertexFaceMemo::slot_for(const Vec3* const points[8], const CCDSettings& settings,
                                              double t_max) {
    if (!storage_) storage_ = std::make_unique<Storage>();
    Storage& storage = *storage_;
    Slot slot;
    int n = 0;
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) slot.key.word[n++] = bits_of((*points[i])[k]);
    slot.key.word[n++] = bits_of(t_max);
    slot.key.word[n++] = bits_of(settings.tolerance);
    slot.key.word[n++] = bits_of(settings.thickness);
    slot.key.word[n++] = static_cast<uint64_t>(settings.max_iterations);

    slot.hash = hash_of(slot.key);
    const size_t set = static_cast<size_t>(slot.hash) & (SETS - 1);
    slot.header = &storage.headers[set];
    Entry* ways = &storage.entries[set * WAYS];
    const uint64_t now = ++storage.clock;
    int oldest = 0;
    for (int w = 0; w < WAYS; ++w) {
        if (slot.header->stamp[w] != 0 && slot.header->hash[w] == slot.hash && ways[w].key == slot.key) {
            slot.header->stamp[w] = now;
            slot.way = w;
            slot.entry = &ways[w];
            slot.found = true;
            return slot;
        }
        if (slot.header->stamp[w] < slot.header->stamp[oldest]) oldest = w;
    }
    slot.way = oldest;
    slot.entry = &ways[oldest];
    slot.found = false;
    return slot;
}

void VertexFaceMemo::fill(Slot& slot, const CCDResult& result) {
    slot.header->hash[slot.way] = slot.hash;
    slot.header->stamp[slot.way] = storage_->clock;
    slot.entry->key = slot.key;
    slot.entry->result = result;
}

CCDResult VertexFaceMemo::vertex_face_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                          const CCDSettings& settings, double t_max, bool& reused,
                                          FinerSearchFork* fork) {
    const Vec3* const points[8] = {&p_t0, &a_t0, &b_t0, &c_t0, &p_t1, &a_t1, &b_t1, &c_t1};
    Slot slot = slot_for(points, settings, t_max);
    reused = slot.found;
    if (slot.found) return slot.entry->result;
    const CCDResult result =
        fork ? usdksl::vertex_face_ccd(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, t_max, *fork)
             : usdksl::vertex_face_ccd(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, t_max);
    fill(slot, result);
    return result;
}

const CCDResult* VertexFaceMemo::find(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                      const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                      const CCDSettings& settings, double t_max) {
    const Vec3* const points[8] = {&p_t0, &a_t0, &b_t0, &c_t0, &p_t1, &a_t1, &b_t1, &c_t1};
    const Slot slot = slot_for(points, settings, t_max);
    return slot.found ? &slot.entry->result : nullptr;
}

void VertexFaceMemo::keep(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0, const Vec3& p_t1,
                          const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1, const CCDSettings& settings,
                          double t_max, const CCDResult& result) {
    const Vec3* const points[8] = {&p_t0, &a_t0, &b_t0, &c_t0, &p_t1, &a_t1, &b_t1, &c_t1};
    Slot slot = slot_for(points, settings, t_max);
    fill(slot, result);
}

} // namespace usdksl
