/// @file ground_truth_test.cpp
/// @brief Vertex-face and edge-edge CCD miss no contact of the public ground
///        truth (Wang et al. sample queries), read in place from the shared
///        data folder (USDKSL_SHARED_DATA); skipped when it is absent.
///
/// A rational converts to the correctly rounded double when its denominator is
/// a power of two (the integer's conversion rounds once, the division is exact)
/// or when numerator and denominator are both exact doubles (one correctly
/// rounded division); other queries are left to the Python test, which
/// converts every query exactly.

#include "usdksl/ccd/edge_edge_ccd.hpp"
#include "usdksl/ccd/vertex_face_ccd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace usdksl;
namespace fs = std::filesystem;

namespace {

constexpr double kExactDoubleInteger = 9007199254740992.0;  // 2^53

struct Query {
    Vec3 points[8] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                      Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    bool truth = false;
};

/// Parses a decimal integer of at most 37 digits exactly.
bool parse_integer(const std::string& text, __int128& out) {
    const bool negative = !text.empty() && text[0] == '-';
    const std::string digits = negative ? text.substr(1) : text;
    if (digits.empty() || digits.size() > 37) return false;
    out = 0;
    for (char c : digits) {
        if (c < '0' || c > '9') return false;
        out = out * 10 + (c - '0');
    }
    if (negative) out = -out;
    return true;
}

/// The correctly rounded double of numerator / denominator, when this test can
/// compute it (see the file comment).
bool exact_rational(const std::string& numerator, const std::string& denominator, double& out) {
    __int128 num = 0, den = 0;
    if (!parse_integer(numerator, num) || !parse_integer(denominator, den) || den <= 0) return false;
    const bool power_of_two = (den & (den - 1)) == 0;
    const __int128 limit = static_cast<__int128>(kExactDoubleInteger);
    if (!power_of_two && (num > limit || -num > limit || den > limit)) return false;
    out = static_cast<double>(num) / static_cast<double>(den);
    return true;
}

/// Queries of one CSV file whose every coordinate converts exactly; `skipped`
/// counts the others.
std::vector<Query> read_queries(const fs::path& file, int& skipped) {
    std::ifstream in(file);
    std::vector<Query> queries;
    std::string line;
    Query query;
    int row = 0;
    bool exact = true;
    while (std::getline(in, line)) {
        std::stringstream fields(line);
        std::string cell[7];
        for (auto& c : cell) std::getline(fields, c, ',');
        for (int axis = 0; axis < 3; ++axis) {
            double value = 0.0;
            if (!exact_rational(cell[2 * axis], cell[2 * axis + 1], value)) {
                exact = false;
                continue;
            }
            query.points[row][axis] = value;
        }
        query.truth = query.truth || cell[6] == "1";
        if (++row == 8) {
            if (exact) queries.push_back(query);
            else ++skipped;
            query = Query{};
            row = 0;
            exact = true;
        }
    }
    return queries;
}

fs::path shared_data() {
    const char* env = std::getenv("USDKSL_SHARED_DATA");
    return env ? fs::path(env) : fs::path();
}

void check_kind(const std::string& kind) {
    const fs::path root = shared_data() / "sample-queries";
    if (!fs::exists(root)) GTEST_SKIP() << "no shared ground truth at " << root << " (set USDKSL_SHARED_DATA)";
    int total = 0, positives = 0, skipped = 0, misses = 0;
    CCDSettings settings;
    settings.tolerance = 1e-6;
    for (const auto& scene : fs::directory_iterator(root)) {
        const fs::path folder = scene.path() / kind;
        if (!fs::is_directory(folder)) continue;
        for (const auto& file : fs::directory_iterator(folder)) {
            if (file.path().extension() != ".csv") continue;
            for (const Query& q : read_queries(file.path(), skipped)) {
                const Vec3* p = q.points;
                const CCDResult r = kind == "vertex-face"
                                        ? vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings)
                                        : edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings);
                ++total;
                if (q.truth) {
                    ++positives;
                    if (!r.hit) ++misses;
                }
                if (r.hit) {
                    ASSERT_GE(r.toi, 0.0);
                    ASSERT_LE(r.toi, 1.0);
                }
            }
        }
    }
    ::testing::Test::RecordProperty("queries", total);
    ::testing::Test::RecordProperty("skipped_queries", skipped);
    EXPECT_EQ(misses, 0) << "false negatives among " << positives << " true contacts";
    EXPECT_GT(total, 1000) << "too few exactly convertible queries (" << skipped << " skipped)";
    EXPECT_GT(positives, 100);
}

} // namespace

TEST(GroundTruth, VertexFaceMissesNoContact) { check_kind("vertex-face"); }
TEST(GroundTruth, EdgeEdgeMissesNoContact) { check_kind("edge-edge"); }

TEST(PlantedContact, VertexFallingThroughAFaceIsFoundNeverLate) {
    // A vertex falls from z = 1 to z = -1 through a triangle at z = 0: contact at t = 0.5 exactly.
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    CCDSettings settings;
    for (double tolerance : {1e-2, 1e-6, 1e-9}) {
        settings.tolerance = tolerance;
        const CCDResult r = vertex_face_ccd(Vec3(0.25, 0.25, 1), a, b, c, Vec3(0.25, 0.25, -1), a, b, c, settings);
        ASSERT_TRUE(r.hit);
        EXPECT_LE(r.toi, 0.5);
        EXPECT_GE(r.toi, 0.5 - tolerance);
    }
}

TEST(PlantedContact, EdgesPassingAtADistanceMissWithoutThicknessAndHitWithIt) {
    // Edge a along x at z = 0; edge b along y moving down from z = 1 to z = 0.2 (never touching).
    CCDSettings settings;
    const Vec3 a0(-1, 0, 0), a1(1, 0, 0);
    const CCDResult miss = edge_edge_ccd(a0, a1, Vec3(0, -1, 1), Vec3(0, 1, 1), a0, a1, Vec3(0, -1, 0.2),
                                         Vec3(0, 1, 0.2), settings);
    EXPECT_FALSE(miss.hit);
    settings.thickness = 0.25;  // within reach at the end: z gap 0.2
    const CCDResult hit = edge_edge_ccd(a0, a1, Vec3(0, -1, 1), Vec3(0, 1, 1), a0, a1, Vec3(0, -1, 0.2),
                                        Vec3(0, 1, 0.2), settings);
    ASSERT_TRUE(hit.hit);
    EXPECT_LE(hit.toi, (1.0 - 0.25) / 0.8);  // the gap reaches 0.25 at t = 0.9375
    EXPECT_GE(hit.toi, (1.0 - 0.25) / 0.8 - settings.tolerance - 1e-12);
}
