#pragma once
// The triangular factor of a QR decomposition, the other half of the square-root UKF's algebra
// (van der Merwe & Wan 2001: "qr{[√W (X − x̄)  √Q]}"; Cholesky.h has the rank-1 half).
//
// Every compound matrix the filter factors has the same shape: a dense block D of weighted
// deviations stacked on a diagonal block of noise standard deviations,
//
//     A = [ D        ]   (Dense × K)
//         [ diag(σ)  ]   (K × K)
//
// and only R (AᵀA = RᵀR) is wanted, never Q. Householder reflections on A keep that structure
// useful: before step k the rows of the diagonal block below row Dense + k are still untouched
// (one non-zero each, in a column > k), so reflection k only spans rows k … Dense + k — always
// Dense + 1 rows instead of Dense + K − k. Loops run over contiguous columns with compile-time
// trip counts, so they vectorise; Eigen's HouseholderQR on the same fixed-size matrix works
// through runtime-sized blocks and was a quarter of the filter's time.
// Fixed-size: no heap allocation.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>

namespace armadillo::fusion::qr {

namespace detail {
/// Σ a_i b_i over n contiguous values with four running sums: a single sum is one long chain of
/// dependent additions (the compiler may not reassociate it), four let the additions overlap.
template <int Count>
inline double dot(const double* a, const double* b) noexcept
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int i = 0;
    for (; i + 3 < Count; i += 4) {
        s0 += a[i] * b[i];
        s1 += a[i + 1] * b[i + 1];
        s2 += a[i + 2] * b[i + 2];
        s3 += a[i + 3] * b[i + 3];
    }
    for (; i < Count; ++i) s0 += a[i] * b[i];
    return (s0 + s1) + (s2 + s3);
}
} // namespace detail

/// Upper-triangular R with non-negative diagonal and RᵀR = DᵀD + diag(σ)². A diagonal entry
/// that comes out exactly zero (no spread and no noise in that direction) is set to 1e-12 so
/// that the triangular solves downstream stay finite.
template <int Dense, int K>
Eigen::Matrix<double, K, K> upperFactor(const Eigen::Matrix<double, Dense, K>& D,
                                        const Eigen::Matrix<double, K, 1>& sigma) noexcept
{
    constexpr int Rows = Dense + K;
    constexpr int Span = Dense + 1;   // rows a reflection touches (see above)
    Eigen::Matrix<double, Rows, K> A;
    A.template topRows<Dense>() = D;
    A.template bottomRows<K>().setZero();
    A.template bottomRows<K>().diagonal() = sigma;

    Eigen::Matrix<double, K, K> R = Eigen::Matrix<double, K, K>::Zero();
    for (int k = 0; k < K; ++k) {
        double* v = A.data() + static_cast<std::ptrdiff_t>(k) * Rows + k;   // column k from row k
        const double norm2 = detail::dot<Span>(v, v);
        if (!(norm2 >= std::numeric_limits<double>::min())) {
            // Nothing (or only subnormal dust, whose 2/vᵀv would overflow) to reflect: row k of R
            // is the current row k of A with a zero pivot, floored below.
            R(k, k) = 0.0;
            for (int j = k + 1; j < K; ++j) R(k, j) = A(k, j);
            continue;
        }
        // Reflection H = I − β v vᵀ with v = x − α e₁, α = −sign(x₀)‖x‖ (no cancellation in v₀).
        const double x0 = v[0];
        const double alpha = x0 >= 0.0 ? -std::sqrt(norm2) : std::sqrt(norm2);
        v[0] = x0 - alpha;
        const double beta = 1.0 / (norm2 - alpha * x0);   // 2 / vᵀv, since vᵀv = 2(‖x‖² − α x₀)
        R(k, k) = alpha;
        for (int j = k + 1; j < K; ++j) {
            double* c = A.data() + static_cast<std::ptrdiff_t>(j) * Rows + k;
            const double f = beta * detail::dot<Span>(v, c);
            for (int i = 0; i < Span; ++i) c[i] -= f * v[i];
            R(k, j) = c[0];   // row k is final once reflection k is applied
        }
    }
    for (int k = 0; k < K; ++k) {
        if (R(k, k) < 0.0) R.row(k) = -R.row(k);
        if (!(R(k, k) > 0.0)) R(k, k) = 1e-12;
    }
    return R;
}

} // namespace armadillo::fusion::qr
