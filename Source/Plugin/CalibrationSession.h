#pragma once
// The guided calibration of thesis §2.4 (device::CalibrationProcedure) run beside a live link,
// for the device panel. No JUCE: the panel only shows what this says.
// Threads: the link thread offers every raw sensor packet (offer(): lock-free, never blocks; a
// full queue drops the packet and counts it); the message thread drains the queue on its timer,
// feeds the procedure and owns everything else. The procedure never runs on the link or audio
// thread, so its allocation and exceptions stay off them.
#include "Core/SpscQueue.h"
#include "Link/Calibration.h"
#include "Link/DeviceLink.h"
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace armadillo::plugin {

class CalibrationSession {
public:
    using Step = device::CalibrationProcedure::Step;
    /// Packets the queue holds: 5 s at the thesis's 200 Hz, so a stalled UI timer loses nothing.
    static constexpr std::size_t kQueueCapacity = 1024;
    /// Steps the user goes through (Done is not one).
    static constexpr int kStepCount = static_cast<int>(Step::Done);

    // --- link thread -----------------------------------------------------------------------
    /// Queues one raw packet while a calibration runs; otherwise does nothing. Never blocks.
    void offer(double t, const device::SensorCounts& counts) noexcept;

    // --- message thread --------------------------------------------------------------------
    /// Starts (or restarts) the procedure from `start`, the calibration the link uses now: its
    /// rad/s thresholds decide what "still" means, and a skipped step keeps its numbers.
    void begin(const device::Calibration& start);
    void begin(const device::Calibration& start, const device::CalibrationProcedure::Params& params);
    /// Stops without a result; `why` is kept for the UI ("" = the user cancelled).
    void cancel(const std::string& why = {});
    /// Moves queued packets into the procedure; returns how many.
    std::size_t drain();

    bool running() const noexcept { return procedure_ != nullptr && ! finished(); }
    bool finished() const noexcept { return procedure_ != nullptr && procedure_->step() == Step::Done; }
    Step step() const noexcept { return procedure_ != nullptr ? procedure_->step() : Step::GyroStill; }
    /// 1..kStepCount for the current step (kStepCount + 1 when finished).
    int stepNumber() const noexcept { return static_cast<int>(step()) + 1; }
    /// "Step 2 of 7: accelerometer extremes".
    std::string stepTitle() const;
    std::string instruction() const;
    double progress() const noexcept { return procedure_ != nullptr ? procedure_->progress() : 0.0; }
    bool ready() const noexcept { return procedure_ != nullptr && procedure_->ready(); }
    /// Accepts the step (finishStep). False with `why` when there is not enough data yet.
    bool next(std::string& why);
    void skip();
    /// The calibration so far (finished steps applied, the others as started).
    device::Calibration result() const;
    /// Which steps were measured (true) and which kept the starting numbers (skipped).
    bool measured(Step s) const noexcept { return measured_[static_cast<int>(s)]; }
    /// Why the last run stopped without finishing ("" = cancelled by the user or still running).
    const std::string& stopReason() const noexcept { return stopReason_; }
    std::uint64_t packetsFed() const noexcept { return fed_; }
    std::uint64_t packetsDropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

    /// Human name of a step for the UI.
    static const char* stepLabel(Step s) noexcept;
    /// A few words for lists ("gyro bias", "accelerometer", "gyro roll").
    static const char* shortLabel(Step s) noexcept;

private:
    void discardQueued() noexcept;

    SpscQueue<device::RawPacket, kQueueCapacity> queue_;
    std::atomic<bool> accepting_ {false};
    std::atomic<std::uint64_t> dropped_ {0};
    std::unique_ptr<device::CalibrationProcedure> procedure_;
    bool measured_[kStepCount + 1] {};
    std::string stopReason_;
    std::uint64_t fed_ = 0;
};

} // namespace armadillo::plugin
