#pragma once
/// @file expansion_arithmetic.hpp
/// @brief Exact floating-point expansion arithmetic (error-free transforms):
///        a real number held as a sum of non-overlapping doubles, so the sign of
///        a polynomial in double inputs can be decided exactly.
///        Requires round-to-nearest and no FMA contraction (-ffp-contract=off).

#include <array>
#include <cstddef>
#include <stdexcept>

namespace usdksl::expansion {

/// @brief a + b = sum + error exactly (Knuth's branch-free two-sum).
inline void two_sum(double a, double b, double& sum, double& error) {
    sum = a + b;
    const double b_virtual = sum - a;
    const double a_virtual = sum - b_virtual;
    error = (a - a_virtual) + (b - b_virtual);
}

/// @brief Splits a into two halves of 26 significant bits each (Dekker).
inline void split(double a, double& high, double& low) {
    constexpr double splitter = 134217729.0; // 2^27 + 1
    const double c = splitter * a;
    const double big = c - a;
    high = c - big;
    low = a - high;
}

/// @brief a * b = product + error exactly (Dekker's two-product, no FMA).
inline void two_product(double a, double b, double& product, double& error) {
    product = a * b;
    double a_high, a_low, b_high, b_low;
    split(a, a_high, a_low);
    split(b, b_high, b_low);
    const double err1 = product - (a_high * b_high);
    const double err2 = err1 - (a_low * b_high);
    const double err3 = err2 - (a_high * b_low);
    error = (a_low * b_low) - err3;
}

/// @brief Most terms an ExactSum holds: every add() keeps at most one term
///        more, and the largest caller (orient3d: 24 triple products of 4
///        terms each) adds 96 doubles. Fixed, so exact signs never allocate
///        (the root finder takes millions of them on flat cloth).
constexpr std::size_t EXACT_SUM_CAPACITY = 128;

/// @brief An exact sum of doubles kept as a non-overlapping expansion,
///        smallest magnitude first, zeros removed.
class ExactSum {
public:
    /// @brief Adds one double exactly (grow-expansion with zero elimination).
    void add(double value) {
        double q = value;
        std::size_t kept = 0;
        for (std::size_t i = 0; i < count_; ++i) {
            double sum, error;
            two_sum(q, terms_[i], sum, error);
            q = sum;
            if (error != 0.0) terms_[kept++] = error;
        }
        count_ = kept;
        if (q != 0.0) {
            if (count_ == EXACT_SUM_CAPACITY) throw std::length_error("ExactSum: more terms than EXACT_SUM_CAPACITY");
            terms_[count_++] = q;
        }
    }

    /// @brief Adds sign * x * y exactly.
    void add_product(double x, double y, double sign = 1.0) {
        double p, e;
        two_product(x, y, p, e);
        add(sign * p);
        add(sign * e);
    }

    /// @brief Adds sign * x * y * z exactly.
    void add_triple_product(double x, double y, double z, double sign = 1.0) {
        double p, e;
        two_product(x, y, p, e);
        double pp, pe, ep, ee;
        two_product(p, z, pp, pe);
        two_product(e, z, ep, ee);
        add(sign * pp);
        add(sign * pe);
        add(sign * ep);
        add(sign * ee);
    }

    /// @brief Exact sign of the sum: -1, 0 or +1 (the largest term decides,
    ///        because the terms do not overlap).
    int sign() const {
        if (count_ == 0) return 0;
        return terms_[count_ - 1] > 0.0 ? 1 : -1;
    }

private:
    std::array<double, EXACT_SUM_CAPACITY> terms_;  // only the first count_ are set
    std::size_t count_ = 0;
};

} // namespace usdksl::expansion
