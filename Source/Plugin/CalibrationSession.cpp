#include "Plugin/CalibrationSession.h"
#include "Core/Errors.h"

namespace armadillo::plugin {

void CalibrationSession::offer(double t, const device::SensorCounts& counts) noexcept
{
    if (! accepting_.load(std::memory_order_acquire)) return;
    if (! queue_.push(device::RawPacket {t, counts})) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void CalibrationSession::begin(const device::Calibration& start)
{
    begin(start, device::CalibrationProcedure::Params {});
}

void CalibrationSession::begin(const device::Calibration& start, const device::CalibrationProcedure::Params& params)
{
    accepting_.store(false, std::memory_order_release);
    discardQueued();   // packets of an earlier run must not count toward this one
    procedure_ = std::make_unique<device::CalibrationProcedure>(start, params);
    for (bool& m : measured_) m = false;
    stopReason_.clear();
    fed_ = 0;
    dropped_.store(0, std::memory_order_relaxed);
    accepting_.store(true, std::memory_order_release);
}

void CalibrationSession::cancel(const std::string& why)
{
    accepting_.store(false, std::memory_order_release);
    discardQueued();
    procedure_.reset();
    stopReason_ = why;
}

void CalibrationSession::discardQueued() noexcept
{
    device::RawPacket p;
    while (queue_.pop(p)) {
    }
}

std::size_t CalibrationSession::drain()
{
    if (procedure_ == nullptr) {
        discardQueued();
        return 0;
    }
    std::size_t n = 0;
    device::RawPacket p;
    while (queue_.pop(p)) {
        procedure_->feed(p.t, p.counts);
        ++n;
    }
    fed_ += n;
    return n;
}

const char* CalibrationSession::stepLabel(Step s) noexcept
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

const char* CalibrationSession::shortLabel(Step s) noexcept
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

std::string CalibrationSession::stepTitle() const
{
    if (procedure_ == nullptr) return "No calibration running";
    if (finished()) return "Calibration complete";
    return "Step " + std::to_string(stepNumber()) + " of " + std::to_string(kStepCount) + ": " + stepLabel(step());
}

std::string CalibrationSession::instruction() const
{
    return procedure_ != nullptr ? procedure_->instruction() : std::string();
}

bool CalibrationSession::next(std::string& why)
{
    why.clear();
    if (procedure_ == nullptr || finished()) {
        why = "No calibration step is running.";
        return false;
    }
    const Step was = procedure_->step();
    try {
        procedure_->finishStep();
    } catch (const InputError&) {
        why = "Not enough data for this step yet (" + std::to_string(static_cast<int>(progress() * 100.0)) + " %): keep following the instruction.";
        return false;
    }
    measured_[static_cast<int>(was)] = true;
    if (finished()) accepting_.store(false, std::memory_order_release);
    return true;
}

void CalibrationSession::skip()
{
    if (procedure_ == nullptr || finished()) return;
    procedure_->skipStep();
    if (finished()) accepting_.store(false, std::memory_order_release);
}

device::Calibration CalibrationSession::result() const
{
    return procedure_ != nullptr ? procedure_->result() : device::Calibration {};
}

} // namespace armadillo::plugin
