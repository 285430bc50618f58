#pragma once
// Rank-1 update and downdate of a Cholesky factor, the two LINPACK routines the square-root UKF
// needs (van der Merwe & Wan 2001, "cholupdate"; LINPACK DCHUD / DCHDD; thesis §2.7).
// Eigen has no such routine. Here the factor is lower-triangular L with P = L Lᵀ
// (DCHUD/DCHDD work on the upper Rᵀ R; the algebra is the transpose).
//
// - update:   L Lᵀ + x xᵀ, always possible (Givens-like rotations, O(n²)).
// - downdate: L Lᵀ − x xᵀ, possible only if the result stays positive definite. As DCHDD does,
//   the test comes first (solve L a = x, need ‖a‖ < 1), so on failure L is left untouched and
//   the caller decides how to recover (SquareRootUkf rebuilds a positive factor).
// Fixed-size templates: no heap allocation.
#include <Eigen/Core>
#include <cmath>

// GCC 12 reports -Warray-bounds false positives for Eigen's 1×1 fixed-size matrices (the scalar
// heading update); the accesses are in bounds (GCC bug 106247 family). Silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif

namespace armadillo::cholesky {

enum class Rank1Result {
    Ok,
    NotPositiveDefinite,   ///< downdate would make the matrix indefinite; L unchanged
    NonFinite,             ///< input factor or vector had NaN/Inf (or a zero diagonal); L unchanged
};

/// L ← chol(L Lᵀ + x xᵀ). L must be lower-triangular with non-zero diagonal; the result has a
/// positive diagonal. x is consumed (passed by value).
template <int N>
Rank1Result update(Eigen::Matrix<double, N, N>& L, Eigen::Matrix<double, N, 1> x) noexcept
{
    if (!x.allFinite()) return Rank1Result::NonFinite;
    for (int k = 0; k < N; ++k)
        if (!(std::abs(L(k, k)) > 0.0) || !std::isfinite(L(k, k))) return Rank1Result::NonFinite;
    for (int k = 0; k < N; ++k) {
        const double lkk = std::abs(L(k, k));
        if (L(k, k) < 0.0) L.col(k).tail(N - k) = -L.col(k).tail(N - k);   // same product, positive diagonal
        const double r = std::sqrt(lkk * lkk + x(k) * x(k));   // well scaled here; hypot is slow
        const double c = r / lkk;
        const double s = x(k) / lkk;
        L(k, k) = r;
        const int rest = N - k - 1;
        auto lk = L.col(k).tail(rest);
        auto xk = x.tail(rest);
        lk = (lk + s * xk) * (1.0 / c);
        xk = c * xk - s * lk;
    }
    return Rank1Result::Ok;
}

/// L ← chol(L Lᵀ − x xᵀ) if that is positive definite (relative margin `margin` on ‖a‖²);
/// otherwise returns NotPositiveDefinite and leaves L as it was.
template <int N>
Rank1Result downdate(Eigen::Matrix<double, N, N>& L, const Eigen::Matrix<double, N, 1>& xIn,
                     double margin = 1e-12) noexcept
{
    if (!xIn.allFinite()) return Rank1Result::NonFinite;
    for (int k = 0; k < N; ++k)
        if (!(std::abs(L(k, k)) > 0.0) || !std::isfinite(L(k, k))) return Rank1Result::NonFinite;
    // DCHDD tests first (solve L a = x, need ‖a‖ < 1). The same condition shows during the sweep
    // itself (some r_k² = l_kk² − x_k² ≤ 0 iff ‖a‖ ≥ 1), so the sweep runs on a copy, and the
    // copy is dropped on failure: one O(n²) pass instead of two, L still unchanged on failure.
    Eigen::Matrix<double, N, 1> x = xIn;
    Eigen::Matrix<double, N, N> W = L;   // work on a copy so that a failure leaves L unchanged
    for (int k = 0; k < N; ++k) {
        const double lkk = std::abs(W(k, k));
        if (W(k, k) < 0.0) W.col(k).tail(N - k) = -W.col(k).tail(N - k);
        const double r2 = (lkk - x(k)) * (lkk + x(k));
        if (!(r2 > margin * lkk * lkk)) return Rank1Result::NotPositiveDefinite;
        const double r = std::sqrt(r2);
        const double c = r / lkk;
        const double s = x(k) / lkk;
        W(k, k) = r;
        const int rest = N - k - 1;
        auto wk = W.col(k).tail(rest);
        auto xk = x.tail(rest);
        wk = (wk - s * xk) * (1.0 / c);
        xk = c * xk - s * wk;
    }
    L = W;
    return Rank1Result::Ok;
}

/// sign > 0: update, sign < 0: downdate (the "cholupdate(S, x, ±)" of the SR-UKF papers).
template <int N>
Rank1Result rank1(Eigen::Matrix<double, N, N>& L, const Eigen::Matrix<double, N, 1>& x, double sign) noexcept
{
    return sign >= 0.0 ? update<N>(L, x) : downdate<N>(L, x);
}

} // namespace armadillo::cholesky

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
