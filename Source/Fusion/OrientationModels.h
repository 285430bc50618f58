#pragma once
// The orientation state space and its models (thesis §2.7.6–2.7.7, ARMADILLO.md §5).
//
// State (mean): q (device → earth, unit), ω (rad/s, device frame, true rate), α (rad/s²,
// device frame), b (rad/s, gyro bias). The thesis's state is (q, ω, α); the bias is the one
// state added here (docs/FUSION.md: on the recordings the bias is what limits heading when the
// magnetometer is disturbed, and as a state it is corrected by every accelerometer update).
// Error state (12): rotation error angle e (q = q̄ · exp(e), device frame), then δω, δα, δb.
// Since issue 36 OrientationFilter runs on AttitudeSpace instead: error state (6) e, δb, with the
// gyroscope as the process model's input (GyroInputModel; docs/FUSION.md, departure 12).
// OrientationSpace and ConstantAccelerationModel stay as the thesis's model and as the generic
// SR-UKF's test bed (TestSquareRootUkf).
#include "Fusion/Quaternion.h"
#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace armadillo::fusion {

/// Named indices of the error state (STYLE.md convention 4).
enum ErrorIndex : int {
    kErrRotation = 0,   ///< 3: error angle, rad, device frame
    kErrRate = 3,       ///< 3: angular velocity, rad/s
    kErrAccel = 6,      ///< 3: angular acceleration, rad/s²
    kErrBias = 9,       ///< 3: gyro bias, rad/s
    kErrDim = 12
};

struct OrientationState {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();   ///< device → earth, unit
    Eigen::Vector3d rate = Eigen::Vector3d::Zero();           ///< ω, rad/s, device frame (bias removed)
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();          ///< α, rad/s², device frame
    Eigen::Vector3d bias = Eigen::Vector3d::Zero();           ///< gyro bias, rad/s, device frame
};

/// The manifold policy for SquareRootUkf: ⊞, ⊟ and the weighted mean.
struct OrientationSpace {
    static constexpr int kDim = kErrDim;
    using State = OrientationState;
    using ErrorVector = Eigen::Matrix<double, kDim, 1>;

    static State boxplus(const State& x, const ErrorVector& d) noexcept
    {
        State r;
        r.q = x.q * quat::exp(d.segment<3>(kErrRotation));
        quat::renormalise(r.q);
        r.rate = x.rate + d.segment<3>(kErrRate);
        r.accel = x.accel + d.segment<3>(kErrAccel);
        r.bias = x.bias + d.segment<3>(kErrBias);
        return r;
    }

    static ErrorVector boxminus(const State& a, const State& b) noexcept
    {
        ErrorVector d;
        d.segment<3>(kErrRotation) = quat::log(b.q.conjugate() * a.q);
        d.segment<3>(kErrRate) = a.rate - b.rate;
        d.segment<3>(kErrAccel) = a.accel - b.accel;
        d.segment<3>(kErrBias) = a.bias - b.bias;
        return d;
    }

    /// Weighted mean; the quaternion part by gradient descent on error angles (Kraft 2003),
    /// seeded with the centre sigma point: q̄ ← q̄ · exp(Σ w_i log(q̄⁻¹ q_i)).
    template <std::size_t K>
    static State mean(const std::array<State, K>& s, double w0, double wi, int iterations) noexcept
    {
        State m;
        m.rate = w0 * s[0].rate;
        m.accel = w0 * s[0].accel;
        m.bias = w0 * s[0].bias;
        for (std::size_t i = 1; i < K; ++i) {
            m.rate += wi * s[i].rate;
            m.accel += wi * s[i].accel;
            m.bias += wi * s[i].bias;
        }
        m.q = meanRotation(s, w0, wi, iterations);
        return m;
    }

    /// The quaternion part of the mean (shared with AttitudeSpace).
    template <std::size_t K>
    static Eigen::Quaterniond meanRotation(const std::array<State, K>& s, double w0, double wi, int iterations) noexcept
    {
        Eigen::Quaterniond q = s[0].q;
        for (int it = 0; it < iterations; ++it) {
            const Eigen::Quaterniond inv = q.conjugate();
            Eigen::Vector3d e = w0 * quat::log(inv * s[0].q);
            for (std::size_t i = 1; i < K; ++i) e += wi * quat::log(inv * s[i].q);
            q = q * quat::exp(e);
            quat::renormalise(q);
            if (e.squaredNorm() < 1e-16) break;   // a step below 1e-8 rad: converged (what is left is far smaller)
        }
        return q;
    }
};

/// Named indices of the error state OrientationFilter runs on since issue 36 (docs/FUSION.md,
/// departure 12): the gyroscope is the process model's input, so ω and α are no longer states.
enum AttitudeErrorIndex : int {
    kAttRotation = 0,   ///< 3: error angle, rad, device frame
    kAttBias = 3,       ///< 3: gyro bias, rad/s
    kAttDim = 6
};

/// The manifold policy for the filter's 6-dimensional error state (q, b). ω and α ride along in
/// the state as values the process model sets (the bias-corrected gyro, and α for bridging gaps);
/// they carry no uncertainty of their own, so ⊞ and ⊟ leave them to the left operand.
struct AttitudeSpace {
    static constexpr int kDim = kAttDim;
    using State = OrientationState;
    using ErrorVector = Eigen::Matrix<double, kDim, 1>;

    static State boxplus(const State& x, const ErrorVector& d) noexcept
    {
        State r = x;
        r.q = x.q * quat::exp(d.segment<3>(kAttRotation));
        quat::renormalise(r.q);
        r.bias = x.bias + d.segment<3>(kAttBias);
        return r;
    }

    /// x ⊞ d and x ⊞ −d at once, for the sigma points: exp(−e) is the conjugate of exp(e) (bit for
    /// bit: quat::exp is odd in e), so one exp serves both.
    static void boxplusPair(const State& x, const ErrorVector& d, State& plus, State& minus) noexcept
    {
        const Eigen::Quaterniond e = quat::exp(d.segment<3>(kAttRotation));
        plus = x;
        minus = x;
        plus.q = x.q * e;
        quat::renormalise(plus.q);
        minus.q = x.q * e.conjugate();
        quat::renormalise(minus.q);
        plus.bias = x.bias + d.segment<3>(kAttBias);
        minus.bias = x.bias - d.segment<3>(kAttBias);
    }

    static ErrorVector boxminus(const State& a, const State& b) noexcept
    {
        ErrorVector d;
        d.segment<3>(kAttRotation) = quat::log(b.q.conjugate() * a.q);
        d.segment<3>(kAttBias) = a.bias - b.bias;
        return d;
    }

    /// Weighted mean: the quaternion by OrientationSpace's gradient descent, the bias linearly.
    template <std::size_t K>
    static State mean(const std::array<State, K>& s, double w0, double wi, int iterations) noexcept
    {
        State m = s[0];
        m.bias = w0 * s[0].bias;
        for (std::size_t i = 1; i < K; ++i) m.bias += wi * s[i].bias;
        m.q = OrientationSpace::meanRotation(s, w0, wi, iterations);
        return m;
    }
};

/// Process model with the gyroscope as its input (issue 36): over one step the device turns by
/// Δ = (g − b) t + α t²/2, q' = q · exp(Δ), ω' = g − b + α t, b' = b. `gyro` is the
/// sample's rate (rad/s, bias included); `accel` (rad/s²) is zero on an ordinary step, where the
/// gyro sample is the mean rate over the step, and α only when a short gap is bridged.
struct GyroInputModel {
    double dt = 0.0;                                    ///< s
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();     ///< rad/s, as measured (bias included)
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();    ///< rad/s², extrapolation over a bridged gap
    void operator()(OrientationState& x) const noexcept
    {
        const Eigen::Vector3d rate = gyro - x.bias;
        x.q = x.q * quat::exp(rate * dt + accel * (0.5 * dt * dt));
        quat::renormalise(x.q);
        x.rate = rate + accel * dt;
    }
};

/// The SO(3) matrices both linearised process models need for Δ (Sola et al. 2018): Rᵀ = exp(Δ)ᵀ
/// and the right Jacobian J_r (exp(φ + δφ) ≈ exp(φ) exp(J_r(φ) δφ), eq. 143).
struct RotationStep {
    Eigen::Matrix3d Rt, Jr;
    explicit RotationStep(const Eigen::Vector3d& delta) noexcept
    {
        const double th2 = delta.squaredNorm();
        double a, b, s1, s2;   // J_r = I − a [Δ]× + b [Δ]×², Rᵀ = I − s1 [Δ]× + s2 [Δ]×²
        if (th2 < 1e-4) {      // series (θ < 0.01 rad): error below 1e-13
            a = 0.5 - th2 / 24.0;
            b = 1.0 / 6.0 - th2 / 120.0;
            s1 = 1.0 - th2 / 6.0;
            s2 = a;
        } else {
            const double th = std::sqrt(th2);
            a = (1.0 - std::cos(th)) / th2;
            b = (th - std::sin(th)) / (th2 * th);
            s1 = std::sin(th) / th;
            s2 = a;
        }
        const Eigen::Matrix3d K = quat::skew(delta);
        const Eigen::Matrix3d K2 = K * K;
        Jr = Eigen::Matrix3d::Identity() - a * K + b * K2;
        Rt = Eigen::Matrix3d::Identity() - s1 * K + s2 * K2;
    }
};

/// The Jacobian of GyroInputModel in the error state (q = q̄ · exp(e)), applied to a factor in
/// place (S ← F S): e' = R(Δ̄)ᵀ e − J_r(Δ̄) t δb, δb' = δb. Only the rotation rows change.
struct GyroInputJacobian {
    double dt = 0.0;                                    ///< s
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();    ///< Δ̄ of the mean, rad
    template <class Factor>
    void operator()(Factor& S) const noexcept
    {
        const RotationStep r(delta);
        S.template middleRows<3>(kAttRotation) =
            (r.Rt.lazyProduct(S.template middleRows<3>(kAttRotation)) -
             (dt * r.Jr).lazyProduct(S.template middleRows<3>(kAttBias))).eval();
    }
};

/// Process model (thesis §2.7.6): constant angular acceleration over one step,
/// e = ω t + α t²/2, q' = q · exp(e), ω' = ω + α t, α' = α, b' = b.
struct ConstantAccelerationModel {
    double dt = 0.0;   ///< s
    void operator()(OrientationState& x) const noexcept
    {
        x.q = x.q * quat::exp(x.rate * dt + x.accel * (0.5 * dt * dt));
        quat::renormalise(x.q);
        x.rate += x.accel * dt;
    }
};

/// The Jacobian of ConstantAccelerationModel in the error state, applied to a factor in place
/// (S ← F S). With q = q̄ · exp(e) and Δ = ω t + α t²/2, to first order in the errors
///   e' = R(Δ̄)ᵀ e + J_r(Δ̄) (δω t + δα t²/2),   δω' = δω + δα t,   δα' = δα,   δb' = δb,
/// where R(Δ̄) is the rotation exp(Δ̄) and J_r the right Jacobian of SO(3) (Sola et al. 2018, eq. 143:
/// exp(φ + δφ) ≈ exp(φ) exp(J_r(φ) δφ)). Block-sparse: only the rotation and rate rows change.
struct ConstantAccelerationJacobian {
    double dt = 0.0;                                        ///< s
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();        ///< Δ̄ = ω̄ t + ᾱ t²/2 of the mean, rad
    template <class Factor>
    void operator()(Factor& S) const noexcept
    {
        const double th2 = delta.squaredNorm();
        double a, b;   // J_r = I − a [Δ]× + b [Δ]×²
        if (th2 < 1e-4) {   // series (θ < 0.01 rad): error below 1e-13
            a = 0.5 - th2 / 24.0;
            b = 1.0 / 6.0 - th2 / 120.0;
        } else {
            const double th = std::sqrt(th2);
            a = (1.0 - std::cos(th)) / th2;
            b = (th - std::sin(th)) / (th2 * th);
        }
        const Eigen::Matrix3d K = quat::skew(delta);
        const Eigen::Matrix3d K2 = K * K;
        const Eigen::Matrix3d Jr = Eigen::Matrix3d::Identity() - a * K + b * K2;
        // exp(Δ) as a matrix (Rodrigues): R = I + sinθ/θ K + (1 − cosθ)/θ² K²; Rᵀ = I − … K + … K².
        double s1, s2;
        if (th2 < 1e-4) {
            s1 = 1.0 - th2 / 6.0;
            s2 = 0.5 - th2 / 24.0;
        } else {
            const double th = std::sqrt(th2);
            s1 = std::sin(th) / th;
            s2 = (1.0 - std::cos(th)) / th2;
        }
        const Eigen::Matrix3d Rt = Eigen::Matrix3d::Identity() - s1 * K + s2 * K2;
        constexpr int C = Factor::ColsAtCompileTime;
        const Eigen::Matrix<double, 3, C> rateAndAccel =
            dt * S.template middleRows<3>(kErrRate) + (0.5 * dt * dt) * S.template middleRows<3>(kErrAccel);
        S.template middleRows<3>(kErrRotation) =
            (Rt.lazyProduct(S.template middleRows<3>(kErrRotation)) + Jr.lazyProduct(rateAndAccel)).eval();
        S.template middleRows<3>(kErrRate) += dt * S.template middleRows<3>(kErrAccel);
    }
};

/// Gravity (thesis §2.7.7): the accelerometer, normalised, sees earth "up" (0, 1, 0) in the
/// device frame: a/|a| = q⁻¹ (0,1,0) q. Linear acceleration is noise here (gated, see filter).
struct GravityObservation {
    Eigen::Vector3d operator()(const OrientationState& x) const noexcept
    {
        return quat::rotateInverse(x.q, Eigen::Vector3d::UnitY());
    }
};

/// Tracked field vector (thesis §2.7.7): m/|m| = q⁻¹ h q with h the unit earth-frame field
/// (north is −Z, dipping down by the tracked dip angle). Kept for completeness and tests; the
/// filter uses the heading-only form below by default.
struct FieldObservation {
    Eigen::Vector3d field {0.0, -1.0, 0.0};   ///< unit, earth frame
    Eigen::Vector3d operator()(const OrientationState& x) const noexcept
    {
        return quat::rotateInverse(x.q, field);
    }
};

/// Heading-only magnetometer (a departure, docs/FUSION.md): the measured field with its
/// vertical part removed (using the prior's tilt) is rotated into earth by each sigma point;
/// the observation is its angle about +Y from magnetic north (−Z), which must be 0. To first
/// order this sees heading only, so a disturbed field cannot tilt the estimate.
struct HeadingObservation {
    Eigen::Vector3d horizontalField {0.0, 0.0, -1.0};   ///< device frame, horizontal in the prior
    Eigen::Matrix<double, 1, 1> operator()(const OrientationState& x) const noexcept
    {
        const Eigen::Vector3d m = quat::rotate(x.q, horizontalField);
        // Rotation φ about +Y takes (0,0,−1) to (−sin φ, 0, −cos φ).
        return Eigen::Matrix<double, 1, 1>(std::atan2(-m.x(), -m.z()));
    }
};

/// Gyroscope (thesis §2.7.7): gyro = ω + b in the device frame.
struct GyroObservation {
    Eigen::Vector3d operator()(const OrientationState& x) const noexcept { return x.rate + x.bias; }
};

/// Gyro-bias tracker output as an observation of the bias state.
struct BiasObservation {
    Eigen::Vector3d operator()(const OrientationState& x) const noexcept { return x.bias; }
};

} // namespace armadillo::fusion
