#include "Fusion/OrientationFilter.h"
#include "Core/Pose.h"
#include <algorithm>
#include <cmath>

namespace armadillo {

const OrientationFilter::Params& OrientationFilter::defaultParams()
{
    static const Params p {};
    return p;
}

bool orientationFromVectors(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag, Eigen::Quaterniond& q)
{
    q = Eigen::Quaterniond::Identity();
    const double na = accel.norm();
    if (!accel.allFinite() || !(na > 0.0)) return false;
    const Eigen::Vector3d up = accel / na;   // specific force at rest points up
    Eigen::Vector3d north;
    const Eigen::Vector3d mh = mag.allFinite() ? Eigen::Vector3d(mag - mag.dot(up) * up) : Eigen::Vector3d::Zero();
    if (mag.allFinite() && mh.norm() > 0.05 * mag.norm()) {
        north = mh.normalized();
    } else {
        // No usable field: put the forearm axis (or, if it is vertical, the face normal) north.
        Eigen::Vector3d x = Eigen::Vector3d::UnitX() - up.x() * up;
        if (x.norm() < 0.1) x = Eigen::Vector3d::UnitY() - up.y() * up;
        north = x.normalized();
    }
    const Eigen::Vector3d east = north.cross(up);
    Eigen::Matrix3d R;   // rows: earth axes (X east, Y up, Z south) in device coordinates
    R.row(0) = east.transpose();
    R.row(1) = up.transpose();
    R.row(2) = (-north).transpose();
    q = quat::normalised(Eigen::Quaterniond(R));
    return true;
}

OrientationFilter::OrientationFilter(const Params& p)
    : params_(p), ukf_(p.ukf), biasTracker_(p.bias), fieldTracker_(p.field)
{
    reset();
}

void OrientationFilter::reset()
{
    ukf_ = SquareRootUkf<OrientationSpace>(params_.ukf);
    biasTracker_.reset();
    fieldTracker_.reset();
    accelLowPass_.reset();
    magLowPass_.reset();
    lowPassDt_ = 0.0;
    lastT_ = 0.0;
    initialised_ = false;
    skipped_ = 0;
    magRejected_ = 0;
}

Eigen::Quaterniond OrientationFilter::orientation() const
{
    return initialised_ ? ukf_.state().q : restOrientation();
}

Eigen::Vector3d OrientationFilter::angularVelocity() const
{
    return initialised_ ? ukf_.state().rate : Eigen::Vector3d::Zero();
}

Eigen::Vector3d OrientationFilter::gyroBias() const { return ukf_.state().bias; }

void OrientationFilter::initialise(const ImuSample& s)
{
    OrientationState x;
    const bool useMag = params_.useMagnetometer && s.mag.allFinite();
    orientationFromVectors(s.accel, useMag ? s.mag : Eigen::Vector3d(kNaN, kNaN, kNaN), x.q);
    x.rate = s.gyro;
    Eigen::Matrix<double, kErrDim, 1> sd;
    // The error angle is in the device frame; tilt and heading are earth-frame ideas, so the
    // initial rotation spread is the larger of the two on every axis (it shrinks within seconds).
    const double rot = useMag ? std::max(params_.initialTiltStd, params_.initialHeadingStd) : params_.initialTiltStd;
    sd.segment<3>(kErrRotation).setConstant(rot);
    sd.segment<3>(kErrRate).setConstant(params_.initialRateStd);
    sd.segment<3>(kErrAccel).setConstant(params_.initialAngularAccelStd);
    sd.segment<3>(kErrBias).setConstant(params_.initialBiasStd);
    ukf_.reset(x, sd.asDiagonal().toDenseMatrix());
    lastT_ = s.t;
    initT_ = s.t;
    initialised_ = true;
    restartInertialFrame();
    if (useMag) fieldTracker_.update(s.accel, s.mag, 0.0);
}

void OrientationFilter::restartInertialFrame()
{
    inertial_ = ukf_.state().q;
    accelLowPass_.reset();
    magLowPass_.reset();
}

void OrientationFilter::setupLowPass(double dt)
{
    // Right after initialisation the gyro bias is not known yet, so the gyro-only inertial frame
    // turns, and a long low-pass there lags behind gravity: the time constants start short and
    // grow to their values over startupFilterSeconds.
    const double ramp = params_.startupFilterSeconds > 0.0
                            ? std::clamp((lastT_ - initT_) / params_.startupFilterSeconds, 0.1, 1.0)
                            : 1.0;
    // Coefficients depend on the step and the ramp; re-derived only when either changes by > 1 %.
    if (lowPassDt_ > 0.0 && std::abs(dt - lowPassDt_) < 0.01 * lowPassDt_ && std::abs(ramp - lowPassRamp_) < 0.01 * lowPassRamp_)
        return;
    lowPassDt_ = dt;
    lowPassRamp_ = ramp;
    accelLowPass_.setup(params_.accelFilterTau * ramp, dt);
    magLowPass_.setup(params_.magFilterTau * ramp, dt);
}

void OrientationFilter::predict(double dt)
{
    double integrateDt = dt, noiseDt = dt;
    if (dt > params_.maxGap) {
        // Nothing is known about the motion inside a long gap: do not extrapolate ω over it,
        // forget ω and α, and widen the covariance as the (capped) elapsed time says.
        ukf_.state().rate.setZero();
        ukf_.state().accel.setZero();
        integrateDt = 0.0;
        noiseDt = std::min(dt, params_.maxGapNoiseTime);
    }
    Eigen::Matrix<double, kErrDim, 1> sd;
    const double r = std::sqrt(noiseDt);
    sd.segment<3>(kErrRotation).setConstant(params_.rotationNoise * r);
    sd.segment<3>(kErrRate).setConstant(params_.rateNoise * r);
    sd.segment<3>(kErrAccel).setConstant(params_.angularAccelNoise * r);
    sd.segment<3>(kErrBias).setConstant(params_.biasNoise * r);
    // The process model neither reads nor changes the gyro bias: its sigma points need no f.
    ukf_.predict<kErrBias>(ConstantAccelerationModel {integrateDt}, sd);
}

void OrientationFilter::updateGravity(const Eigen::Vector3d& accel, double rawNorm)
{
    const double n = accel.norm();
    if (!(n > 0.0) || !std::isfinite(n) || !std::isfinite(rawNorm)) return;
    // Linear and centripetal acceleration are not modelled (thesis §2.7.7): they show as a norm
    // away from 1 g, so the noise grows with that distance, and the soft gate catches the rest.
    const double deviation = std::abs(rawNorm - kStandardGravity) / kStandardGravity;
    const double sd = params_.gravityNoise * (1.0 + params_.gravityNormGain * deviation);
    ukf_.update<3, 3>(Eigen::Vector3d(accel / n), GravityObservation {}, Eigen::Vector3d::Constant(sd),
                   params_.gravityNisLimit);
}

void OrientationFilter::updateHeading(const Eigen::Vector3d& mag)
{
    const Eigen::Quaterniond& q = ukf_.state().q;
    Eigen::Vector3d me = quat::rotate(q, mag);
    const double total = me.norm();
    me.y() = 0.0;   // keep the horizontal part only: heading information, no tilt information
    if (!(me.norm() > params_.minHorizontalField * total)) return;
    HeadingObservation h;
    h.horizontalField = quat::rotateInverse(q, me.normalized());
    // Angles wrap at ±π: a prior more than 90° off would straddle the cut; never the case after
    // initialisation from the same magnetometer unless the field is disturbed, so it is skipped.
    const double prior = h(ukf_.state())(0);
    if (std::abs(prior) > 0.5 * kPi) {
        ++magRejected_;
        return;
    }
    ukf_.update<1, 3>(Eigen::Matrix<double, 1, 1>(0.0), h, Eigen::Matrix<double, 1, 1>(params_.headingNoise),
                   params_.headingNisLimit);
}

void OrientationFilter::update(const ImuSample& s)
{
    if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite() || !(s.accel.norm() > 0.0)) {
        ++skipped_;
        return;
    }
    if (!initialised_) {
        initialise(s);
        return;
    }
    const double dt = s.t - lastT_;
    if (!(dt > 0.0)) {
        ++skipped_;
        return;
    }
    lastT_ = s.t;

    const bool rest = biasTracker_.update(s.gyro, s.accel, dt);
    if (dt > params_.maxGap) restartInertialFrame();
    else inertial_ = (inertial_ * quat::exp((s.gyro - ukf_.state().bias) * dt)).normalized();
    setupLowPass(dt);
    // Gyro (ω + b) and bias observations are linear: exact updates without sigma points.
    const Eigen::Vector3d gyroStd = Eigen::Vector3d::Constant(params_.gyroNoise);
    Eigen::Matrix<double, 3, kErrDim> gyroH = Eigen::Matrix<double, 3, kErrDim>::Zero();
    gyroH.block<3, 3>(0, kErrRate).setIdentity();
    gyroH.block<3, 3>(0, kErrBias).setIdentity();
    auto gyroUpdate = [&] { ukf_.updateLinear<3>(s.gyro - GyroObservation {}(ukf_.state()), gyroH, gyroStd); };
    if (params_.gyroCoversPrecedingInterval && dt <= params_.maxGap) {
        gyroUpdate();
        predict(dt);
    } else {
        predict(dt);
        gyroUpdate();
    }
    if (rest) {
        Eigen::Matrix<double, 3, kErrDim> biasH = Eigen::Matrix<double, 3, kErrDim>::Zero();
        biasH.block<3, 3>(0, kErrBias).setIdentity();
        ukf_.updateLinear<3>(biasTracker_.bias() - BiasObservation {}(ukf_.state()), biasH,
                             Eigen::Vector3d::Constant(params_.biasObservationNoise));
    }
    const double accelNorm = s.accel.norm();
    const Eigen::Vector3d accelSmooth =
        quat::rotateInverse(inertial_, accelLowPass_.filter(quat::rotate(inertial_, s.accel)));
    updateGravity(accelSmooth, accelNorm);

    if (params_.useMagnetometer && s.mag.allFinite()) {
        if (fieldTracker_.update(s.accel, s.mag, dt))
            updateHeading(quat::rotateInverse(inertial_, magLowPass_.filter(quat::rotate(inertial_, s.mag))));
        else
            ++magRejected_;
    }
}

} // namespace armadillo
