#include "Fusion/OrientationFilter.h"
#include "Core/Pose.h"
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace armadillo::fusion {

const OrientationFilter::Params& OrientationFilter::defaultParams()
{
    static const Params p {};
    return p;
}

namespace {
using Params = OrientationFilter::Params;
struct NumericParameter {
    const char* name;
    double& (*member)(Params&);
};
struct BoolParameter {
    const char* name;
    bool& (*member)(Params&);
};
// Every numeric parameter by its member name (tuning and cross-validation: `armadillo fuse --param`).
const NumericParameter kNumeric[] = {
        {"rotationNoise", [](Params& p) -> double& { return p.rotationNoise; }},
        {"rateNoise", [](Params& p) -> double& { return p.rateNoise; }},
        {"angularAccelNoise", [](Params& p) -> double& { return p.angularAccelNoise; }},
        {"biasNoise", [](Params& p) -> double& { return p.biasNoise; }},
        {"shockThreshold", [](Params& p) -> double& { return p.shockThreshold; }},
        {"shockRotationNoise", [](Params& p) -> double& { return p.shockRotationNoise; }},
        {"gyroNoise", [](Params& p) -> double& { return p.gyroNoise; }},
        {"accelFilterTau", [](Params& p) -> double& { return p.accelFilterTau; }},
        {"magFilterTau", [](Params& p) -> double& { return p.magFilterTau; }},
        {"magDisagreementTau", [](Params& p) -> double& { return p.magDisagreementTau; }},
        {"outputLead", [](Params& p) -> double& { return p.outputLead; }},
        {"startupFilterSeconds", [](Params& p) -> double& { return p.startupFilterSeconds; }},
        {"driftBiasWindow", [](Params& p) -> double& { return p.driftBiasWindow; }},
        {"driftBiasWindows", [](Params& p) -> double& { return p.driftBiasWindows; }},
        {"driftBiasMaxWindow", [](Params& p) -> double& { return p.driftBiasMaxWindow; }},
        {"driftBiasProof", [](Params& p) -> double& { return p.driftBiasProof; }},
        {"driftBiasNisLimit", [](Params& p) -> double& { return p.driftBiasNisLimit; }},
        {"gravityNoise", [](Params& p) -> double& { return p.gravityNoise; }},
        {"youngAverageVelocity", [](Params& p) -> double& { return p.youngAverageVelocity; }},
        {"youngMaxVelocity", [](Params& p) -> double& { return p.youngMaxVelocity; }},
        {"youngMotionTime", [](Params& p) -> double& { return p.youngMotionTime; }},
        {"youngSpreadFloor", [](Params& p) -> double& { return p.youngSpreadFloor; }},
        {"reacquireRepeat", [](Params& p) -> double& { return p.reacquireRepeat; }},
        {"rangeTau", [](Params& p) -> double& { return p.rangeTau; }},
        {"leverArmTau", [](Params& p) -> double& { return p.leverArmTau; }},
        {"leverArmPrior", [](Params& p) -> double& { return p.leverArmPrior; }},
        {"hardIronTau", [](Params& p) -> double& { return p.hardIronTau; }},
        {"hardIronPrior", [](Params& p) -> double& { return p.hardIronPrior; }},
        {"gravityNormGain", [](Params& p) -> double& { return p.gravityNormGain; }},
        {"gravityNisLimit", [](Params& p) -> double& { return p.gravityNisLimit; }},
        {"headingNoise", [](Params& p) -> double& { return p.headingNoise; }},
        {"headingNisLimit", [](Params& p) -> double& { return p.headingNisLimit; }},
        {"biasObservationNoise", [](Params& p) -> double& { return p.biasObservationNoise; }},
        {"initialTiltStd", [](Params& p) -> double& { return p.initialTiltStd; }},
        {"initialHeadingStd", [](Params& p) -> double& { return p.initialHeadingStd; }},
        {"initialBiasStd", [](Params& p) -> double& { return p.initialBiasStd; }},
        {"reacquireAccelTolerance", [](Params& p) -> double& { return p.reacquireAccelTolerance; }},
        {"maxBridge", [](Params& p) -> double& { return p.maxBridge; }},
        {"reacquireWindow", [](Params& p) -> double& { return p.reacquireWindow; }},
        {"reacquireHeadingNoise", [](Params& p) -> double& { return p.reacquireHeadingNoise; }},
        {"disagreementTime", [](Params& p) -> double& { return p.disagreementTime; }},
        {"acquireDisagreementTime", [](Params& p) -> double& { return p.acquireDisagreementTime; }},
        {"acquireRotationNoise", [](Params& p) -> double& { return p.acquireRotationNoise; }},
        {"acquireTime", [](Params& p) -> double& { return p.acquireTime; }},
        {"headingDisagreement", [](Params& p) -> double& { return p.headingDisagreement; }},
        {"headingConsistency", [](Params& p) -> double& { return p.headingConsistency; }},
        {"tiltDisagreement", [](Params& p) -> double& { return p.tiltDisagreement; }},
        {"minHorizontalField", [](Params& p) -> double& { return p.minHorizontalField; }},
        {"bias.restGyroDeviation", [](Params& p) -> double& { return p.bias.restGyroDeviation; }},
        {"bias.restAccelDeviation", [](Params& p) -> double& { return p.bias.restAccelDeviation; }},
        {"bias.restFilterTau", [](Params& p) -> double& { return p.bias.restFilterTau; }},
        {"bias.minRestTime", [](Params& p) -> double& { return p.bias.minRestTime; }},
        {"field.tau", [](Params& p) -> double& { return p.field.tau; }},
        {"field.accelTolerance", [](Params& p) -> double& { return p.field.accelTolerance; }},
        {"field.normTolerance", [](Params& p) -> double& { return p.field.normTolerance; }},
        {"field.dipTolerance", [](Params& p) -> double& { return p.field.dipTolerance; }},
        {"field.newFieldTime", [](Params& p) -> double& { return p.field.newFieldTime; }},
        {"field.candidateTau", [](Params& p) -> double& { return p.field.candidateTau; }},
};
const BoolParameter kBool[] = {
        {"shockRestartsFieldLowPass", [](Params& p) -> bool& { return p.shockRestartsFieldLowPass; }},
        {"accelTaperedStart", [](Params& p) -> bool& { return p.accelTaperedStart; }},
        {"useMagnetometer", [](Params& p) -> bool& { return p.useMagnetometer; }},
        {"reacquireFieldVector", [](Params& p) -> bool& { return p.reacquireFieldVector; }},
        {"acquireHoldAfterGap", [](Params& p) -> bool& { return p.acquireHoldAfterGap; }},
        {"reacquireKeepField", [](Params& p) -> bool& { return p.reacquireKeepField; }},
        {"acquireFieldVector", [](Params& p) -> bool& { return p.acquireFieldVector; }},
        {"youngCorrelated", [](Params& p) -> bool& { return p.youngCorrelated; }},
        {"gyroCoversPrecedingInterval", [](Params& p) -> bool& { return p.gyroCoversPrecedingInterval; }},
};
} // namespace

bool OrientationFilter::setParameter(Params& p, const std::string& name, double value)
{
    for (const NumericParameter& n : kNumeric)
        if (name == n.name) {
            n.member(p) = value;
            return true;
        }
    for (const BoolParameter& b : kBool)
        if (name == b.name) {
            b.member(p) = value != 0.0;
            return true;
        }
    return false;
}

std::vector<std::string> OrientationFilter::parameterNames()
{
    std::vector<std::string> out;
    for (const NumericParameter& n : kNumeric) out.emplace_back(n.name);
    for (const BoolParameter& b : kBool) out.emplace_back(b.name);
    return out;
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
    : params_(p), ukf_(p.ukf), biasTracker_(p.bias), fieldTracker_(p.field), gaps_(p.gap)
{
    accelLowPass_.setTaperedStart(p.accelTaperedStart);
    reset();
}

void OrientationFilter::reset()
{
    ukf_ = SquareRootUkf<AttitudeSpace>(params_.ukf);
    biasTracker_.reset();
    fieldTracker_.reset();
    accelLowPass_.reset();
    magLowPass_.reset();
    magFastLowPass_.reset();
    lowPassDt_ = 0.0;
    lastT_ = 0.0;
    lastAccel_.setConstant(core::kNaN);
    lastGyro_.setConstant(core::kNaN);
    gaps_ = core::GapDetector(params_.gap);
    headingDisagreeT_ = tiltDisagreeT_ = 0.0;
    reacquirePending_ = false;
    afterGap_ = false;
    driftBiasActive_ = false;
    hardIronW_ = 0.0;
    hardIronR_.setZero();
    hardIronRm_.setZero();
    hardIronM_.setZero();
    leverH_.setZero();
    leverY_.setZero();
    rangeW_ = 0.0;
    rangeR_.setZero();
    rangeAtGap_ = 1e9;
    fieldEarthAtGap_.setConstant(core::kNaN);
    magAverageInertial_.setConstant(core::kNaN);
    initialised_ = false;
    skipped_ = 0;
    magRejected_ = 0;
    recovery_ = Recovery {};
}

Eigen::Quaterniond OrientationFilter::orientation() const
{
    if (!initialised_) return core::restOrientation();
    const OrientationState& x = ukf_.state();
    if (params_.outputLead == 0.0 || !x.rate.allFinite()) return x.q;
    return quat::normalised(x.q * quat::exp(x.rate * params_.outputLead));
}

Eigen::Vector3d OrientationFilter::angularVelocity() const
{
    return initialised_ ? ukf_.state().rate : Eigen::Vector3d::Zero();
}

Eigen::Vector3d OrientationFilter::gyroBias() const { return ukf_.state().bias; }

Eigen::Vector3d OrientationFilter::hardIron() const
{
    // Ridge least squares for (m_earth, h) in m = Rᵀ m_earth + h: the ridge only on h, so that what
    // the turns do not separate is the earth's field.
    Eigen::Matrix<double, 6, 6> H;
    H.topLeftCorner<3, 3>() = (hardIronW_ + 1e-9) * Eigen::Matrix3d::Identity();
    H.topRightCorner<3, 3>() = hardIronR_;
    H.bottomLeftCorner<3, 3>() = hardIronR_.transpose();
    H.bottomRightCorner<3, 3>() = (hardIronW_ + params_.hardIronPrior) * Eigen::Matrix3d::Identity();
    Eigen::Matrix<double, 6, 1> y;
    y << hardIronRm_, hardIronM_;
    const Eigen::Matrix<double, 6, 1> x = H.ldlt().solve(y);
    return x.allFinite() ? Eigen::Vector3d(x.tail<3>()) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d OrientationFilter::leverArm() const
{
    // Ridge least squares: (Σ MᵀM + λI) r = Σ Mᵀ(a − gravity); r = 0 while the motion shows none.
    return (leverH_ + params_.leverArmPrior * Eigen::Matrix3d::Identity()).ldlt().solve(leverY_);
}

void OrientationFilter::resetCovariance(double rotationStd)
{
    // Everything about the motion is forgotten; the gyro bias is a property of the sensor and keeps
    // its own uncertainty (its cross terms with the lost orientation go with it).
    const Eigen::Matrix<double, kAttDim, kAttDim> P = ukf_.covariance();
    Eigen::Matrix<double, kAttDim, 1> sd;
    sd.segment<3>(kAttRotation).setConstant(rotationStd);
    for (int i = 0; i < 3; ++i) {
        const double b = P(kAttBias + i, kAttBias + i);
        sd(kAttBias + i) = std::isfinite(b) && b > 0.0 ? std::min(std::sqrt(b), params_.initialBiasStd) : params_.initialBiasStd;
    }
    ukf_.reset(ukf_.state(), sd.asDiagonal().toDenseMatrix());
}

void OrientationFilter::initialise(const core::ImuSample& s)
{
    OrientationState x;
    const bool useMag = params_.useMagnetometer && s.mag.allFinite();
    orientationFromVectors(s.accel, useMag ? s.mag : Eigen::Vector3d(core::kNaN, core::kNaN, core::kNaN), x.q);
    x.rate = s.gyro;
    Eigen::Matrix<double, kAttDim, 1> sd;
    // The error angle is in the device frame; tilt and heading are earth-frame ideas, so the
    // initial rotation spread is the larger of the two on every axis (it shrinks within seconds).
    const double rot = useMag ? std::max(params_.initialTiltStd, params_.initialHeadingStd) : params_.initialTiltStd;
    sd.segment<3>(kAttRotation).setConstant(rot);
    sd.segment<3>(kAttBias).setConstant(params_.initialBiasStd);
    ukf_.reset(x, sd.asDiagonal().toDenseMatrix());
    lastT_ = s.t;
    lastGyro_ = s.gyro;
    initT_ = acquireStartT_ = s.t;
    afterGap_ = false;
    lastAccel_ = s.accel;
    initialised_ = true;
    restartInertialFrame();
    if (useMag) fieldTracker_.update(s.accel, s.mag, 0.0);
    driftBiasActive_ = params_.driftBiasWindow > 0.0;
    driftBiasNext_ = params_.driftBiasWindow;
    driftBiasWindows_ = 0;
    driftPrevProved_ = false;
    if (driftBiasActive_) {
        driftBias_.setAccelTolerance(params_.field.accelTolerance);   // the same "only gravity" test as the dip's
        startDriftWindow();
        driftBias_.update(1e-9, s.gyro, s.accel, useMag ? s.mag : Eigen::Vector3d::Constant(core::kNaN));
    }
}

void OrientationFilter::startDriftWindow()
{
    driftBias_.start(ukf_.state().bias, driftBiasNext_);
    if (driftBiasWindows_ > 0) driftBiasNext_ = std::min(2.0 * driftBiasNext_, params_.driftBiasMaxWindow);   // the first two alike: the second confirms the first
}

/// The smallest earth-frame rotation that turns `q` so that the device-frame direction `upDevice`
/// points up: tilt corrected, heading kept as far as the new tilt allows.
static Eigen::Quaterniond levelled(const Eigen::Quaterniond& q, const Eigen::Vector3d& upDevice)
{
    const Eigen::Vector3d upNow = quat::rotate(q, upDevice.normalized());
    return quat::normalised(Eigen::Quaterniond::FromTwoVectors(upNow, Eigen::Vector3d::UnitY()) * q);
}

void OrientationFilter::reacquire(const core::ImuSample& s, double gap)
{
    // The orientation is unknown after a gap the filter cannot bridge: start again as at start-up.
    // Tilt from this sample when its norm says it is mostly gravity (one sample of a moving arm can
    // carry g of linear acceleration; then the prior's tilt is the better guess). Heading: the
    // prior's, until the field has been trusted for acquireDisagreementTime without a break (the
    // heading reset in updateHeading): one sample that passes the field tracker inside a disturbed
    // field would otherwise throw a good heading away.
    OrientationState& x = ukf_.state();
    // The field's steady average in the earth frame, as the state last saw it (reacquireKeepField).
    if (acquiring() <= 0.0) {
        fieldEarthAtGap_ = Eigen::Vector3d::Constant(core::kNaN);
        if (magAverageInertial_.allFinite() && magAverageInertial_.norm() > 0.0)
            fieldEarthAtGap_ = quat::rotate(x.q, quat::rotateInverse(inertial_, magAverageInertial_)).normalized();
    }
    driftBiasActive_ = false;   // the power-up drift estimate needs an unbroken gyro
    gapLength_ = gap;
    rateBeforeGap_ = x.rate.allFinite() ? x.rate.norm() : 0.0;
    reacquireTurn_ = 0.0;
    // The range the arm has been moving in: E[cos θ] of its orientations about their mean from the
    // mean rotation matrix's singular values (sign of the smallest from the determinant), θ_rms ≈
    // √(2(1 − E cos θ)); two orientations of that range are √2 × θ_rms apart.
    rangeAtGap_ = 1e9;
    if (params_.rangeTau > 0.0 && rangeW_ > 0.5) {
        const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rangeR_ / rangeW_, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Vector3d sv = svd.singularValues();
        if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) sv(2) = -sv(2);
        const double c = std::clamp(0.5 * (sv.sum() - 1.0), -1.0, 1.0);
        rangeAtGap_ = 2.0 * std::sqrt(1.0 - c);
    }
    // With the joint step the orientation before the gap is its prior, kept unlevelled (one sample
    // of a moving arm can carry g of linear acceleration in any direction within the tolerance).
    const bool step = params_.reacquireWindow > 0.0 && params_.reacquireFieldVector;
    if (!step && std::abs(s.accel.norm() - core::kStandardGravity) < params_.reacquireAccelTolerance * core::kStandardGravity)
        x.q = levelled(x.q, s.accel);
    x.rate = s.gyro - x.bias;
    x.accel.setZero();
    lastGyro_ = s.gyro;
    resetCovariance(std::max(params_.initialTiltStd, params_.initialHeadingStd));
    ++recovery_.reacquired;
    acquireStartT_ = s.t;
    reacquirePending_ = params_.reacquireWindow > 0.0;
    reacquireNextAge_ = params_.reacquireWindow;
    afterGap_ = true;
    reacquireStartT_ = s.t;
    reacquireSamples_ = reacquireFieldSamples_ = 0;
    headingDisagreeT_ = tiltDisagreeT_ = 0.0;
    restartInertialFrame();
}

void OrientationFilter::restartInertialFrame()
{
    inertial_ = ukf_.state().q;
    accelAverageStartT_ = lastT_;
    youngDv_ = 0.0;
    youngSum_.setZero();
    youngSumSq_ = youngN_ = 0.0;
    accelLowPass_.reset();
    magLowPass_.reset();
    magFastLowPass_.reset();
    magAverageInertial_.setConstant(core::kNaN);
}

void OrientationFilter::reacquireStep(const Eigen::Vector3d& up, const Eigen::Vector3d& field)
{
    if (params_.reacquireFieldVector) {
        reacquireStepJoint(up, field);
        return;
    }
    // After a gap the state is the orientation before it (levelled by the first sample): good if
    // the arm held still, anything if it turned. The young averages are a measurement of known
    // quality (tilt: the gravity noise and the Δv/T of a young average, as in updateGravity;
    // heading: reacquireHeadingNoise plus the tilt error it inherits through the field's dip). Their
    // disagreement d with the state is the state's error plus theirs, so the state's own error is
    // about √(d² − σ²), and the two combine with the weight w = (d² − σ²)/d² on the measurement:
    // a state that agrees keeps its precision, one that disagrees by far more than the averages'
    // error takes theirs. Tilt first (levelling turns least), then heading about the vertical.
    Eigen::Quaterniond q = ukf_.state().q;
    const double T = std::max(lastT_ - reacquireStartT_, 1e-3);
    const double young = youngVelocity() / (core::kStandardGravity * T);
    const double tiltVar = params_.gravityNoise * params_.gravityNoise + young * young;
    const Eigen::Vector3d upEarth = quat::rotate(q, up.normalized());
    const double tilt = std::acos(std::clamp(upEarth.y(), -1.0, 1.0));
    const double wTilt = tilt * tilt > tiltVar ? 1.0 - tiltVar / (tilt * tilt) : 0.0;
    bool moved = false;
    if (wTilt > 0.0) {
        const Eigen::AngleAxisd level(Eigen::Quaterniond::FromTwoVectors(upEarth, Eigen::Vector3d::UnitY()));
        q = quat::normalised(Eigen::Quaterniond(Eigen::AngleAxisd(wTilt * level.angle(), level.axis())) * q);
        moved = true;
    }
    // The tilt's remaining error: the combination's variance (w·σ² of the measurement's) where the
    // measurement counted, else the state's (at most the disagreement seen).
    const double tiltAfter = std::sqrt(wTilt * tiltVar + (1.0 - wTilt) * std::min(tilt * tilt, tiltVar));
    double rotationStd = tiltAfter;
    if (field.allFinite()) {
        Eigen::Vector3d me = quat::rotate(q, field);
        const double total = me.norm();
        me.y() = 0.0;
        if (me.norm() > params_.minHorizontalField * total) {
            me.normalize();
            const double turn = std::atan2(me.cross(-Eigen::Vector3d::UnitZ()).y(), -me.z());
            // A tilt error about the horizontal axis across the field turns the field's horizontal
            // part by up to tan(inclination) times as much.
            const double inclination = std::abs(std::asin(std::clamp(quat::rotate(q, field.normalized()).y(), -1.0, 1.0)));
            const double headingVar = params_.reacquireHeadingNoise * params_.reacquireHeadingNoise +
                                      std::pow(tiltAfter * std::tan(std::min(inclination, 1.4)), 2);
            const double wHeading = turn * turn > headingVar ? 1.0 - headingVar / (turn * turn) : 0.0;
            if (wHeading > 0.0) {
                q = quat::normalised(Eigen::Quaterniond(Eigen::AngleAxisd(wHeading * turn, Eigen::Vector3d::UnitY())) * q);
                moved = true;
            }
            rotationStd = std::max(rotationStd, std::sqrt(wHeading * headingVar + (1.0 - wHeading) * std::min(turn * turn, headingVar)));
        }
    }
    if (!moved) return;
    ++recovery_.reacquireSteps;
    ukf_.state().q = q;
    resetCovariance(std::clamp(rotationStd, params_.gravityNoise, std::max(params_.initialTiltStd, params_.initialHeadingStd)));
    headingDisagreeT_ = tiltDisagreeT_ = 0.0;
}

void OrientationFilter::reacquireStepJoint(const Eigen::Vector3d& up, const Eigen::Vector3d& field)
{
    // Wahba's problem (Markley's SVD solution): the rotation A (earth → device) that best maps each
    // earth-frame reference r_i onto its device-frame measurement b_i, weighted by 1/σ_i². Three
    // sources (docs/FUSION.md, "Dropouts and re-acquisition"):
    //  - the orientation before the gap, turned since by the gyro (inertial_: the gyro-only frame
    //    restarted at the gap's end from that orientation), as its three axes. Its error is the
    //    turn during the gap, which nobody measured: at most the arm's rate around the gap (before
    //    it, and the mean over the window after it) times the gap's length;
    //  - the young gravity average (up), trusted as the gravity update trusts it (Δv/T);
    //  - the young field average as a direction against the earth's field (north, dipping by the
    //    reference dip of the field tracker), trusted to reacquireHeadingNoise.
    // The information each adds about the device-frame error angle is w_i (I − b_i b_iᵀ); its
    // inverse is the rotation covariance the filter continues with.
    const double T = std::max(lastT_ - reacquireStartT_, 1e-3);
    const double young = youngVelocity() / (core::kStandardGravity * T);
    const double gravityVar = params_.gravityNoise * params_.gravityNoise + young * young;
    const double rate = std::max(rateBeforeGap_, reacquireTurn_ / T);
    const double priorStd = std::max(std::min(rate * gapLength_, rangeAtGap_), params_.gravityNoise);
    const Eigen::Quaterniond prior = inertial_;
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d info = Eigen::Matrix3d::Identity() / (priorStd * priorStd);
    auto add = [&](const Eigen::Vector3d& b, const Eigen::Vector3d& r, double w) {
        B += w * b * r.transpose();
        info += w * (Eigen::Matrix3d::Identity() - b * b.transpose());
    };
    // Each axis of the prior carries half the information of an isotropic error σ on two axes.
    const Eigen::Matrix3d Rp = prior.toRotationMatrix();   // device → earth
    for (int k = 0; k < 3; ++k) {
        const double w = 0.5 / (priorStd * priorStd);
        B += w * Rp.row(k).transpose() * Eigen::Vector3d::Unit(k).transpose();
    }
    const double un = up.norm();
    const bool haveUp = un > 0.0 && std::isfinite(un);
    const bool haveField = field.allFinite() && field.norm() > 0.0 && fieldTracker_.haveDip();
    // The young averages of gravity and of a clean field must meet at the field's reference dip
    // (the angle between up and the field, ≈ 90° + inclination); the gravity average is off by at
    // least as much as they miss it (the field's direction is good to a few degrees).
    const double dipMiss = haveUp && haveField
                               ? std::abs(std::acos(std::clamp(up.dot(field) / (un * field.norm()), -1.0, 1.0)) - fieldTracker_.referenceDip())
                               : 0.0;
    if (haveUp) add(up / un, Eigen::Vector3d::UnitY(), 1.0 / (gravityVar + dipMiss * dipMiss));
    if (haveField) {
        add(field.normalized(), acquisitionFieldReference(), 1.0 / (params_.reacquireHeadingNoise * params_.reacquireHeadingNoise));
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(B, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Vector3d d(1.0, 1.0, svd.matrixU().determinant() * svd.matrixV().determinant());
    const Eigen::Matrix3d A = svd.matrixU() * d.asDiagonal() * svd.matrixV().transpose();   // earth → device
    const Eigen::Quaterniond q = quat::normalised(Eigen::Quaterniond(Eigen::Matrix3d(A.transpose())));
    const Eigen::Matrix3d P = info.inverse();
    // A state that agrees with the answer within the answer's own spread keeps its precision.
    const Eigen::Quaterniond& now = ukf_.state().q;
    const Eigen::Vector3d e = quat::log(now.conjugate() * q);
    if (!(e.dot(info * e) > 3.0)) return;   // within the 3-dof spread of the solution
    ++recovery_.reacquireSteps;
    ukf_.state().q = q;
    // Rotation block: the solution's covariance, its spread kept within [gravityNoise, cap] per axis.
    const double cap = std::max(params_.initialTiltStd, params_.initialHeadingStd);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(P);
    Eigen::Vector3d ev = es.eigenvalues();
    for (int i = 0; i < 3; ++i) ev(i) = std::clamp(ev(i), params_.gravityNoise * params_.gravityNoise, cap * cap);
    const Eigen::Matrix3d Pc = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
    const Eigen::Matrix<double, kAttDim, kAttDim> Pold = ukf_.covariance();
    Eigen::Matrix<double, kAttDim, kAttDim> Pnew = Eigen::Matrix<double, kAttDim, kAttDim>::Zero();
    Pnew.block<3, 3>(kAttRotation, kAttRotation) = Pc;
    for (int i = 0; i < 3; ++i) {
        const double b = Pold(kAttBias + i, kAttBias + i);
        const double sd = std::isfinite(b) && b > 0.0 ? std::min(std::sqrt(b), params_.initialBiasStd) : params_.initialBiasStd;
        Pnew(kAttBias + i, kAttBias + i) = sd * sd;
    }
    ukf_.reset(ukf_.state(), Eigen::Matrix<double, kAttDim, kAttDim>(Pnew.llt().matrixL()));
    headingDisagreeT_ = tiltDisagreeT_ = 0.0;
}

void OrientationFilter::setupLowPass(double dt)
{
    // Right after initialisation the gyro bias is not known yet, so the gyro-only inertial frame
    // turns, and a long low-pass there lags behind gravity: the time constants start short and
    // grow to their values over startupFilterSeconds. After a gap or a re-acquisition the bias is
    // known: the low-pass restarts empty at its full time constant (its start-up mean, Trackers.h,
    // lets fresh samples win at once and then averages as long as the inertial frame allows).
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
    magFastLowPass_.setup(params_.magDisagreementTau * ramp, dt);
}

Eigen::Vector3d OrientationFilter::acquisitionFieldReference() const
{
    if (params_.reacquireKeepField && fieldEarthAtGap_.allFinite()) return fieldEarthAtGap_;
    const double inclination = fieldTracker_.referenceDip() - 0.5 * core::kPi;
    return {0.0, -std::sin(inclination), -std::cos(inclination)};   // north (−Z), dipping down
}

double OrientationFilter::youngVelocity() const
{
    if (params_.youngMotionTime > 0.0 && afterGap_) {
        const double var = youngN_ > 1.0 ? std::max(0.0, youngSumSq_ / youngN_ - (youngSum_ / youngN_).squaredNorm()) : 0.0;
        return std::clamp(std::sqrt(var) * params_.youngMotionTime, params_.youngSpreadFloor,
                          std::max(params_.youngSpreadFloor, params_.youngMaxVelocity));
    }
    return std::max(params_.youngAverageVelocity, std::min(youngDv_, params_.youngMaxVelocity));
}

double OrientationFilter::acquiring() const
{
    return params_.acquireTime > 0.0 ? std::max(0.0, 1.0 - (lastT_ - acquireStartT_) / params_.acquireTime) : 0.0;
}

double OrientationFilter::disagreementLimit() const
{
    return acquiring() > 0.0 ? params_.acquireDisagreementTime : params_.disagreementTime;
}

void OrientationFilter::predict(double dt, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double shock, bool bridge)
{
    Eigen::Matrix<double, kAttDim, 1> sd;
    // Acquisition noise only while the rotation spread is below the initial one: sigma points sit
    // at ±√6·σ, and a wider spread would wrap the heading angle at ±π.
    // After a gap the noise holds its full value while acquiring (acquireHoldAfterGap): the young
    // averages the state follows mature over those seconds; at start-up it fades.
    double acquiringNow = acquiring();
    if (afterGap_ && params_.acquireHoldAfterGap && acquiringNow > 0.0) acquiringNow = 1.0;
    const double cap = std::max(params_.initialTiltStd, params_.initialHeadingStd);
    const auto& S = ukf_.sqrtCovariance();
    for (int i = kAttRotation; i < kAttRotation + 3; ++i)
        if (S.row(i).squaredNorm() > cap * cap) acquiringNow = 0.0;
    const double rotation = params_.rotationNoise + acquiringNow * params_.acquireRotationNoise;
    // The gyro's own white noise turns the state too (gyroNoise·t per step). Over a bridged gap the
    // rotation is extrapolated with ω and α, and its error is that of their random changes over the
    // gap: a random walk of ω gives rateNoise²t³/3, one of α angularAccelNoise²t⁵/20.
    double var = rotation * rotation * dt + params_.gyroNoise * params_.gyroNoise * dt * dt + shock * shock;
    if (bridge)
        var += params_.rateNoise * params_.rateNoise * dt * dt * dt / 3.0 +
               params_.angularAccelNoise * params_.angularAccelNoise * dt * dt * dt * dt * dt / 20.0;
    sd.segment<3>(kAttRotation).setConstant(std::sqrt(var));
    sd.segment<3>(kAttBias).setConstant(params_.biasNoise * std::sqrt(dt));
    // Linearised (docs/FUSION.md, cost): over one step the model is linear to far below the noise.
    const OrientationState& x = ukf_.state();
    const Eigen::Vector3d delta = (gyro - x.bias) * dt + accel * (0.5 * dt * dt);
    ukf_.predictLinearised(GyroInputModel {dt, gyro, accel}, GyroInputJacobian {dt, delta}, sd);
}

void OrientationFilter::updateGravity(const Eigen::Vector3d& accel, double rawNorm, double dt, bool tiltRule, double extraStd)
{
    const double n = accel.norm();
    if (!(n > 0.0) || !std::isfinite(n) || !std::isfinite(rawNorm)) return;
    // A state that low-passed gravity contradicts for disagreementTime without a break is wrong
    // (a prior the soft gate would only nudge): level it at once and let the measurements refine.
    const Eigen::Vector3d upDevice = accel / n;
    const Eigen::Vector3d upState = quat::rotateInverse(ukf_.state().q, Eigen::Vector3d::UnitY());
    const double angle = std::acos(std::clamp(upDevice.dot(upState), -1.0, 1.0));
    tiltDisagreeT_ = tiltRule && angle > params_.tiltDisagreement ? tiltDisagreeT_ + dt : 0.0;
    if (tiltDisagreeT_ > disagreementLimit()) {
        ukf_.state().q = levelled(ukf_.state().q, upDevice);
        resetCovariance(std::max(params_.initialTiltStd, params_.initialHeadingStd));
        ++recovery_.tiltResets;
        tiltDisagreeT_ = 0.0;
    }
    // Linear and centripetal acceleration are not modelled (thesis §2.7.7): they show as a norm
    // away from 1 g, so the noise grows with that distance, and the soft gate catches the rest.
    const double deviation = std::abs(rawNorm - core::kStandardGravity) / core::kStandardGravity;
    // The low-passed direction is gravity plus the velocity change over its window divided by the
    // window: right after a restart (start-up, gap) the window is short and a moving arm's Δv/T is
    // tens of degrees, so the young average is trusted as little as that (issue 36).
    const double age = std::max(lastT_ - accelAverageStartT_, dt);
    double young = youngVelocity() / (core::kStandardGravity * age);
    // After a gap, the young average's error is one error for as long as it lasts (youngCorrelated).
    if (params_.youngCorrelated && params_.youngMotionTime > 0.0 && afterGap_ && age < params_.accelFilterTau)
        young *= std::sqrt(std::max(1.0, std::min(age, params_.youngMotionTime) / dt));
    const double base = params_.gravityNoise * (1.0 + params_.gravityNormGain * deviation);
    const double sd = std::sqrt(base * base + young * young + extraStd * extraStd);
    ukf_.update<3, 3>(upDevice, GravityObservation {}, Eigen::Vector3d::Constant(sd), params_.gravityNisLimit);
}

void OrientationFilter::updateHeading(const Eigen::Vector3d& mag, const Eigen::Vector3d& magFast, double dt)
{
    const Eigen::Quaterniond& q = ukf_.state().q;
    // The field in the earth frame, horizontal part only (heading information, no tilt information);
    // false when too little of it is horizontal.
    auto horizontal = [&](const Eigen::Vector3d& m, Eigen::Vector3d& me) {
        me = quat::rotate(q, m);
        const double total = me.norm();
        me.y() = 0.0;
        return me.norm() > params_.minHorizontalField * total;
    };
    Eigen::Vector3d me, meFast;
    if (!horizontal(mag, me) || !horizontal(magFast, meFast)) return;
    HeadingObservation h;
    h.horizontalField = quat::rotateInverse(q, me.normalized());
    const double innovation = h(ukf_.state())(0);
    // The disagreement rule watches the shorter average: a field that changed shows there within
    // seconds, while the long one (the estimate's) is still half the old field.
    const double prior = std::atan2(-meFast.x(), -meFast.z());
    // A trusted field that contradicts the heading for disagreementTime without a break wins: the
    // state turns about the vertical onto it (this also ends the lock-out of a prior more than 90°
    // off, which the update below must skip because the angle wraps at ±π).
    // Consistent means the innovation stays within headingConsistency of its mean over the run:
    // a disturbed field that slips past the field tracker wobbles as the arm turns, the earth's
    // does not.
    if (std::abs(prior) > params_.headingDisagreement &&
        (headingDisagreeT_ <= 0.0 || std::abs(prior - headingDisagreeMean_) < params_.headingConsistency)) {
        headingDisagreeMean_ = headingDisagreeT_ > 0.0 ? headingDisagreeMean_ + (prior - headingDisagreeMean_) * dt / (headingDisagreeT_ + dt) : prior;
        headingDisagreeT_ += dt;
    } else {
        headingDisagreeT_ = 0.0;
    }
    if (headingDisagreeT_ > disagreementLimit()) {
        me = meFast.normalized();
        const double turn = std::atan2(me.cross(-Eigen::Vector3d::UnitZ()).y(), -me.z());
        ukf_.state().q = quat::normalised(Eigen::Quaterniond(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitY())) * q);
        resetCovariance(std::max(params_.initialTiltStd, params_.initialHeadingStd));
        ++recovery_.headingResets;
        headingDisagreeT_ = 0.0;
        magLowPass_.reset();   // half of its average is the field that was just found wrong
        return;
    }
    if (std::abs(innovation) > 0.5 * core::kPi) {
        ++magRejected_;
        return;
    }
    ukf_.update<1, 3>(Eigen::Matrix<double, 1, 1>(0.0), h, Eigen::Matrix<double, 1, 1>(params_.headingNoise),
                   params_.headingNisLimit);
}

Eigen::Vector3d OrientationFilter::withoutTurnAcceleration(const core::ImuSample& s, double dt, bool unsteady)
{
    if (!(params_.leverArmTau > 0.0)) return s.accel;
    const Eigen::Vector3d w = s.gyro - ukf_.state().bias;
    const Eigen::Vector3d al = ukf_.state().accel;
    Eigen::Matrix3d M;   // [ω]×² + [α]×
    M << -(w.y() * w.y() + w.z() * w.z()), w.x() * w.y() - al.z(), w.x() * w.z() + al.y(),
        w.x() * w.y() + al.z(), -(w.x() * w.x() + w.z() * w.z()), w.y() * w.z() - al.x(),
        w.x() * w.z() - al.y(), w.y() * w.z() + al.x(), -(w.x() * w.x() + w.y() * w.y());
    if (!M.allFinite()) return s.accel;
    // Learned only from the steady filter (its gravity is what the residual is taken against).
    if (acquiring() <= 0.0 && !unsteady) {
        const Eigen::Vector3d lin = s.accel - quat::rotateInverse(ukf_.state().q, Eigen::Vector3d(0.0, core::kStandardGravity, 0.0));
        const double k = std::min(1.0, dt / params_.leverArmTau);
        leverH_ += k * (M.transpose() * M - leverH_);
        leverY_ += k * (M.transpose() * lin - leverY_);
    }
    // Taken off only while the accelerometer's average is young: the turn's acceleration turns with
    // the arm, and a full-length average in the inertial frame cancels it anyway.
    return lastT_ - accelAverageStartT_ < params_.accelFilterTau ? Eigen::Vector3d(s.accel - M * leverArm()) : s.accel;
}

Eigen::Vector3d OrientationFilter::withoutHardIron(const Eigen::Vector3d& mag, double dt, bool gap)
{
    if (!(params_.hardIronTau > 0.0)) return mag;
    // Learned only from the steady filter, taken off only while the averages are young.
    if (acquiring() <= 0.0 && !gap) {
        const Eigen::Matrix3d R = ukf_.state().q.toRotationMatrix();   // device → earth
        const double k = std::min(1.0, dt / params_.hardIronTau);
        hardIronW_ += k * (1.0 - hardIronW_);
        hardIronR_ += k * (R - hardIronR_);
        hardIronRm_ += k * (R * mag - hardIronRm_);
        hardIronM_ += k * (mag - hardIronM_);
    }
    return lastT_ - accelAverageStartT_ < params_.accelFilterTau ? Eigen::Vector3d(mag - hardIron()) : mag;
}

/// The power-up bias from the drift of gravity and field in a gyro-only frame (GyroDriftBias): one
/// window closes, is judged (proof, confirmation) and the next starts.
void OrientationFilter::updateDriftBias(const core::ImuSample& s, double dt, bool gap, bool shock, bool fieldTrusted)
{
    if (gap || shock) {   // a window broken by a bridged gap or a shock starts again
        driftBias_.start(ukf_.state().bias, driftBiasNext_);
    } else if (driftBias_.update(dt, s.gyro, s.accel, fieldTrusted ? s.mag : Eigen::Vector3d::Constant(core::kNaN))) {
        if (driftBias_.estimated()) {
            // Observed along the covariance's principal axes (their variances as the noise).
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(driftBias_.covariance());
            const Eigen::Vector3d var = eig.eigenvalues().cwiseMax(1e-14);
            Eigen::Matrix<double, 3, kAttDim> H = Eigen::Matrix<double, 3, kAttDim>::Zero();
            H.block<3, 3>(0, kAttBias) = eig.eigenvectors().transpose();
            const Eigen::Vector3d d = driftBias_.bias() - ukf_.state().bias;
            const Eigen::Vector3d nu = eig.eigenvectors().transpose() * d;
            // Soft gate against what the filter knows: an estimate further off than the two
            // covariances allow (χ²(3) beyond driftBiasNisLimit) has its variance inflated to that limit.
            const Eigen::Matrix3d Pb = ukf_.covariance().block<3, 3>(kAttBias, kAttBias);
            const double nis = d.dot((Pb + driftBias_.covariance()).ldlt().solve(d));
            const double inflate = std::isfinite(nis) && nis > params_.driftBiasNisLimit ? nis / params_.driftBiasNisLimit : 1.0;
            // Observed only where the window proves the filter's bias wrong (the filter's value outside
            // the window's driftBiasProof confidence region): a bias-free sensor's windows are noise.
            const double proof = d.dot(driftBias_.covariance().ldlt().solve(d));
            // ... and only when the window before it proved the same (a real bias persists; a
            // window fooled by the motion is not repeated by the next one).
            const bool proved = std::isfinite(proof) && proof >= params_.driftBiasProof;
            const Eigen::Vector3d change = driftBias_.bias() - driftPrevBias_;
            const double agreement = change.dot((driftBias_.covariance() + driftPrevCov_).ldlt().solve(change));
            const bool confirmed = proved && driftPrevProved_ && std::isfinite(agreement) && agreement < params_.driftBiasProof;
            driftPrevProved_ = proved;
            driftPrevBias_ = driftBias_.bias();
            driftPrevCov_ = driftBias_.covariance();
            if (nu.allFinite() && var.allFinite() && confirmed)
                ukf_.updateLinear<3>(nu, H, (inflate * var).cwiseSqrt());
        } else {
            driftPrevProved_ = false;   // a window that said nothing confirms nothing
        }
        if (++driftBiasWindows_ < params_.driftBiasWindows) startDriftWindow();
        else driftBiasActive_ = false;
    }
}

void OrientationFilter::update(const core::ImuSample& s)
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
    const bool gap = gaps_.step(dt);
    if (gap) {
        ++recovery_.gaps;
        recovery_.longestGap = std::max(recovery_.longestGap, dt);
    }

    const bool rest = biasTracker_.update(s.gyro, s.accel, dt);
    const bool fieldTrusted = params_.useMagnetometer && s.mag.allFinite() && fieldTracker_.update(s.accel, s.mag, dt);
    if (params_.useMagnetometer && s.mag.allFinite() && !fieldTrusted) {
        ++magRejected_;
        headingDisagreeT_ = 0.0;   // a heading reset needs an unbroken run of trusted samples
    }
    // A shock shows as a jump of the accelerometer between successive samples (NaN before the first).
    const double jump = (s.accel - lastAccel_).norm() / core::kStandardGravity;
    lastAccel_ = s.accel;
    const double shock = jump > params_.shockThreshold ? params_.shockRotationNoise * (jump - params_.shockThreshold) : 0.0;
    // The same shock turns the gyro-only frame in which the magnetometer is averaged: what the
    // low-pass has averaged so far is misplaced by the gyro's error, and it would hold the heading
    // on that error for magFilterTau. Its history is dropped (it restarts with a plain mean).
    if (shock > 0.0 && params_.shockRestartsFieldLowPass) magLowPass_.reset();
    if (gap && dt > params_.maxBridge) {
        reacquire(s, dt);
        return;
    }
    // The gyro is the process model's input (departure 12): the step turns by ω t + α t²/2 (the
    // thesis's constant-acceleration model) with ω the sample's rate less the bias and α its change
    // since the previous sample (the bias cancels there).
    if (gap) {
        // A short gap is bridged with ω and α (over ≤ maxBridge their extrapolation is good to a
        // fraction of a degree); the gyro sample after it is the rate at its end. The inertial frame
        // of the low-pass follows the same extrapolated turn, so what it has averaged is kept.
        ++recovery_.bridged;
        const Eigen::Quaterniond before = ukf_.state().q;
        const OrientationState& x = ukf_.state();
        predict(dt, x.rate + x.bias, x.accel, shock, true);
        ukf_.state().rate = s.gyro - ukf_.state().bias;
        inertial_ = quat::normalised(inertial_ * (before.conjugate() * ukf_.state().q));
    } else {
        const Eigen::Vector3d change = (s.gyro - lastGyro_) / dt;
        // The gyro-only frame turns as the state does (the same rate over the same interval).
        const Eigen::Vector3d turnRate = params_.gyroCoversPrecedingInterval || !change.allFinite() ? s.gyro : Eigen::Vector3d(0.5 * (s.gyro + lastGyro_));
        inertial_ = (inertial_ * quat::exp((turnRate - ukf_.state().bias) * dt)).normalized();
        if (change.allFinite()) ukf_.state().accel = change;
        if (params_.gyroCoversPrecedingInterval) {
            predict(dt, s.gyro, Eigen::Vector3d::Zero(), shock, false);   // α only bridges gaps
        } else {
            predict(dt, lastGyro_, ukf_.state().accel, shock, false);
            ukf_.state().rate = s.gyro - ukf_.state().bias;
        }
    }
    lastGyro_ = s.gyro;
    if (params_.rangeTau > 0.0 && acquiring() <= 0.0 && !gap) {
        const double k = std::min(1.0, dt / params_.rangeTau);
        rangeW_ += k * (1.0 - rangeW_);
        rangeR_ += k * (ukf_.state().q.toRotationMatrix() - rangeR_);
    }
    setupLowPass(dt);
    if (driftBiasActive_) updateDriftBias(s, dt, gap, shock > 0.0, fieldTrusted);
    if (rest) {
        Eigen::Matrix<double, 3, kAttDim> biasH = Eigen::Matrix<double, 3, kAttDim>::Zero();
        biasH.block<3, 3>(0, kAttBias).setIdentity();
        ukf_.updateLinear<3>(biasTracker_.bias() - BiasObservation {}(ukf_.state()), biasH,
                             Eigen::Vector3d::Constant(params_.biasObservationNoise));
    }
    // The acceleration of the turn at the lever arm, as the gyro predicts it, is not gravity.
    const Eigen::Vector3d accel = withoutTurnAcceleration(s, dt, shock > 0.0 || gap);
    const double accelNorm = accel.norm();
    if (youngDv_ < params_.youngMaxVelocity) youngDv_ += std::abs(accelNorm - core::kStandardGravity) * dt;
    const Eigen::Vector3d accelInertial = quat::rotate(inertial_, accel);
    if (params_.youngMotionTime > 0.0 && afterGap_ && lastT_ - accelAverageStartT_ < params_.accelFilterTau) {
        // The young average's samples' spread about their mean (youngVelocity).
        youngSum_ += accelInertial;
        youngSumSq_ += accelInertial.squaredNorm();
        youngN_ += 1.0;
    }
    const Eigen::Vector3d accelSmooth = quat::rotateInverse(inertial_, accelLowPass_.filter(accelInertial));
    Eigen::Vector3d inertialMag, magFast;
    if (fieldTrusted) {
        inertialMag = quat::rotate(inertial_, withoutHardIron(s.mag, dt, gap));
        magAverageInertial_ = magLowPass_.filter(inertialMag);
        magFast = quat::rotateInverse(inertial_, magFastLowPass_.filter(inertialMag));
    }
    if (reacquirePending_) {
        ++reacquireSamples_;
        if (fieldTrusted) ++reacquireFieldSamples_;
        reacquireTurn_ += (s.gyro - ukf_.state().bias).norm() * dt;
        if (lastT_ - reacquireStartT_ >= reacquireNextAge_) {
            // The field's average counts if most of the window's samples were trusted.
            const bool field = 2 * reacquireFieldSamples_ > reacquireSamples_ && magAverageInertial_.allFinite();
            reacquireStep(accelSmooth, field ? quat::rotateInverse(inertial_, magAverageInertial_)
                                             : Eigen::Vector3d::Constant(core::kNaN));
            // Again at reacquireRepeat × this age while acquiring (the averages have matured).
            reacquireNextAge_ *= params_.reacquireRepeat;
            reacquirePending_ = params_.reacquireRepeat > 1.0 && reacquireNextAge_ < params_.acquireTime;
        }
    }
    // While acquiring after a gap a trusted field is observed whole (below): it fixes the tilt
    // better than the young gravity average, so that average's disagreement is no reason to level.
    const bool fieldVector = fieldTrusted && afterGap_ && params_.acquireFieldVector && acquiring() > 0.0 && fieldTracker_.haveDip();
    // The young averages of gravity and of a clean field must meet at the field's reference dip;
    // by as much as they do not, the gravity average is off (the field's direction is good to a few
    // degrees): its error shows, at least in the plane of the two.
    double dipMiss = 0.0;
    if (fieldVector && accelSmooth.norm() > 0.0) {
        const Eigen::Vector3d f = quat::rotateInverse(inertial_, magAverageInertial_);
        dipMiss = std::abs(std::acos(std::clamp(accelSmooth.normalized().dot(f.normalized()), -1.0, 1.0)) - fieldTracker_.referenceDip());
    }
    updateGravity(accelSmooth, accelNorm, dt, !fieldVector, dipMiss);

    if (fieldTrusted) {
        if (fieldVector) {
            FieldObservation h;
            h.field = acquisitionFieldReference();
            ukf_.update<3, 3>(quat::rotateInverse(inertial_, magAverageInertial_).normalized(), h,
                              Eigen::Vector3d::Constant(params_.reacquireHeadingNoise), params_.gravityNisLimit);
        } else {
            updateHeading(quat::rotateInverse(inertial_, magAverageInertial_), magFast, dt);
        }
    }
}

} // namespace armadillo::fusion
