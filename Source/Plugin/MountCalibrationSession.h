#pragma once
// The guided mount calibration (device::MountCalibration: arm level ahead, arm hanging down,
// optionally a quarter roll) for the device panel, fed from the OSC input's sensor-frame tap.
// No JUCE: the panel only shows what this says. Message thread only: the receiver thread pushes
// into the merger's lock-free tap, and drain() pops from it on the panel's timer.
// A pose that has enough still samples is frozen until Next, so moving on to the next pose
// before pressing Next cannot overwrite it.
#include "Osc/Mount.h"
#include "Osc/OscInput.h"
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace armadillo::plugin {

class MountCalibrationSession {
public:
    using Pose = device::MountCalibration::Pose;
    /// Poses the user goes through (the third is optional).
    static constexpr int kPoseCount = 3;

    /// Starts (or restarts) the calibration; `device` names the sensor (for the saved file).
    void begin(const std::string& device = {});
    void begin(const std::string& device, const device::MountCalibration::Params& params);
    /// Stops without a result; `why` is kept for the UI ("" = the user cancelled).
    void cancel(const std::string& why = {});
    /// One sensor-frame sample (accel m/s², gyro rad/s or NaN). Ignored unless running.
    void feed(const device::SensorFrameSample& s);
    /// Pops samples with `pop` (the OSC input's tap) until it returns false; returns how many.
    std::size_t drain(const std::function<bool(device::SensorFrameSample&)>& pop);

    bool running() const noexcept { return calibration_ != nullptr && ! finished_ && failed_.empty(); }
    /// Solved: result() holds the mount.
    bool finished() const noexcept { return finished_; }
    /// The poses did not determine a rotation: why (and the user restarts or closes).
    const std::string& failure() const noexcept { return failed_; }
    Pose pose() const noexcept { return calibration_ != nullptr ? calibration_->pose() : Pose::LevelForward; }
    /// 1..kPoseCount for the current pose (kPoseCount + 1 when done).
    int stepNumber() const noexcept { return static_cast<int>(pose()) + 1; }
    /// "Pose 2 of 3: hanging down".
    std::string stepTitle() const;
    std::string instruction() const;
    double progress() const noexcept { return calibration_ != nullptr ? calibration_->progress() : 0.0; }
    bool ready() const noexcept { return calibration_ != nullptr && running() && calibration_->ready(); }
    /// Only the roll pose may be skipped.
    bool canSkip() const noexcept { return running() && pose() == Pose::RolledRight; }
    /// Accepts the pose. After the last one the mount is solved. False with `why` when the pose
    /// has not enough still samples yet, or the poses do not determine a rotation.
    bool next(std::string& why);
    /// Skips the optional roll pose and solves. False with `why` as for next().
    bool skip(std::string& why);
    /// The solved mount (name "calibrated", device as given to begin()).
    const device::Mount& result() const noexcept { return result_; }
    const std::string& device() const noexcept { return device_; }
    std::uint64_t samplesFed() const noexcept { return fed_; }
    const std::string& stopReason() const noexcept { return stopReason_; }

    /// "mount-<device>.json" with the device id made safe for a file name ("mount-sensor.json"
    /// for an unnamed one; an "address:port" sender without its ephemeral port): where the app
    /// keeps each device's mount.
    static std::string fileNameForDevice(const std::string& device);

private:
    bool solve(std::string& why);

    std::unique_ptr<device::MountCalibration> calibration_;
    device::Mount result_;
    std::string device_, failed_, stopReason_;
    bool finished_ = false;
    std::uint64_t fed_ = 0;
};

} // namespace armadillo::plugin
