#pragma once
// The left arm (docs/STAGE.md "Two arms", issue 28), for every clock: a second source with its
// own mailbox and tracker (its own SR-UKF for IMU samples, its own orientations for a sender
// that fuses itself), fused on the control side each step as the right arm's source is
// (live::fuseStep: at most kMaxImuPerStep samples, the newest). Its source is opened through the
// registry (Live/Sources/SourceRegistry.h): an OSC sender for the block clock (BlockRig), an OSC
// sender, a port or the simulated forearm for `play` (LiveSession); a recording's rows for the
// offline clock (RowClock), handed to each step.
//
// Threads: setOn() on the message thread; the source's thread fills input(); fuse() on the
// control side (the token holder, or the right arm's source thread): no allocation, lock, I/O or throw.
#include "Fusion/ArmTracker.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/LiveInput.h"
#include <atomic>
#include <cstdint>

namespace armadillo::live {

class LeftArm {
public:
    /// Message thread: whether the left arm is in use (the `leftArmOsc` setting).
    void setOn(bool on) noexcept { on_.store(on, std::memory_order_release); }
    bool on() const noexcept { return on_.load(std::memory_order_acquire); }
    /// The receiver's mailbox.
    live::LiveInput& input() noexcept { return input_; }

    /// Control side: the left arm's state after this step's samples — its mailbox's, or a
    /// recording's rows at the offline clock (`recorded`, all of them in order) — null while off
    /// (its tracker then starts afresh when it comes back on, so no angular velocity spans the gap).
    const core::ArmState* fuse(const live::RecordedRows& recorded = {}) noexcept
    {
        if (! on()) {
            if (wasOn_) {
                tracker_.reset();
                arm_ = core::ArmState {};
                wasOn_ = false;
            }
            return nullptr;
        }
        wasOn_ = true;
        if (recorded.rows != nullptr) {
            if (recorded.end > recorded.first) arm_ = live::fuseRecorded(recorded, tracker_);
        } else {
            arm_ = live::fuseStep(input_, tracker_, orientation_, orientationUsed_);
        }
        return &arm_;
    }

private:
    std::atomic<bool> on_ {false};
    live::LiveInput input_;
    // Control side only.
    fusion::ArmTracker tracker_;
    core::ArmState arm_ {};
    live::LiveOrientation orientation_ {};
    std::uint64_t orientationUsed_ = 0;
    bool wasOn_ = false;
};

} // namespace armadillo::live
