#pragma once
// The guided mount calibration of an OSC sensor (link::MountCalibration, Link/Mount.h: arm level
// ahead, arm hanging down, optionally a quarter roll), written once for the app's Mount window
// (Plugin/MountCalibrationPanel.cpp) and the command line's `play --calibrate-mount`
// (Cli/CmdPlay.cpp's GuidedMount, with Advance::WhenReady), both fed from the rig's sensor-frame
// tap (live::LiveSession::popSensorFrame, OscSampleMerger::popSensorSample below it).
// Two ways to advance:
//   • Advance::OnNext (the app): a pose that has enough still samples is frozen until Next, so
//     moving on to the next pose before pressing Next cannot overwrite it;
//   • Advance::WhenReady (a text presenter with no Next key): each pose is taken as soon as it has
//     enough still samples; the optional roll pose is skipped when the session ends in it
//     (conclude()).
// The presenter hears each pose through the announcer (one line a pose: "mount calibration pose
// 2 (hanging down): let the arm hang …", then "mount calibration complete"); the result is a
// link::Mount, written by save().
// Threads: one front-end thread (the app's message thread, the CLI's main thread); the OSC
// receiver thread only pushes into the merger's lock-free tap, and drain() pops from it.
#include "Link/Mount.h"
#include "Osc/OscInput.h"
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace armadillo::procedures {

class MountCalibration {
public:
    using Pose = link::MountCalibration::Pose;
    enum class Advance { OnNext, WhenReady };
    /// Poses the user goes through (the third is optional).
    static constexpr int kPoseCount = 3;

    /// Called with one line for the presenter at begin(), at every pose change and when solved.
    void setAnnouncer(std::function<void(const std::string& line)> announce) { announce_ = std::move(announce); }
    /// Starts (or restarts) the calibration; `device` names the sensor (for the saved file).
    void begin(const std::string& device = {}, Advance advance = Advance::OnNext);
    void begin(const std::string& device, const link::MountCalibration::Params& params, Advance advance = Advance::OnNext);
    /// Names the sensor once it is known (a sender's name arrives with its first packets).
    void setDevice(const std::string& device);
    /// Stops without a result; `why` is kept for the UI ("" = the user cancelled).
    void cancel(const std::string& why = {});
    /// One sensor-frame sample (accel m/s², gyro rad/s or NaN). Ignored unless running.
    void feed(const osc::SensorFrameSample& s);
    /// Pops samples with `pop` (the OSC input's tap) until it returns false; returns how many.
    std::size_t drain(const std::function<bool(osc::SensorFrameSample&)>& pop);

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
    /// "Let the arm hang straight down, relaxed." (the failure when failed).
    std::string instruction() const;
    /// The current state in one line: "mount calibration pose 2 (hanging down): let the arm hang
    /// …", "mount calibration complete".
    std::string announcement() const;
    double progress() const noexcept { return calibration_ != nullptr ? calibration_->progress() : 0.0; }
    bool ready() const noexcept { return calibration_ != nullptr && running() && calibration_->ready(); }
    /// Only the roll pose may be skipped.
    bool canSkip() const noexcept { return running() && pose() == Pose::RolledRight; }
    /// Accepts the pose. After the last one the mount is solved. False with `why` when the pose
    /// has not enough still samples yet, or the poses do not determine a rotation.
    bool next(std::string& why);
    /// Skips the optional roll pose and solves. False with `why` as for next().
    bool skip(std::string& why);
    /// Ends the walk where it stands (a session that ends): the roll pose skipped when it is the
    /// one waiting, the mount solved. True when result() holds it; else false with the reason
    /// ("two poses are needed", …; pose() says where it stopped).
    bool conclude(std::string& why);
    /// The solved mount (name "calibrated", device as given to begin() or setDevice()).
    const link::Mount& result() const noexcept { return result_; }
    /// Writes result() to `path` (atomic; IoError when it cannot).
    void save(const std::string& path) const;
    const std::string& device() const noexcept { return device_; }
    std::uint64_t samplesFed() const noexcept { return fed_; }
    const std::string& stopReason() const noexcept { return stopReason_; }

    /// "mount-<device>.json" with the device id made safe for a file name ("mount-sensor.json"
    /// for an unnamed one; an "address:port" sender without its ephemeral port): where the app
    /// keeps each device's mount.
    static std::string fileNameForDevice(const std::string& device);

private:
    bool solve(std::string& why);
    void announce() const;

    std::unique_ptr<link::MountCalibration> calibration_;
    std::function<void(const std::string&)> announce_;
    link::Mount result_;
    std::string device_, failed_, failedWhy_, stopReason_;
    Advance advance_ = Advance::OnNext;
    bool finished_ = false;
    std::uint64_t fed_ = 0;
};

} // namespace armadillo::procedures
