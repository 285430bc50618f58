#include "Link/Motion.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include <algorithm>
#include <cmath>
#include <random>

namespace armadillo::link {

Eigen::Vector3d angularVelocity(const Eigen::Quaterniond& q0, const Eigen::Quaterniond& q1, double h)
{
    // q1 = q0 · δ with δ a turn about device axes: ω_device = axis · angle / h.
    Eigen::Quaterniond d = q0.conjugate() * q1;
    if (d.w() < 0.0) d.coeffs() = -d.coeffs();
    const double s = d.vec().norm();
    if (s < 1e-15) return Eigen::Vector3d::Zero();
    const double angle = 2.0 * std::atan2(s, d.w());
    return d.vec() / s * (angle / h);
}

namespace {
constexpr double kPunchCycle = 60.0;   // s
constexpr double kPunchLength = 0.12;  // s: the push
constexpr double kPunchPeak = 1.5 * 9.80665;
// The fist then stops: a half-sine against the push with the same area, so the velocity is back
// to zero. Until issue 49 there was no stop, and every punch left the arm 1.1 m/s faster for good:
// an accelerometer average then leaned by Δv/T for seconds after each one, which no arm does (a
// slower 0.375 g stop over 480 ms was tried too: a long lean of its own, harder than any real one).
constexpr double kBrakeLength = 0.12;  // s (as sharp as the push: a fist stops as it started)
constexpr double kBrakePeak = kPunchPeak * kPunchLength / kBrakeLength;
} // namespace

WanderingMotion::WanderingMotion(std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> phase(0.0, 2.0 * core::kPi);
    for (double& p : phase_) p = phase(rng);
    std::uniform_real_distribution<double> gap(2.0, 6.0);
    for (double t = 1.5; t < kPunchCycle - 1.0; t += gap(rng)) punchTimes_.push_back(t);
}

Eigen::Quaterniond WanderingMotion::orientation(double t) const
{
    const double w = 2.0 * core::kPi;
    core::Pose p;
    p.elevationDeg = 40.0 * std::sin(w * 0.11 * t + phase_[0]) + 20.0 * std::sin(w * 0.31 * t + phase_[1]);
    p.azimuthDeg = core::wrapDeg360(50.0 * std::sin(w * 0.05 * t + phase_[2]) + 20.0 * std::sin(w * 0.23 * t + phase_[3]));
    p.rollDeg = 70.0 * std::sin(w * 0.13 * t + phase_[4]) + 20.0 * std::sin(w * 0.41 * t + phase_[5]);
    return poseToQuaternion(p);
}

MotionState WanderingMotion::at(double t) const
{
    MotionState m;
    m.q = orientation(t);
    constexpr double h = 1e-3;
    m.omega = angularVelocity(orientation(t - h), orientation(t + h), 2.0 * h);
    const double tc = std::fmod(std::max(t, 0.0), kPunchCycle);
    for (const double p : punchTimes_) {
        if (tc >= p && tc < p + kPunchLength) {
            m.linearAccel.x() = kPunchPeak * std::sin(core::kPi * (tc - p) / kPunchLength);
            break;
        }
        if (tc >= p + kPunchLength && tc < p + kPunchLength + kBrakeLength) {
            m.linearAccel.x() = -kBrakePeak * std::sin(core::kPi * (tc - p - kPunchLength) / kBrakeLength);
            break;
        }
    }
    return m;
}

FunctionMotion::FunctionMotion(std::function<Eigen::Quaterniond(double)> q, std::function<Eigen::Vector3d(double)> linearAccel)
    : q_(std::move(q)), accel_(std::move(linearAccel))
{
}

MotionState FunctionMotion::at(double t) const
{
    MotionState m;
    m.q = q_(t).normalized();
    constexpr double h = 1e-4;
    m.omega = angularVelocity(q_(t - h).normalized(), q_(t + h).normalized(), 2.0 * h);
    if (accel_) m.linearAccel = accel_(t);
    return m;
}

FileMotion::FileMotion(const std::string& path, bool loop) : loop_(loop)
{
    const core::CsvTable table = core::CsvTable::read(path);
    if (detectMotionKind(table) == core::MotionKind::Imu)
        throw core::InputError(path, table.headerLine(), "", "an IMU file cannot drive the simulator (use a quaternion or pose file)");
    const std::vector<core::TimedQuaternion> rows = motionAsQuaternions(table);
    if (rows.empty()) throw core::InputError(path, 0, "", "no rows: the motion file is empty");
    for (const auto& r : rows) {
        times_.push_back(r.t);
        qs_.push_back(r.q.normalized());
    }
}

Eigen::Quaterniond FileMotion::orientation(double t) const
{
    double tt = times_.front() + std::max(t, 0.0);
    const double len = duration();
    if (loop_ && len > 0.0 && tt > times_.back()) tt = times_.front() + std::fmod(tt - times_.front(), len);
    if (tt <= times_.front()) return qs_.front();
    if (tt >= times_.back()) return qs_.back();
    const auto it = std::upper_bound(times_.begin(), times_.end(), tt);
    const std::size_t i = static_cast<std::size_t>(it - times_.begin());
    const double t0 = times_[i - 1], t1 = times_[i];
    const double a = t1 > t0 ? (tt - t0) / (t1 - t0) : 1.0;
    return qs_[i - 1].slerp(a, qs_[i]);
}

MotionState FileMotion::at(double t) const
{
    MotionState m;
    m.q = orientation(t);
    constexpr double h = 2e-3;
    m.omega = angularVelocity(orientation(t - h), orientation(t + h), 2.0 * h);
    return m;
}

} // namespace armadillo::link
