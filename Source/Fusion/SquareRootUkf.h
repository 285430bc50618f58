#pragma once
// Square-root unscented Kalman filter (van der Merwe & Wan, ICASSP 2001), thesis §2.7, on a
// state that lives on a manifold: the covariance is kept in an N-dimensional error space
// (for orientation: error angles, never raw quaternions) and noise is additive there.
//
// The filter is generic; the state space is a policy type (see OrientationModels.h):
//   struct Space {
//     static constexpr int kDim;                       // error-state dimension N
//     using State = ...;                               // the mean (e.g. quaternion + vectors)
//     static State boxplus(const State&, const Matrix<N,1>&);      // x ⊞ δ
//     static Matrix<N,1> boxminus(const State& a, const State& b); // a ⊟ b (error of a about b)
//     static State mean(const std::array<State,2N+1>&, double w0, double wi, int iterations);
//   };
// Process and observation models are plain callables, so models stay separate from the filter.
//
// Square-root form: S is lower-triangular with P = S Sᵀ. Prediction and the innovation factor
// come from a QR decomposition of the weighted deviations (plus the noise square roots) and a
// rank-1 Cholesky update/downdate for the centre point, whose weight may be negative; the
// correction is a series of rank-1 downdates by the columns of K·S_yy; the gain comes from two
// triangular solves. A failed downdate is detected (Cholesky.h) and recovered by rebuilding a
// positive-definite factor from S Sᵀ − u uᵀ with its eigenvalues floored; it is counted.
// Fixed-size Eigen throughout: no heap allocation.
#include "Fusion/Cholesky.h"
#include "Fusion/QrFactor.h"
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

// GCC 12 reports -Warray-bounds false positives for Eigen's 1×1 fixed-size matrices (the scalar
// heading update); the accesses are in bounds (GCC bug 106247 family). Silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif

namespace armadillo::fusion {

/// Sigma-point spread and weights (van der Merwe): λ = α²(N + κ) − N, γ = √(N + λ).
struct UkfWeights {
    double alpha = 1.0;   ///< spread of the sigma points (dimensionless, 0 < α ≤ 1)
    double beta = 2.0;    ///< prior knowledge of the distribution (2 = Gaussian)
    double kappa = 0.0;   ///< secondary scaling (dimensionless)
    int meanIterations = 4;   ///< gradient-descent steps of the manifold mean (Kraft 2003: ~4)
};

struct UkfStats {
    std::size_t downdateFailures = 0;   ///< rank-1 downdates refused and recovered
    std::size_t rejectedUpdates = 0;    ///< measurement updates skipped (non-finite innovation)
};

template <class Space>
class SquareRootUkf {
public:
    static constexpr int N = Space::kDim;
    static constexpr int kSigma = 2 * N + 1;
    using State = typename Space::State;
    using ErrorVector = Eigen::Matrix<double, N, 1>;
    using Factor = Eigen::Matrix<double, N, N>;
    using SigmaStates = std::array<State, kSigma>;

    explicit SquareRootUkf(const UkfWeights& w = {}) { setWeights(w); }

    void setWeights(const UkfWeights& w)
    {
        weights_ = w;
        const double lambda = w.alpha * w.alpha * (N + w.kappa) - N;
        gamma_ = std::sqrt(N + lambda);
        wm0_ = lambda / (N + lambda);
        wc0_ = wm0_ + (1.0 - w.alpha * w.alpha + w.beta);
        wi_ = 1.0 / (2.0 * (N + lambda));
    }
    const UkfWeights& weights() const noexcept { return weights_; }
    double gamma() const noexcept { return gamma_; }
    double meanWeight0() const noexcept { return wm0_; }
    double covWeight0() const noexcept { return wc0_; }
    double weightI() const noexcept { return wi_; }

    /// Sets the mean and the square root of the covariance (lower-triangular S, P = S Sᵀ).
    void reset(const State& x, const Factor& sqrtP)
    {
        x_ = x;
        S_ = sqrtP.template triangularView<Eigen::Lower>();
    }
    const State& state() const noexcept { return x_; }
    State& state() noexcept { return x_; }
    const Factor& sqrtCovariance() const noexcept { return S_; }
    Factor covariance() const { return S_ * S_.transpose(); }
    const UkfStats& stats() const noexcept { return stats_; }

    /// Time update: every sigma point goes through `f(State&)` (in place); `noiseStd` is the
    /// standard deviation of the additive process noise over this step, per error component.
    ///
    /// `Untouched`: error components from this index on are neither read nor changed by f, and
    /// ⊞/⊟ are plain addition there (for orientation: the gyro bias). S is lower-triangular, so
    /// sigma columns j ≥ Untouched move only those components and f(x̄ ⊞ ±γS_j) = f(x̄) ⊞ ±γS_j
    /// (exact up to rounding): 2(N − Untouched) evaluations of f are saved, nothing is approximated.
    template <int Untouched = N, class ProcessModel>
    void predict(ProcessModel&& f, const ErrorVector& noiseStd)
    {
        static_assert(Untouched >= 0 && Untouched <= N, "Untouched must be within the error state");
        makeSigmaPoints(Untouched);
        f(sigma_[0]);
        for (int j = 0; j < Untouched; ++j) {
            f(sigma_[1 + j]);
            f(sigma_[1 + N + j]);
        }
        for (int j = Untouched; j < N; ++j) {
            const ErrorVector d = gamma_ * S_.col(j);
            sigma_[1 + j] = Space::boxplus(sigma_[0], d);
            sigma_[1 + N + j] = Space::boxplus(sigma_[0], -d);
        }
        x_ = Space::mean(sigma_, wm0_, wi_, weights_.meanIterations);
        // Compound matrix [√Wi (X_i ⊟ x̄) | √Q]ᵀ, QR → the upper factor of P⁻ without its centre term.
        Eigen::Matrix<double, 2 * N, N> A;
        const double swi = std::sqrt(wi_);
        const ErrorVector d0 = Space::boxminus(sigma_[0], x_);
        for (int j = 0; j < Untouched; ++j) {
            A.row(j) = swi * Space::boxminus(sigma_[1 + j], x_).transpose();
            A.row(N + j) = swi * Space::boxminus(sigma_[1 + N + j], x_).transpose();
        }
        for (int j = Untouched; j < N; ++j) {   // X_i ⊟ x̄ = (X_0 ⊟ x̄) ± γ S_j there, as above
            A.row(j) = swi * (d0 + gamma_ * S_.col(j)).transpose();
            A.row(N + j) = swi * (d0 - gamma_ * S_.col(j)).transpose();
        }
        S_ = qr::upperFactor<2 * N, N>(A, noiseStd).transpose();
        rank1(S_, ErrorVector(std::sqrt(std::abs(wc0_)) * d0), wc0_);
    }

    /// Linearised time update (the one place this filter is not unscented; docs/FUSION.md): the
    /// mean goes through `f(State&)` once, and the factor through the model's Jacobian,
    /// `applyJacobian(Factor&)` replacing S by F·S in place, then S⁻ = qr([F S | √Q]ᵀ). For a
    /// process model that is linear, or nearly so over one step, this is what the unscented
    /// transform would give up to terms of second order in the spread (orientation over one 3.5 ms
    /// step: means 2e-8 rad apart at the running filter's spread, 3e-5 rad right after a
    /// re-acquisition; TestSquareRootUkf), at a fraction of the cost: no sigma points, no manifold mean.
    template <class ProcessModel, class Jacobian>
    void predictLinearised(ProcessModel&& f, Jacobian&& applyJacobian, const ErrorVector& noiseStd)
    {
        f(x_);
        applyJacobian(S_);
        S_ = qr::upperFactor<N, N>(Factor(S_.transpose()), noiseStd).transpose();
    }

    /// Measurement update with an M-vector z, model `h(const State&) → Matrix<M,1>` and
    /// independent additive noise of standard deviation `noiseStd`. Returns the normalised
    /// innovation squared (NIS, χ² with M degrees of freedom when the model holds), or NaN when
    /// the update was refused (non-finite values). If `nisLimit` is exceeded the noise is inflated
    /// so that the NIS equals the limit (a soft gate: an outlier moves the state only a little).
    ///
    /// `Leading`: the observation depends only on the first `Leading` error components (e.g. 3:
    /// orientation only). S is lower-triangular, so sigma columns j ≥ Leading leave those
    /// components at the mean and their observations equal h(x̄): exact, and it saves evaluating
    /// and building 2(N − Leading) sigma points.
    template <int M, int Leading = N, class ObservationModel>
    double update(const Eigen::Matrix<double, M, 1>& z, ObservationModel&& h,
                  const Eigen::Matrix<double, M, 1>& noiseStd, double nisLimit = INFINITY)
    {
        static_assert(Leading >= 1 && Leading <= N, "Leading must be within the error state");
        using VecM = Eigen::Matrix<double, M, 1>;
        makeSigmaPoints(Leading);
        std::array<VecM, kSigma> Y;
        Y[0] = h(sigma_[0]);
        for (int j = 0; j < N; ++j) {
            if (j < Leading) {
                Y[1 + j] = h(sigma_[1 + j]);
                Y[1 + N + j] = h(sigma_[1 + N + j]);
            } else {
                Y[1 + j] = Y[0];
                Y[1 + N + j] = Y[0];
            }
        }
        VecM yMean = wm0_ * Y[0];
        for (int i = 1; i < kSigma; ++i) yMean += wi_ * Y[i];
        const VecM nu = z - yMean;
        if (!nu.allFinite()) {
            ++stats_.rejectedUpdates;
            return NAN;
        }

        // The 2(N − Leading) sigma points beyond Leading all observe Y[0]: their equal rows of the
        // compound matrix are one row scaled by √(2(N − Leading)) (same BᵀB, so the same factor).
        constexpr int Rows = Leading < N ? 2 * Leading + 1 : 2 * N;
        Eigen::Matrix<double, Rows, M> B;
        const double swi = std::sqrt(wi_);
        for (int j = 0; j < Leading; ++j) {
            B.row(2 * j) = swi * (Y[1 + j] - yMean).transpose();
            B.row(2 * j + 1) = swi * (Y[1 + N + j] - yMean).transpose();
        }
        if constexpr (Leading < N) B.row(2 * Leading) = (swi * std::sqrt(2.0 * (N - Leading))) * (Y[0] - yMean).transpose();
        Eigen::Matrix<double, M, M> Syy = qr::upperFactor<Rows, M>(B, noiseStd).transpose();
        const VecM dy0 = std::sqrt(std::abs(wc0_)) * (Y[0] - yMean);
        rank1(Syy, dy0, wc0_);

        double nis = whitened(Syy, nu).squaredNorm();
        if (nis > nisLimit) {
            // Inflate R by k so that the NIS drops to the limit; k found by one rescaling of the
            // innovation factor (the sigma spread is kept), good to first order.
            const double k = nis / nisLimit;
            Syy = qr::upperFactor<Rows, M>(B, VecM(std::sqrt(k) * noiseStd)).transpose();
            rank1(Syy, dy0, wc0_);
            nis = whitened(Syy, nu).squaredNorm();
        }

        // Pxy = Σ Wc_i (X_i ⊟ x̄)(Y_i − ȳ)ᵀ; X_i ⊟ x̄ = ±γ S_j exactly, and the centre term is zero.
        Eigen::Matrix<double, N, M> D;
        for (int j = 0; j < N; ++j) D.row(j) = (Y[1 + j] - Y[1 + N + j]).transpose();
        // Products of these small fixed sizes are written lazily: Eigen's default sends anything with
        // rows + cols + depth ≥ 20 through its blocked GEMM (packing, dispatch), slower here.
        const Eigen::Matrix<double, N, M> Pxy = (wi_ * gamma_) * S_.lazyProduct(D);
        if (!correct(Pxy, Syy, nu)) return NAN;
        return nis;
    }

    /// The step both measurement updates share: gain K = Pxy (Syy Syyᵀ)⁻¹ by two triangular solves
    /// (Kᵀ = Syy⁻ᵀ (Syy⁻¹ Pxyᵀ)), the correction x ⊞ K ν, and the downdate of S by the columns of
    /// K·Syy. False (and counted) when the correction is not finite; nothing changes then.
    template <int M>
    bool correct(const Eigen::Matrix<double, N, M>& Pxy, const Eigen::Matrix<double, M, M>& Syy,
                 const Eigen::Matrix<double, M, 1>& nu)
    {
        Eigen::Matrix<double, M, N> Kt = Pxy.transpose();
        solveLower(Syy, Kt);
        solveLowerTransposed(Syy, Kt);
        const Eigen::Matrix<double, N, M> K = Kt.transpose();
        const ErrorVector dx = K * nu;
        if (!dx.allFinite()) {
            ++stats_.rejectedUpdates;
            return false;
        }
        x_ = Space::boxplus(x_, dx);
        const Eigen::Matrix<double, N, M> U = K.lazyProduct(Syy);
        downdateBy<M>(U);
        return true;
    }

    /// Measurement update for a linear observation y = H (x ⊟ x̄) + ȳ (here: gyro = ω + b, bias).
    /// The unscented transform of a linear map is exact, so no sigma points are needed: the
    /// deviations are H·S directly. Same square-root algebra (QR, triangular solves, downdates).
    template <int M>
    double updateLinear(const Eigen::Matrix<double, M, 1>& nu, const Eigen::Matrix<double, M, N>& H,
                        const Eigen::Matrix<double, M, 1>& noiseStd)
    {
        if (!nu.allFinite()) {
            ++stats_.rejectedUpdates;
            return NAN;
        }
        const Eigen::Matrix<double, M, N> HS = H.lazyProduct(S_);
        const Eigen::Matrix<double, M, M> Syy =
            qr::upperFactor<N, M>(Eigen::Matrix<double, N, M>(HS.transpose()), noiseStd).transpose();
        const Eigen::Matrix<double, N, M> Pxy = S_.lazyProduct(HS.transpose());
        if (!correct(Pxy, Syy, nu)) return NAN;
        return whitened(Syy, nu).squaredNorm();
    }

    /// Rank-1 update (sign ≥ 0) or downdate (sign < 0) of a factor, with recovery on failure:
    /// the covariance S Sᵀ ± x xᵀ is rebuilt with eigenvalues floored at a small positive value.
    template <int K>
    void rank1(Eigen::Matrix<double, K, K>& L, const Eigen::Matrix<double, K, 1>& x, double sign)
    {
        if (cholesky::rank1<K>(L, x, sign) == cholesky::Rank1Result::Ok) return;
        ++stats_.downdateFailures;
        recoverFactor<K>(L, x, sign);
    }

    /// S ← chol(S Sᵀ − U Uᵀ) (M rank-1 downdates, interleaved), with the same recovery as rank1().
    template <int M>
    void downdateBy(const Eigen::Matrix<double, N, M>& U)
    {
        if (cholesky::downdateColumns<N, M>(S_, U) == cholesky::Rank1Result::Ok) return;
        ++stats_.downdateFailures;
        recoverFactor<N, M>(S_, U, -1.0);
    }

private:
    void makeSigmaPoints(int columns = N)
    {
        sigma_[0] = x_;
        for (int j = 0; j < columns; ++j) {
            const ErrorVector d = gamma_ * S_.col(j);
            // A space that can form x ⊞ d and x ⊞ −d together (one exp for both) says so.
            if constexpr (requires(State& a, State& b) { Space::boxplusPair(x_, d, a, b); }) {
                Space::boxplusPair(x_, d, sigma_[1 + j], sigma_[1 + N + j]);
            } else {
                sigma_[1 + j] = Space::boxplus(x_, d);
                sigma_[1 + N + j] = Space::boxplus(x_, -d);
            }
        }
    }

    template <int M>
    static Eigen::Matrix<double, M, 1> whitened(const Eigen::Matrix<double, M, M>& L, Eigen::Matrix<double, M, 1> v)
    {
        solveLower(L, v);
        return v;
    }

    /// B ← L⁻¹ B and B ← L⁻ᵀ B for a lower-triangular M×M factor (M ≤ 3 here) by substitution.
    /// Eigen's triangular solver routes a many-column right-hand side through its blocked
    /// kernels (packing), which costs more than the arithmetic at these sizes.
    template <int M, int C>
    static void solveLower(const Eigen::Matrix<double, M, M>& L, Eigen::Matrix<double, M, C>& B)
    {
        for (int i = 0; i < M; ++i) {
            for (int k = 0; k < i; ++k) B.row(i) -= L(i, k) * B.row(k);
            B.row(i) *= 1.0 / L(i, i);
        }
    }
    template <int M, int C>
    static void solveLowerTransposed(const Eigen::Matrix<double, M, M>& L, Eigen::Matrix<double, M, C>& B)
    {
        for (int i = M - 1; i >= 0; --i) {
            for (int k = i + 1; k < M; ++k) B.row(i) -= L(k, i) * B.row(k);
            B.row(i) *= 1.0 / L(i, i);
        }
    }

    template <int K, int Cols = 1>
    static void recoverFactor(Eigen::Matrix<double, K, K>& L, const Eigen::Matrix<double, K, Cols>& x, double sign)
    {
        using Mat = Eigen::Matrix<double, K, K>;
        Mat P = L * L.transpose();
        if (x.allFinite()) P += (sign >= 0.0 ? 1.0 : -1.0) * x * x.transpose();
        P = 0.5 * (P + P.transpose()).eval();
        if (!P.allFinite()) P = Mat::Identity() * 1e-6;
        Eigen::SelfAdjointEigenSolver<Mat> eig(P);
        Eigen::Matrix<double, K, 1> ev = eig.eigenvalues();
        const double floor = std::max(1e-12, 1e-9 * std::abs(ev.maxCoeff()));
        for (int i = 0; i < K; ++i) ev(i) = std::max(ev(i), floor);
        const Mat Pp = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
        Eigen::LLT<Mat> llt(Pp);
        if (llt.info() == Eigen::Success)
            L = llt.matrixL();
        else
            L = ev.cwiseSqrt().asDiagonal();   // last resort: finite, positive, right scale
    }

    UkfWeights weights_ {};
    double gamma_ = 0.0, wm0_ = 0.0, wc0_ = 0.0, wi_ = 0.0;
    State x_ {};
    Factor S_ = Factor::Identity();
    SigmaStates sigma_ {};
    UkfStats stats_ {};
};

} // namespace armadillo::fusion

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
