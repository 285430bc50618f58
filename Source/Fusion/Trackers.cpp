#include "Fusion/Trackers.h"
#include "Core/Types.h"
#include <algorithm>
#include <cmath>

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

} // namespace armadillo::fusion
