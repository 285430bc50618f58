#include "Procedures/MountCalibration.h"
#include <Eigen/Core>
#include <cctype>

namespace armadillo::procedures {

void MountCalibration::begin(const std::string& device, Advance advance) { begin(device, link::MountCalibration::Params {}, advance); }

void MountCalibration::begin(const std::string& device, const link::MountCalibration::Params& params, Advance advance)
{
    calibration_ = std::make_unique<link::MountCalibration>(params);
    result_ = link::Mount {};
    device_ = device;
    advance_ = advance;
    failed_.clear();
    failedWhy_.clear();
    stopReason_.clear();
    finished_ = false;
    fed_ = 0;
    announce();
}

void MountCalibration::setDevice(const std::string& device)
{
    device_ = device;
    if (finished_) result_.device = device;
}

void MountCalibration::cancel(const std::string& why)
{
    calibration_.reset();
    finished_ = false;
    failed_.clear();
    failedWhy_.clear();
    stopReason_ = why;
}

void MountCalibration::feed(const osc::SensorFrameSample& s)
{
    // A pose with enough data waits for Next: the arm moving on must not replace it.
    if (! running() || calibration_->ready()) return;
    calibration_->feed(Eigen::Vector3d(s.accel[0], s.accel[1], s.accel[2]), Eigen::Vector3d(s.gyro[0], s.gyro[1], s.gyro[2]));
    ++fed_;
    if (advance_ == Advance::WhenReady && calibration_->ready()) {
        calibration_->finishStep();
        if (calibration_->pose() == Pose::Done) {
            std::string why;
            solve(why);
        }
        announce();
    }
}

std::size_t MountCalibration::drain(const std::function<bool(osc::SensorFrameSample&)>& pop)
{
    std::size_t n = 0;
    osc::SensorFrameSample s;
    while (pop(s)) {   // popped even when not running, so no stale samples wait in the tap
        feed(s);
        ++n;
    }
    return n;
}

std::string MountCalibration::stepTitle() const
{
    if (finished_) return "Mount calibration done";
    if (! failed_.empty()) return "Mount calibration failed";
    const Pose p = pose();
    return "Pose " + std::to_string(static_cast<int>(p) + 1) + " of " + std::to_string(kPoseCount) + ": " + link::MountCalibration::poseName(p);
}

std::string MountCalibration::instruction() const
{
    if (! failed_.empty()) return failed_;
    std::string s = link::MountCalibration::instruction(finished_ ? Pose::Done : pose());
    if (! s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
    return s + ".";
}

std::string MountCalibration::announcement() const
{
    if (! failed_.empty()) return "mount calibration failed: " + failedWhy_;
    const Pose p = pose();
    if (finished_ || p == Pose::Done) return "mount calibration complete";
    return "mount calibration pose " + std::to_string(static_cast<int>(p) + 1) + " (" + link::MountCalibration::poseName(p) +
           "): " + link::MountCalibration::instruction(p);
}

void MountCalibration::announce() const
{
    if (announce_ && calibration_ != nullptr) announce_(announcement());
}

bool MountCalibration::next(std::string& why)
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
    const bool ok = calibration_->pose() != Pose::Done || solve(why);
    announce();
    return ok;
}

bool MountCalibration::skip(std::string& why)
{
    why.clear();
    if (! canSkip()) {
        why = "Only the roll pose is optional.";
        return false;
    }
    calibration_->skipRoll();
    const bool ok = solve(why);
    announce();
    return ok;
}

bool MountCalibration::conclude(std::string& why)
{
    why.clear();
    if (finished_) return true;
    if (calibration_ == nullptr) {
        why = "no mount calibration ran";
        return false;
    }
    if (! failed_.empty()) {
        why = failedWhy_;
        return false;
    }
    calibration_->skipRoll();   // the third pose is optional
    return solve(why);
}

bool MountCalibration::solve(std::string& why)
{
    link::Mount m;
    if (! calibration_->solve(m, why)) {
        failedWhy_ = why;
        failed_ = "No mount found: " + why + ". Start again.";
        return false;
    }
    m.device = device_;
    result_ = m;
    finished_ = true;
    return true;
}

void MountCalibration::save(const std::string& path) const { link::saveMount(path, result_); }

std::string MountCalibration::fileNameForDevice(const std::string& device)
{
    // A sender known only by "address:port" keeps its address: the port is a fresh ephemeral
    // one each time the app reopens its socket, so it would give every session its own file.
    std::string id = device;
    if (const auto colon = id.rfind(':'); colon != std::string::npos && id.find(':') == colon &&
                                          id.find_first_not_of("0123456789", colon + 1) == std::string::npos && colon + 1 < id.size())
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

} // namespace armadillo::procedures
