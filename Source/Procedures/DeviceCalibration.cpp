#include "Procedures/DeviceCalibration.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include <algorithm>
#include <cmath>
#include <ctime>

namespace armadillo::procedures {

void DeviceCalibration::offer(double t, const link::SensorCounts& counts) noexcept
{
    if (! accepting_.load(std::memory_order_acquire)) return;
    if (! queue_.push(Packet {t, counts})) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void DeviceCalibration::begin(const link::Calibration& start) { begin(start, link::CalibrationProcedure::Params {}); }

void DeviceCalibration::begin(const link::Calibration& start, const link::CalibrationProcedure::Params& params)
{
    accepting_.store(false, std::memory_order_release);
    discardQueued();   // packets of an earlier run must not count toward this one
    procedure_ = std::make_unique<link::CalibrationProcedure>(start, params);
    for (bool& m : measured_) m = false;
    stopReason_.clear();
    fed_ = 0;
    dropped_.store(0, std::memory_order_relaxed);
    accepting_.store(true, std::memory_order_release);
}

void DeviceCalibration::cancel(const std::string& why)
{
    accepting_.store(false, std::memory_order_release);
    discardQueued();
    procedure_.reset();
    stopReason_ = why;
}

void DeviceCalibration::discardQueued() noexcept
{
    Packet p;
    while (queue_.pop(p)) {
    }
}

std::size_t DeviceCalibration::drain()
{
    if (procedure_ == nullptr) {
        discardQueued();
        return 0;
    }
    std::size_t n = 0;
    Packet p;
    while (queue_.pop(p)) {
        procedure_->feed(p.t, p.counts);
        ++n;
    }
    fed_ += n;
    return n;
}

const char* DeviceCalibration::stepLabel(Step s) noexcept
{
    switch (s) {
    case Step::GyroStill: return "gyroscope bias (keep still)";
    case Step::AccelExtremes: return "accelerometer (each axis down and up)";
    case Step::MagHorizontal: return "magnetometer, level circle";
    case Step::MagVertical: return "magnetometer, vertical circles";
    case Step::GyroTurnX: return "gyroscope scale, roll (x)";
    case Step::GyroTurnY: return "gyroscope scale, turn about vertical (y)";
    case Step::GyroTurnZ: return "gyroscope scale, tip (z)";
    case Step::Done: return "done";
    }
    return "?";
}

const char* DeviceCalibration::shortLabel(Step s) noexcept
{
    switch (s) {
    case Step::GyroStill: return "gyro bias";
    case Step::AccelExtremes: return "accelerometer";
    case Step::MagHorizontal:
    case Step::MagVertical: return "magnetometer";
    case Step::GyroTurnX: return "gyro roll";
    case Step::GyroTurnY: return "gyro turn";
    case Step::GyroTurnZ: return "gyro tip";
    case Step::Done: return "done";
    }
    return "?";
}

std::string DeviceCalibration::stepTitle() const
{
    if (procedure_ == nullptr) return "No calibration running";
    if (finished()) return "Calibration complete";
    return "Step " + std::to_string(stepNumber()) + " of " + std::to_string(kStepCount) + ": " + stepLabel(step());
}

std::string DeviceCalibration::instruction() const { return procedure_ != nullptr ? procedure_->instruction() : std::string(); }

bool DeviceCalibration::next(std::string& why)
{
    why.clear();
    if (procedure_ == nullptr || finished()) {
        why = "No calibration step is running.";
        return false;
    }
    const Step was = procedure_->step();
    try {
        procedure_->finishStep();
    } catch (const core::InputError&) {
        why = "Not enough data for this step yet (" + std::to_string(static_cast<int>(progress() * 100.0)) + " %): keep following the instruction.";
        return false;
    }
    measured_[static_cast<int>(was)] = true;
    if (finished()) accepting_.store(false, std::memory_order_release);
    return true;
}

void DeviceCalibration::skip()
{
    if (procedure_ == nullptr || finished()) return;
    procedure_->skipStep();
    if (finished()) accepting_.store(false, std::memory_order_release);
}

link::Calibration DeviceCalibration::result() const { return procedure_ != nullptr ? procedure_->result() : link::Calibration {}; }

void DeviceCalibration::save(const std::string& path) const
{
    link::Calibration c = result();
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    c.date = date;
    link::saveCalibration(path, c);
}

std::string DeviceCalibration::measuredList(bool measured) const
{
    std::string out;
    for (int k = 0; k < kStepCount; ++k) {
        const auto s = static_cast<Step>(k);
        if (measured_[k] != measured) continue;
        if (s == Step::MagHorizontal) continue;   // the magnetometer is one entry (its vertical step decides)
        out += (out.empty() ? "" : ", ") + std::string(shortLabel(s));
    }
    return out;
}

// --- the rehearsal ------------------------------------------------------------------------------

void CalibrationRehearsal::setStep(DeviceCalibration::Step s) noexcept
{
    start_.store(-1.0, std::memory_order_relaxed);
    step_.store(static_cast<int>(s), std::memory_order_release);
}

double CalibrationRehearsal::movementSeconds(DeviceCalibration::Step s) noexcept
{
    using Step = DeviceCalibration::Step;
    switch (s) {
    case Step::AccelExtremes: return 6.2;   // six poses, 1 s each
    case Step::MagHorizontal: return 4.2;   // one level circle
    case Step::MagVertical: return 16.2;    // four vertical circles
    case Step::GyroTurnX:
    case Step::GyroTurnY:
    case Step::GyroTurnZ: return 2.5;       // the turn, then still
    case Step::GyroStill:
    case Step::Done: break;
    }
    return 0.0;
}

bool CalibrationRehearsal::performed() const noexcept
{
    const double start = start_.load(std::memory_order_relaxed), last = last_.load(std::memory_order_relaxed);
    const auto s = static_cast<DeviceCalibration::Step>(step_.load(std::memory_order_acquire));
    return start >= 0.0 && last - start >= movementSeconds(s);
}

Eigen::Quaterniond CalibrationRehearsal::orientation(DeviceCalibration::Step s, double since) const
{
    using Q = Eigen::Quaterniond;
    using A = Eigen::AngleAxisd;
    using Step = DeviceCalibration::Step;
    constexpr double pi = 3.14159265358979323846;
    switch (s) {
    case Step::AccelExtremes: {   // each axis down and up, held 1 s each (x, y, z)
        static const Q poses[] = {Q(A(pi / 2, Eigen::Vector3d::UnitZ())), Q(A(-pi / 2, Eigen::Vector3d::UnitZ())), Q::Identity(),
                                  Q(A(pi, Eigen::Vector3d::UnitX())),     Q(A(-pi / 2, Eigen::Vector3d::UnitX())), Q(A(pi / 2, Eigen::Vector3d::UnitX()))};
        return poses[static_cast<int>(std::floor(since)) % 6];
    }
    case Step::MagHorizontal: return Q(A(2 * pi * since / 4.0, Eigen::Vector3d::UnitY()));   // level circles, 4 s each
    case Step::MagVertical: {   // four vertical circles, 4 s each, over and over
        const double u = std::fmod(since, 16.0), a = 2 * pi * std::fmod(u, 4.0) / 4.0;
        switch (static_cast<int>(u / 4.0)) {
        case 0: return Q(A(a, Eigen::Vector3d::UnitX()));
        case 1: return Q(A(a, Eigen::Vector3d::UnitZ()));
        case 2: return Q(A(pi / 2, Eigen::Vector3d::UnitY())) * Q(A(a, Eigen::Vector3d::UnitZ()));
        default: return Q(A(pi / 2, Eigen::Vector3d::UnitZ())) * Q(A(a, Eigen::Vector3d::UnitX()));
        }
    }
    case Step::GyroTurnX:
    case Step::GyroTurnY:
    case Step::GyroTurnZ: {   // one full turn in 2 s, then still
        const Eigen::Vector3d axis = Eigen::Vector3d::Unit(static_cast<int>(s) - static_cast<int>(Step::GyroTurnX));
        return core::restOrientation() * Q(A(2 * pi * std::clamp(since / 2.0, 0.0, 1.0), axis));
    }
    case Step::GyroStill:
    case Step::Done: break;
    }
    return core::restOrientation();
}

link::MotionState CalibrationRehearsal::at(double t) const
{
    double start = start_.load(std::memory_order_relaxed);
    if (start < 0.0) {   // the step's movement begins now
        start_.compare_exchange_strong(start, t, std::memory_order_relaxed);
        start = start_.load(std::memory_order_relaxed);
    }
    last_.store(t, std::memory_order_relaxed);
    const auto s = static_cast<DeviceCalibration::Step>(step_.load(std::memory_order_acquire));
    const double since = std::max(0.0, t - start), h = 1e-3;
    link::MotionState m;
    m.q = orientation(s, since);
    m.omega = link::angularVelocity(m.q, orientation(s, since + h), h);
    return m;
}

} // namespace armadillo::procedures
