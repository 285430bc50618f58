#pragma once
// Rank-1 update and downdate of a Cholesky factor, the two LINPACK routines the square-root UKF
// needs (van der Merwe & Wan 2001, "cholupdate"; LINPACK DCHUD / DCHDD; thesis §2.7).
// Eigen has one too (LLT::rankUpdate(v, sigma), σ < 0 for a downdate), and ours is kept for two
// reasons: Eigen's works on an LLT object, not on the triangular block of the filter's own
// fixed-size factor, so each use would copy the factor in and out; and its downdate finds an
// indefinite result column by column, after it has already overwritten the columns before it
// (it then reports NumericalIssue through info()), whereas the filter needs L intact to recover.
// Ours tests the downdate first (as DCHDD does) and sweeps contiguous columns (FUSION.md, cost).
// Here the factor is lower-triangular L with P = L Lᵀ (DCHUD/DCHDD work on the upper
// Rᵀ R; the algebra is the transpose).
//
// - update:   L Lᵀ + x xᵀ, always possible (Givens-like rotations, O(n²)).
// - downdate: L Lᵀ − x xᵀ, possible only if the result stays positive definite. As DCHDD does,
//   the test comes first (solve L a = x, need ‖a‖ < 1), so on failure L is left untouched and
//   the caller decides how to recover (SquareRootUkf rebuilds a positive factor).
// Fixed-size templates: no heap allocation.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>

// GCC 12 reports -Warray-bounds false positives for Eigen's 1×1 fixed-size matrices (the scalar
// heading update); the accesses are in bounds (GCC bug 106247 family). Silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif

namespace armadillo::fusion::cholesky {

enum class Rank1Result {
    Ok,
    NotPositiveDefinite,   ///< downdate would make the matrix indefinite; L unchanged
    NonFinite,             ///< input factor or vector had NaN/Inf (or a zero diagonal); L unchanged
};

namespace detail {
/// One column of the sweep: rows k+1..N−1 of column `l` and of `x` are rotated together.
/// Column-major storage makes both contiguous, and with N a compile-time constant the loop
/// vectorises (Eigen's runtime-sized tail() blocks did not: the rank-1 steps were a fifth of
/// the filter's time). `sign` +1 for the update, −1 for the downdate.
template <int N>
inline void rotateColumn(double* l, double* x, int k, double s, double invC, double c, double sign) noexcept
{
    for (int i = k + 1; i < N; ++i) {
        const double li = (l[i] + sign * s * x[i]) * invC;
        x[i] = c * x[i] - s * li;
        l[i] = li;
    }
}

template <int N>
inline bool usableFactor(const Eigen::Matrix<double, N, N>& L) noexcept
{
    for (int k = 0; k < N; ++k)
        if (!(std::abs(L(k, k)) > 0.0) || !std::isfinite(L(k, k))) return false;
    return true;
}
} // namespace detail

/// L ← chol(L Lᵀ + x xᵀ). L must be lower-triangular with non-zero diagonal; the result has a
/// positive diagonal. x is consumed (passed by value).
template <int N>
Rank1Result update(Eigen::Matrix<double, N, N>& L, Eigen::Matrix<double, N, 1> x) noexcept
{
    if (!x.allFinite()) return Rank1Result::NonFinite;
    if (!detail::usableFactor<N>(L)) return Rank1Result::NonFinite;
    double* xs = x.data();
    for (int k = 0; k < N; ++k) {
        double* lk = L.data() + static_cast<std::ptrdiff_t>(k) * N;   // column k
        if (lk[k] < 0.0)   // same product, positive diagonal
            for (int i = k; i < N; ++i) lk[i] = -lk[i];
        const double lkk = lk[k];
        const double r = std::sqrt(lkk * lkk + xs[k] * xs[k]);   // well scaled here; hypot is slow
        const double invL = 1.0 / lkk;
        lk[k] = r;
        detail::rotateColumn<N>(lk, xs, k, xs[k] * invL, lkk / r, r * invL, 1.0);
    }
    return Rank1Result::Ok;
}

/// L ← chol(L Lᵀ − X Xᵀ) for the M columns of X (M successive rank-1 downdates, as DCHDD would
/// do them one after the other), if every step stays positive definite (relative margin
/// `margin` on each pivot); otherwise returns NotPositiveDefinite and leaves L as it was.
///
/// The M sweeps are interleaved column by column: downdate m touches column k after downdate
/// m − 1 has finished column k and before it starts column k + 1, which is exactly the data each
/// step reads in the one-after-the-other order, so the result is bit-identical to it. Each pivot
/// costs a square root and two divisions whose latencies chain within one sweep; interleaving
/// lets M chains overlap (the SR-UKF's measurement updates downdate by M = 3 columns at once).
template <int N, int M>
Rank1Result downdateColumns(Eigen::Matrix<double, N, N>& L, const Eigen::Matrix<double, N, M>& X,
                            double margin = 1e-12) noexcept
{
    if (!X.allFinite()) return Rank1Result::NonFinite;
    if (!detail::usableFactor<N>(L)) return Rank1Result::NonFinite;
    // DCHDD tests first (solve L a = x, need ‖a‖ < 1). The same condition shows during the sweep
    // itself (some r_k² = l_kk² − x_k² ≤ 0 iff ‖a‖ ≥ 1), so the sweep runs on a copy, and the
    // copy is dropped on failure: one O(n²) pass instead of two, L still unchanged on failure.
    Eigen::Matrix<double, N, M> x = X;
    Eigen::Matrix<double, N, N> W = L;   // work on a copy so that a failure leaves L unchanged
    for (int k = 0; k < N; ++k) {
        double* wk = W.data() + static_cast<std::ptrdiff_t>(k) * N;   // column k
        if (wk[k] < 0.0)
            for (int i = k; i < N; ++i) wk[i] = -wk[i];
        for (int m = 0; m < M; ++m) {
            double* xs = x.data() + static_cast<std::ptrdiff_t>(m) * N;
            const double lkk = wk[k];
            const double r2 = (lkk - xs[k]) * (lkk + xs[k]);
            if (!(r2 > margin * lkk * lkk)) return Rank1Result::NotPositiveDefinite;
            const double r = std::sqrt(r2);
            const double invL = 1.0 / lkk;
            wk[k] = r;
            detail::rotateColumn<N>(wk, xs, k, xs[k] * invL, lkk / r, r * invL, -1.0);
        }
    }
    L = W;
    return Rank1Result::Ok;
}

/// L ← chol(L Lᵀ − x xᵀ) if that is positive definite (relative margin `margin` on ‖a‖²);
/// otherwise returns NotPositiveDefinite and leaves L as it was.
template <int N>
Rank1Result downdate(Eigen::Matrix<double, N, N>& L, const Eigen::Matrix<double, N, 1>& x,
                     double margin = 1e-12) noexcept
{
    return downdateColumns<N, 1>(L, x, margin);
}

/// sign > 0: update, sign < 0: downdate (the "cholupdate(S, x, ±)" of the SR-UKF papers).
template <int N>
Rank1Result rank1(Eigen::Matrix<double, N, N>& L, const Eigen::Matrix<double, N, 1>& x, double sign) noexcept
{
    return sign >= 0.0 ? update<N>(L, x) : downdate<N>(L, x);
}

} // namespace armadillo::fusion::cholesky

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
