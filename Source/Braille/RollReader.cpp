#include "Braille/RollReader.h"
#include "Core/Pose.h"
#include "Core/Types.h"
#include <algorithm>
#include <cmath>

namespace armadillo::braille {

const char* postureName(ReadingPosture p) noexcept
{
    switch (p) {
    case ReadingPosture::Forward: return "forward";
    case ReadingPosture::Backward: return "backward";
    case ReadingPosture::Invalid: break;
    }
    return "invalid";
}

void RollReader::reset() noexcept
{
    posture_ = ReadingPosture::Invalid;
    lastValid_ = ReadingPosture::Invalid;
    anchorDeg_ = 0.0;
    quietUntil_ = -1e300;
}

namespace {
/// Angle (deg) between the forearm axis and the vertical line (up or down): 0 hanging or raised.
double tiltFromVerticalDeg(const Eigen::Vector3d& axis)
{
    return core::radToDeg(std::acos(std::clamp(std::abs(axis.y()), 0.0, 1.0)));
}
} // namespace

ReadingPosture RollReader::classify(const Eigen::Vector3d& axisIn, const RollReaderParams& p) noexcept
{
    const double n = axisIn.norm();
    if (!(n > 1e-9) || !std::isfinite(n)) return ReadingPosture::Invalid;
    const double tilt = tiltFromVerticalDeg(axisIn / n);
    if (tilt <= p.verticalZoneDeg) return ReadingPosture::Forward;
    if (90.0 - tilt <= p.horizontalZoneDeg) return ReadingPosture::Backward;
    return ReadingPosture::Invalid;
}

ReadingPosture RollReader::nextPosture(const Eigen::Vector3d& axis) const noexcept
{
    // Hysteresis on the zone edges (thesis §3.2.4): the current zone is kept until the axis is
    // zoneHysteresisDeg beyond its limit, and a new zone is entered only that far inside it.
    const double tilt = tiltFromVerticalDeg(axis);
    const double h = params_.zoneHysteresisDeg;
    const double vLimit = params_.verticalZoneDeg + (posture_ == ReadingPosture::Forward ? h : -h);
    const double hLimit = params_.horizontalZoneDeg + (posture_ == ReadingPosture::Backward ? h : -h);
    if (tilt <= vLimit) return ReadingPosture::Forward;
    if (90.0 - tilt <= hLimit) return ReadingPosture::Backward;
    return ReadingPosture::Invalid;
}

double RollReader::rollAngle(ReadingPosture posture, const Eigen::Vector3d& axisIn, const Eigen::Vector3d& normalIn) noexcept
{
    const Eigen::Vector3d axis = axisIn.normalized();
    const Eigen::Vector3d normal = normalIn.normalized();
    if (posture == ReadingPosture::Forward) {
        // Thesis §4.3.1: the normal's projection on the horizontal X–Z plane, as a heading
        // clockwise from magnetic north (−Z). With the arm hanging the normal is near horizontal.
        const double h = std::hypot(normal.x(), normal.z());
        if (!(h > 1e-6)) return core::kNaN;
        return core::radToDeg(std::atan2(normal.x(), -normal.z()));
    }
    if (posture == ReadingPosture::Backward) {
        // The normal's rotation about the forearm axis, from "up" projected perpendicular to it;
        // right-handed about the axis = clockwise looking from elbow to hand (the Pose roll sign).
        const Eigen::Vector3d up = Eigen::Vector3d::UnitY() - axis.y() * axis;
        const double upNorm = up.norm();
        if (!(upNorm > 1e-6)) return core::kNaN;
        const Eigen::Vector3d u = up / upNorm;
        return core::radToDeg(std::atan2(u.cross(normal).dot(axis), u.dot(normal)));
    }
    return core::kNaN;
}

RollUpdate RollReader::update(double t, const Eigen::Vector3d& axisIn, const Eigen::Vector3d& normalIn, bool valid) noexcept
{
    RollUpdate out;
    const double an = axisIn.norm(), nn = normalIn.norm();
    if (!valid || !(an > 1e-9) || !(nn > 1e-9) || !std::isfinite(an) || !std::isfinite(nn) || !std::isfinite(t)) {
        posture_ = ReadingPosture::Invalid;
        return out;
    }
    const Eigen::Vector3d axis = axisIn / an;
    const Eigen::Vector3d normal = normalIn / nn;

    const ReadingPosture next = nextPosture(axis);
    const double angle = rollAngle(next, axis, normal);
    if (next == ReadingPosture::Invalid || !std::isfinite(angle)) {
        posture_ = ReadingPosture::Invalid;
        return out;
    }
    out.posture = next;
    out.rollDeg = angle;
    if (next != posture_) {
        // Entering a reading zone: the thresholds are armed around where the arm is now, so the
        // move into the zone itself never reads as a roll.
        out.directionChanged = lastValid_ != ReadingPosture::Invalid && lastValid_ != next;
        posture_ = next;
        lastValid_ = next;
        anchorDeg_ = angle;
        return out;
    }
    out.turnDeg = core::wrapDeg180(angle - anchorDeg_);
    if (t < quietUntil_) return out;
    if (std::abs(out.turnDeg) >= params_.stepDeg) {
        out.advanced = true;
        anchorDeg_ = angle;
        quietUntil_ = t + params_.deadTime;
    }
    return out;
}

RollUpdate RollReader::update(const core::ArmState& arm) noexcept
{
    const Eigen::Quaterniond q = arm.q.normalized();
    return update(arm.t, q * Eigen::Vector3d::UnitX(), q * Eigen::Vector3d::UnitY(), arm.valid && std::isfinite(q.w()));
}

} // namespace armadillo::braille
