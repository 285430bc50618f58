#pragma once
// The plugin's left arm (docs/STAGE.md "Two arms", issue 28): a second source, an OSC sender,
// with its own mailbox and tracker (its own SR-UKF for IMU samples, its own orientations for a
// sender that fuses itself), fused on the control side each step as the right arm's source is
// (live::ControlLoop::fuse: at most kMaxImuPerStep samples, the newest). Its receiver (same
// dialects, detection and mount as the right arm's OSC input) lives in Connections.
//
// Threads: setOn() on the message thread; the OSC receiver's thread fills input(); fuse() on the
// control side (the token holder): no allocation, lock, I/O or throw.
#include "Engine/ArmTracker.h"
#include "Live/ControlLoop.h"
#include "Live/LiveInput.h"
#include <atomic>
#include <cstdint>

namespace armadillo::plugin {

class LeftArm {
public:
    /// Message thread: whether the left arm is in use (the `leftArmOsc` setting).
    void setOn(bool on) noexcept { on_.store(on, std::memory_order_release); }
    bool on() const noexcept { return on_.load(std::memory_order_acquire); }
    /// The receiver's mailbox.
    live::LiveInput& input() noexcept { return input_; }

    /// Control side: the left arm's state after this step's samples; null while off (its tracker
    /// then starts afresh when it comes back on, so no angular velocity spans the gap).
    const ArmState* fuse() noexcept
    {
        if (! on()) {
            if (wasOn_) {
                tracker_.reset();
                arm_ = ArmState {};
                wasOn_ = false;
            }
            return nullptr;
        }
        wasOn_ = true;
        live::LiveImu sample;
        for (std::size_t waiting = input_.imuWaiting();
             waiting > static_cast<std::size_t>(live::ControlLoop::kMaxImuPerStep) && input_.popImu(sample);)
            --waiting;   // a burst: the newest are fused, the oldest dropped
        int fused = 0;
        for (; fused < live::ControlLoop::kMaxImuPerStep && input_.popImu(sample); ++fused) arm_ = tracker_.update(live::toImuSample(sample));
        const std::uint64_t seen = orientation_.serial;
        orientation_ = input_.latest(orientation_);
        if (fused == 0 && orientation_.serial != 0 && orientation_.serial != seen)
            arm_ = tracker_.updateOrientation(orientation_.t, Eigen::Quaterniond(orientation_.w, orientation_.x, orientation_.y, orientation_.z));
        return &arm_;
    }

private:
    std::atomic<bool> on_ {false};
    live::LiveInput input_;
    // Control side only.
    ArmTracker tracker_;
    ArmState arm_ {};
    live::LiveOrientation orientation_ {};
    bool wasOn_ = false;
};

} // namespace armadillo::plugin
