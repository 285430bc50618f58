#pragma once
// The guided device calibration of thesis §2.4 (link::CalibrationProcedure, Link/Calibration.h)
// run beside a live link, written once for `armadillo calibrate` (Cli/CmdCalibrate.cpp presents it
// on stdin/stderr) and the app's Calibration window (Plugin/CalibrationPanel.cpp). Seven steps,
// each with a title and an instruction; the presenter offers Next (accepted when the step has
// enough data, else refused with why), Skip (the step keeps the starting calibration's numbers)
// and Cancel. The result is a link::Calibration, written by save().
// Threads: the link thread offers every raw sensor packet (offer(): lock-free, never blocks; a
// full queue drops the packet and counts it); the front-end thread (the app's message thread, the
// CLI's main thread) drains the queue (drain()), feeds the procedure and owns everything else. The
// procedure never runs on the link or audio thread, so its allocation and exceptions stay off them.
#include "Core/SpscQueue.h"
#include "Link/Calibration.h"
#include "Link/Motion.h"
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace armadillo::procedures {

class DeviceCalibration {
public:
    using Step = link::CalibrationProcedure::Step;
    /// Packets the queue holds: 5 s at the thesis's 200 Hz, so a stalled UI timer loses nothing.
    static constexpr std::size_t kQueueCapacity = 1024;
    /// Steps the user goes through (Done is not one).
    static constexpr int kStepCount = static_cast<int>(Step::Done);

    // --- link thread -----------------------------------------------------------------------
    /// Queues one raw packet (t in s, increasing) while a calibration runs; otherwise does
    /// nothing. Never blocks, allocates or throws.
    void offer(double t, const link::SensorCounts& counts) noexcept;

    // --- front-end thread ------------------------------------------------------------------
    /// Starts (or restarts) the procedure from `start`, the calibration the link uses now: its
    /// rad/s thresholds decide what "still" means, and a skipped step keeps its numbers.
    void begin(const link::Calibration& start);
    void begin(const link::Calibration& start, const link::CalibrationProcedure::Params& params);
    /// Stops without a result; `why` is kept for the UI ("" = the user cancelled).
    void cancel(const std::string& why = {});
    /// Moves queued packets into the procedure; returns how many.
    std::size_t drain();

    bool running() const noexcept { return procedure_ != nullptr && ! finished(); }
    bool finished() const noexcept { return procedure_ != nullptr && procedure_->step() == Step::Done; }
    Step step() const noexcept { return procedure_ != nullptr ? procedure_->step() : Step::GyroStill; }
    /// 1..kStepCount for the current step (kStepCount + 1 when finished).
    int stepNumber() const noexcept { return static_cast<int>(step()) + 1; }
    /// "Step 2 of 7: accelerometer (each axis down and up)"; "Calibration complete".
    std::string stepTitle() const;
    std::string instruction() const;
    double progress() const noexcept { return procedure_ != nullptr ? procedure_->progress() : 0.0; }
    bool ready() const noexcept { return procedure_ != nullptr && procedure_->ready(); }
    /// Accepts the step (finishStep). False with `why` when there is not enough data yet.
    bool next(std::string& why);
    void skip();
    /// The calibration so far (finished steps applied, the others as started).
    link::Calibration result() const;
    /// Writes result() to `path` (atomic; IoError when it cannot), `date` stamped now (UTC).
    void save(const std::string& path) const;
    /// Which steps were measured (true) and which kept the starting numbers (skipped).
    bool measured(Step s) const noexcept { return measured_[static_cast<int>(s)]; }
    /// "gyro bias, gyro roll" / "magnetometer, gyro tip": the steps measured or kept, for a summary.
    std::string measuredList(bool measured) const;
    /// Why the last run stopped without finishing ("" = cancelled by the user or still running).
    const std::string& stopReason() const noexcept { return stopReason_; }
    std::uint64_t packetsFed() const noexcept { return fed_; }
    std::uint64_t packetsDropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

    /// Human name of a step for the UI.
    static const char* stepLabel(Step s) noexcept;
    /// A few words for lists ("gyro bias", "accelerometer", "gyro roll").
    static const char* shortLabel(Step s) noexcept;

private:
    struct Packet {
        double t = 0.0;
        link::SensorCounts counts {};
    };
    void discardQueued() noexcept;

    core::SpscQueue<Packet, kQueueCapacity> queue_;
    std::atomic<bool> accepting_ {false};
    std::atomic<std::uint64_t> dropped_ {0};
    std::unique_ptr<link::CalibrationProcedure> procedure_;
    bool measured_[kStepCount + 1] {};
    std::string stopReason_;
    std::uint64_t fed_ = 0;
};

/// A simulated forearm that does what each step asks (for `armadillo calibrate --simulate`, a
/// rehearsal of the procedure and its test): still at rest; each axis down and up (1 s each);
/// a level circle (4 s); four vertical circles (4 s each); one full turn about x, y, z (2 s) and
/// stop. The presenter says which step runs (setStep, any thread); the motion starts the step's
/// movement at the first sample after that, and performed() says when it has gone through it
/// once — the simulated user's "done" (a step taken as soon as it is ready() would measure half
/// a turn or half the extremes). at() runs on the simulator's thread: lock-free.
class CalibrationRehearsal final : public link::MotionSource {
public:
    void setStep(DeviceCalibration::Step s) noexcept;
    /// The step's movement has been done once (any thread).
    bool performed() const noexcept;
    /// s of movement a step takes (0 for keeping still: the procedure times that itself).
    static double movementSeconds(DeviceCalibration::Step s) noexcept;
    link::MotionState at(double t) const override;

private:
    Eigen::Quaterniond orientation(DeviceCalibration::Step s, double since) const;
    std::atomic<int> step_ {0};
    mutable std::atomic<double> start_ {-1.0};   ///< s of simulator time the step began (< 0: at the next sample)
    mutable std::atomic<double> last_ {-1.0};    ///< s of simulator time of the latest sample
};

} // namespace armadillo::procedures
