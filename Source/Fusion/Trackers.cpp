#include "Fusion/Trackers.h"
#include "Core/Types.h"
#include "Fusion/Quaternion.h"
#include <algorithm>
#include <cmath>
#include <Eigen/Cholesky>

namespace armadillo::fusion {
namespace {
/// Weight of one step of a first-order low-pass with time constant tau (s) over dt (s).
double lowPassGain(double dt, double tau) { return tau > 0.0 ? 1.0 - std::exp(-dt / tau) : 1.0; }
} // namespace

GyroBiasTracker::GyroBiasTracker() : params_(Params {}) {}
MagneticFieldTracker::MagneticFieldTracker() : params_(Params {}) {}

bool GyroBiasTracker::update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double dt)
{
    if (!gyro.allFinite() || !accel.allFinite() || !(dt > 0.0)) return atRest();
    State& s = state_;
    if (!s.primed) {
        s.gyroLowPass = gyro;
        s.accelLowPass = accel;
        s.primed = true;
    }
    const double k = lowPassGain(dt, params_.restFilterTau);
    s.gyroLowPass += k * (gyro - s.gyroLowPass);
    s.accelLowPass += k * (accel - s.accelLowPass);
    const bool still = (gyro - s.gyroLowPass).norm() < params_.restGyroDeviation
                    && (accel - s.accelLowPass).norm() < params_.restAccelDeviation
                    && s.gyroLowPass.norm() < 4.0 * params_.restGyroDeviation;
    if (!still) {
        s.restTime = 0.0;
        s.samples = 0;
        return false;
    }
    s.restTime += dt;
    // Running mean over the last `windowSamples` samples (exponential once the window is full).
    s.samples = std::min(s.samples + 1, std::max(1, params_.windowSamples));
    s.mean += (gyro - s.mean) / static_cast<double>(s.samples);
    return atRest();
}

double MagneticFieldTracker::dipAngle(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag)
{
    const double na = accel.norm(), nm = mag.norm();
    if (!(na > 0.0) || !(nm > 0.0) || !std::isfinite(na) || !std::isfinite(nm)) return core::kNaN;
    return std::acos(std::clamp(accel.dot(mag) / (na * nm), -1.0, 1.0));
}

bool MagneticFieldTracker::update(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag, double dt)
{
    State& s = state_;
    const double n = mag.norm();
    if (!mag.allFinite() || !(n > 0.0)) return false;
    dt = std::max(dt, 0.0);
    const bool accelOk = accel.allFinite()
        && std::abs(accel.norm() - core::kStandardGravity) < params_.accelTolerance * core::kStandardGravity;
    const double dip = accelOk ? dipAngle(accel, mag) : core::kNaN;
    const bool dipValid = std::isfinite(dip);

    if (!s.haveNorm) {
        s.norm = n;
        s.haveNorm = true;
    }
    if (!s.haveDip && dipValid) {
        s.dip = dip;
        s.haveDip = true;
    }
    const bool normOk = std::abs(n - s.norm) < params_.normTolerance * s.norm;
    const bool dipOk = !dipValid || !s.haveDip || std::abs(dip - s.dip) < params_.dipTolerance;
    const double k = lowPassGain(dt, params_.tau);
    if (normOk && dipOk) {
        s.norm += k * (n - s.norm);
        if (dipValid) s.dip += k * (dip - s.dip);
        s.disturbedTime = 0.0;
        s.candidateTime = 0.0;
        return true;
    }

    // Disturbed. A field that stays different but steady long enough is the new normal
    // (e.g. the user moved to another room): track it as a candidate and adopt it.
    s.disturbedTime += dt;
    if (s.candidateTime == 0.0) {
        s.candidateNorm = n;
        s.candidateDip = dipValid ? dip : 0.0;
        s.candidateDipValid = dipValid;
    }
    const bool steady = std::abs(n - s.candidateNorm) < params_.normTolerance * s.candidateNorm
        && (!dipValid || !s.candidateDipValid || std::abs(dip - s.candidateDip) < params_.dipTolerance);
    if (!steady) {
        s.candidateTime = 0.0;
        return false;
    }
    const double kc = lowPassGain(dt, params_.candidateTau);
    s.candidateNorm += kc * (n - s.candidateNorm);
    if (dipValid) {
        s.candidateDip = s.candidateDipValid ? s.candidateDip + kc * (dip - s.candidateDip) : dip;
        s.candidateDipValid = true;
    }
    s.candidateTime += dt;
    if (s.candidateTime >= params_.newFieldTime) {
        s.norm = s.candidateNorm;
        if (s.candidateDipValid) {
            s.dip = s.candidateDip;
            s.haveDip = true;
        }
        s.candidateTime = 0.0;
        s.disturbedTime = 0.0;
        return true;
    }
    return false;
}

} // namespace armadillo::fusion

namespace armadillo::fusion {

void ButterworthLowPass3::setup(double tau, double dt)
{
    tau_ = tau;
    dt_ = dt;
    if (!(tau > 0.0) || !(dt > 0.0)) {   // pass-through
        b0_ = 1.0;
        b1_ = b2_ = a1_ = a2_ = 0.0;
        return;
    }
    const double fc = std::sqrt(2.0) / (2.0 * core::kPi * tau);
    const double k = std::tan(core::kPi * std::min(fc * dt, 0.45)); // pre-warped, below Nyquist
    const double q = std::sqrt(2.0);                             // 1/Q of a Butterworth pair
    const double norm = 1.0 / (1.0 + q * k + k * k);
    b0_ = k * k * norm;
    b1_ = 2.0 * b0_;
    b2_ = b0_;
    a1_ = 2.0 * (k * k - 1.0) * norm;
    a2_ = (1.0 - q * k + k * k) * norm;
}

void ButterworthLowPass3::prime(const Eigen::Vector3d& steady)
{
    // Steady state of direct form II transposed for a constant input x: y = x.
    s2_ = (b2_ - a2_) * steady;
    s1_ = (b1_ - a1_) * steady + s2_;
    primed_ = true;
}

Eigen::Vector3d ButterworthLowPass3::filter(const Eigen::Vector3d& x)
{
    if (!primed_) {
        const double k = static_cast<double>(count_);
        sum0_ += x;
        sum1_ += k * x;
        sum2_ += (k * k) * x;
        ++count_;
        const double n = static_cast<double>(count_);
        const Eigen::Vector3d mean = tapered_ ? Eigen::Vector3d((n * (sum1_ + sum0_) - (sum2_ + sum1_)) / (n * (n + 1.0) * (n + 2.0) / 6.0))
                                              : Eigen::Vector3d(sum0_ / n);
        if (static_cast<double>(count_) * dt_ < tau_) return mean;
        prime(mean);
        return mean;
    }
    const Eigen::Vector3d y = b0_ * x + s1_;
    s1_ = b1_ * x - a1_ * y + s2_;
    s2_ = b2_ * x - a2_ * y;
    return y;
}


// --- GyroDriftBias ------------------------------------------------------------------------------

void GyroDriftBias::start(const Eigen::Vector3d& b0, double seconds)
{
    rows_.clear();
    rows_.reserve(capacity_);   // a copied estimator's buffer has only its size
    lastAccel_.setConstant(core::kNaN);
    lastMag_.setConstant(core::kNaN);
    R_.setIdentity();
    A_.setZero();
    b0_ = b0;
    age_ = 0.0;
    length_ = seconds;
    estimated_ = false;
}

bool GyroDriftBias::update(double dt, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, const Eigen::Vector3d& mag)
{
    if (!(length_ > 0.0) || !(dt > 0.0) || !gyro.allFinite() || !accel.allFinite() || !(accel.norm() > 0.0)) return false;
    if (!rows_.empty()) {
        A_ += R_.toRotationMatrix() * dt;
        R_ = (R_ * quat::exp((gyro - b0_) * dt)).normalized();
    }
    age_ += dt;
    const bool field = mag.allFinite() && mag.norm() > 0.0;
    // A sample whose magnitude is off 1 g carries linear acceleration (a punch, a swing's pull):
    // its direction says nothing trustworthy about gravity's drift.
    // A reading repeated exactly is a held one (a stream slower than the gyro's, a lost message):
    // it was taken earlier than this row's turn, so it is left out too.
    const bool gravity = std::abs(accel.norm() - core::kStandardGravity) <= accelTolerance_ * core::kStandardGravity && accel != lastAccel_;
    lastAccel_ = accel;
    const bool freshField = field && mag != lastMag_;
    lastMag_ = mag;
    const Eigen::Vector3d rate = gyro - b0_, up = accel.normalized();
    const Eigen::Vector3d north = field ? Eigen::Vector3d(mag.normalized()) : Eigen::Vector3d::Zero();
    rows_.push_back(Row {A_, R_ * up, R_ * north, R_ * rate.cross(up), R_ * rate.cross(north), freshField, gravity});
    if (age_ < length_ && rows_.size() < capacity_) return false;
    solve();
    length_ = 0.0;
    return true;
}

void GyroDriftBias::solve()
{
    estimated_ = false;
    Eigen::Vector3d gSum = Eigen::Vector3d::Zero(), fSum = Eigen::Vector3d::Zero();
    std::size_t ng = 0, nf = 0;
    for (const Row& r : rows_) {
        if (r.gravity) {
            gSum += r.u;
            ++ng;
        }
        if (r.field) {
            fSum += r.v;
            ++nf;
        }
    }
    const bool useGravity = ng >= 16, useField = nf >= 16;
    if (!useGravity && !useField) return;
    const Eigen::Vector3d g = useGravity ? Eigen::Vector3d(gSum.normalized()) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d f = useField ? Eigen::Vector3d(fSum.normalized()) : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d G = quat::skew(g), F = quat::skew(f);
    // Unknowns (g', f', e, δ): u = g' − G A e + δ c_u, v = f' − F A e + δ c_v. δ is the time by
    // which the gyro-only frame runs ahead of the samples it turns (a sampling convention, a
    // stream's offset): the turn between them, c = R (ω × sample), is no bias. Two passes:
    // unweighted, then each sensor weighed by its residuals' variance (inflated for their correlation).
    constexpr int kN = 10;
    using Vec = Eigen::Matrix<double, kN, 1>;
    using Mat = Eigen::Matrix<double, kN, kN>;
    double wu = 1.0, wv = 1.0;
    Mat N;
    Vec x = Vec::Zero();
    auto rowU = [&](const Row& r) {
        Eigen::Matrix<double, 3, kN> X = Eigen::Matrix<double, 3, kN>::Zero();
        X.block<3, 3>(0, 0).setIdentity();
        X.block<3, 3>(0, 6) = -G * r.A;
        X.col(9) = r.cu;
        return X;
    };
    auto rowV = [&](const Row& r) {
        Eigen::Matrix<double, 3, kN> X = Eigen::Matrix<double, 3, kN>::Zero();
        X.block<3, 3>(0, 3).setIdentity();
        X.block<3, 3>(0, 6) = -F * r.A;
        X.col(9) = r.cv;
        return X;
    };
    // Residual variance and lag-1 correlation of one sensor's rows; its weight from them.
    struct Residuals {
        double sum2 = 0.0, lag1 = 0.0;
        Eigen::Vector3d prev = Eigen::Vector3d::Zero();
        bool havePrev = false;
        void add(const Eigen::Vector3d& r)
        {
            sum2 += r.squaredNorm();
            if (havePrev) lag1 += r.dot(prev);
            prev = r;
            havePrev = true;
        }
        double weight(std::size_t count) const
        {
            const double var = sum2 / std::max(1.0, 2.0 * static_cast<double>(count) - 5.0) + 1e-18;   // 2 of 3 components carry information
            const double rho = std::clamp(lag1 / (sum2 + 1e-300), 0.0, 0.999);
            return 1.0 / (var * (1.0 + rho) / (1.0 - rho));
        }
    };
    for (int pass = 0; pass < 2; ++pass) {
        N.setZero();
        Vec y = Vec::Zero();
        auto accumulate = [&](const Eigen::Matrix<double, 3, kN>& X, const Eigen::Vector3d& obs, double w) {
            N.noalias() += w * X.transpose() * X;
            y.noalias() += w * X.transpose() * obs;
        };
        for (const Row& r : rows_) {
            if (useGravity && r.gravity) accumulate(rowU(r), r.u, wu);
            if (useField && r.field) accumulate(rowV(r), r.v, wv);
        }
        if (!useField) N.block<3, 3>(3, 3).setIdentity();
        if (!useGravity) N.block<3, 3>(0, 0).setIdentity();
        N.diagonal().array() += 1e-12 * (N.trace() / kN + 1e-300);
        const Eigen::LDLT<Mat> ldlt(N);
        x = ldlt.solve(y);
        if (!x.allFinite()) return;
        if (pass == 1) {
            const Mat C = ldlt.solve(Mat::Identity());
            cov_ = C.block<3, 3>(6, 6);
            cov_ = 0.5 * (cov_ + cov_.transpose());
            bias_ = b0_ + x.segment<3>(6);
            estimated_ = cov_.allFinite() && bias_.allFinite();
            return;
        }
        Residuals gravity, field;
        for (const Row& r : rows_) {
            if (useGravity && r.gravity) gravity.add(r.u - rowU(r) * x);
            if (useField && r.field) field.add(r.v - rowV(r) * x);
        }
        wu = useGravity ? gravity.weight(ng) : 0.0;
        wv = useField ? field.weight(nf) : 0.0;
    }
}

} // namespace armadillo::fusion
