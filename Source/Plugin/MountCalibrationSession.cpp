#include "Plugin/MountCalibrationSession.h"
#include <Eigen/Core>
#include <cctype>

namespace armadillo::plugin {

void MountCalibrationSession::begin(const std::string& device)
{
    begin(device, device::MountCalibration::Params {});
}

void MountCalibrationSession::begin(const std::string& device, const device::MountCalibration::Params& params)
{
    calibration_ = std::make_unique<device::MountCalibration>(params);
    result_ = device::Mount {};
    device_ = device;
    failed_.clear();
    stopReason_.clear();
    finished_ = false;
    fed_ = 0;
}

void MountCalibrationSession::cancel(const std::string& why)
{
    calibration_.reset();
    finished_ = false;
    failed_.clear();
    stopReason_ = why;
}

void MountCalibrationSession::feed(const device::SensorFrameSample& s)
{
    // A pose with enough data waits for Next: the arm moving on must not replace it.
    if (! running() || calibration_->ready()) return;
    calibration_->feed(Eigen::Vector3d(s.accel[0], s.accel[1], s.accel[2]), Eigen::Vector3d(s.gyro[0], s.gyro[1], s.gyro[2]));
    ++fed_;
}

std::size_t MountCalibrationSession::drain(const std::function<bool(device::SensorFrameSample&)>& pop)
{
    std::size_t n = 0;
    device::SensorFrameSample s;
    while (pop(s)) {   // popped even when not running, so no stale samples wait in the tap
        feed(s);
        ++n;
    }
    return n;
}

std::string MountCalibrationSession::stepTitle() const
{
    if (finished_) return "Mount calibration done";
    if (! failed_.empty()) return "Mount calibration failed";
    const Pose p = pose();
    return "Pose " + std::to_string(static_cast<int>(p) + 1) + " of " + std::to_string(kPoseCount) + ": "
           + device::MountCalibration::poseName(p);
}

std::string MountCalibrationSession::instruction() const
{
    if (! failed_.empty()) return failed_;
    std::string s = device::MountCalibration::instruction(finished_ ? Pose::Done : pose());
    if (! s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
    return s + ".";
}

bool MountCalibrationSession::next(std::string& why)
{
    why.clear();
    if (! running()) {
        why = "No mount calibration is running.";
        return false;
    }
    if (! calibration_->ready()) {
        why = fed_ == 0 ? "No sensor samples yet: the sender must send its accelerometer to the OSC input port."
                        : "Not enough still samples for this pose yet: hold the arm still in it.";
        return false;
    }
    calibration_->finishStep();
    if (calibration_->pose() == Pose::Done) return solve(why);
    return true;
}

bool MountCalibrationSession::skip(std::string& why)
{
    why.clear();
    if (! canSkip()) {
        why = "Only the roll pose is optional.";
        return false;
    }
    calibration_->skipRoll();
    return solve(why);
}

bool MountCalibrationSession::solve(std::string& why)
{
    device::Mount m;
    if (! calibration_->solve(m, why)) {
        failed_ = "No mount found: " + why + ". Start again.";
        return false;
    }
    m.device = device_;
    result_ = m;
    finished_ = true;
    return true;
}

std::string MountCalibrationSession::fileNameForDevice(const std::string& device)
{
    // A sender known only by "address:port" keeps its address: the port is a fresh ephemeral
    // one each time the app reopens its socket, so it would give every session its own file.
    std::string id = device;
    if (const auto colon = id.rfind(':'); colon != std::string::npos && id.find(':') == colon
        && id.find_first_not_of("0123456789", colon + 1) == std::string::npos && colon + 1 < id.size())
        id.erase(colon);
    std::string safe;
    for (const char c : id) {
        const bool keep = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_';
        if (keep) safe += c;
        else if (! safe.empty() && safe.back() != '-') safe += '-';
        if (safe.size() >= 48) break;
    }
    while (! safe.empty() && safe.back() == '-') safe.pop_back();
    return "mount-" + (safe.empty() ? std::string("sensor") : safe) + ".json";
}

} // namespace armadillo::plugin
