#include "Live/ControlLoop.h"
#include "Live/SetList.h"
#include <cmath>

namespace armadillo::live {

ControlLoop::ControlLoop() = default;

ControlLoop::~ControlLoop()
{
    delete pending_.exchange(nullptr);
    delete retired_.exchange(nullptr);
    delete active_;
}

LiveInput& ControlLoop::input(SourceKind kind) noexcept
{
    switch (kind) {
    case SourceKind::Simulator: return inputs_[1];
    case SourceKind::Osc: return inputs_[2];
    case SourceKind::Device:
    case SourceKind::HostAutomation: break;
    }
    return inputs_[0];
}

// Builder side ------------------------------------------------------------------------------------

bool ControlLoop::offer(std::unique_ptr<EngineSlot>& slot) noexcept
{
    if (!slot || pending_.load(std::memory_order_acquire) != nullptr || retired_.load(std::memory_order_acquire) != nullptr)
        return false;
    newest_ = slot.get();
    pending_.store(slot.release(), std::memory_order_release);
    return true;
}

void ControlLoop::collect() noexcept
{
    delete retired_.exchange(nullptr, std::memory_order_acq_rel);
}

void ControlLoop::replace(std::unique_ptr<EngineSlot> slot) noexcept
{
    delete pending_.exchange(nullptr);
    delete retired_.exchange(nullptr);
    delete active_;
    active_ = slot.release();
    newest_ = active_;
    tracker_.reset();
    lastSource_ = -1;
}

EngineSlot* ControlLoop::newest() noexcept { return newest_; }

// Control side ------------------------------------------------------------------------------------

void ControlLoop::swapInPending() noexcept
{
    if (EngineSlot* next = pending_.exchange(nullptr, std::memory_order_acq_rel)) {
        // The retired slot is empty: offer() refuses while it is not.
        retired_.store(active_, std::memory_order_release);
        active_ = next;
        tracker_.reset();   // a new scene starts from the next sample, not from the old one's history
        swaps_.fetch_add(1, std::memory_order_relaxed);
    }
}

void ControlLoop::resetArm() noexcept
{
    tracker_.reset();
    lastSource_ = -1;
}

ArmState ControlLoop::fuse(LiveInput& in) noexcept
{
    return fuseStep(in, tracker_, lastOrientation_, lastOrientationSerial_, &droppedImu_);
}

ArmState fuseStep(LiveInput& in, ArmTracker& tracker, LiveOrientation& last, std::uint64_t& lastUsedSerial,
                  std::atomic<std::uint64_t>* dropped) noexcept
{
    // Bounded: at most kMaxImuPerStep samples, the newest; older ones are dropped and counted.
    std::size_t waiting = in.imuWaiting();
    LiveImu imu;
    while (waiting > static_cast<std::size_t>(ControlLoop::kMaxImuPerStep) && in.popImu(imu)) {
        --waiting;
        if (dropped != nullptr) dropped->fetch_add(1, std::memory_order_relaxed);
    }
    ArmState arm = tracker.state();
    bool fused = false;
    for (int i = 0; i < ControlLoop::kMaxImuPerStep && in.popImu(imu); ++i) {
        arm = tracker.update(toImuSample(imu));
        fused = true;
    }
    if (!fused) {
        last = in.latest(last);
        if (last.serial != 0 && last.serial != lastUsedSerial) {
            lastUsedSerial = last.serial;
            arm = tracker.updateOrientation(last.t, Eigen::Quaterniond(last.w, last.x, last.y, last.z));
        }
    }
    return arm;
}

ControlResult ControlLoop::tick(const ControlStep& step) noexcept
{
    ControlResult result;
    const std::uint64_t swapsBefore = swaps_.load(std::memory_order_relaxed);
    swapInPending();
    result.swapped = swaps_.load(std::memory_order_relaxed) != swapsBefore;
    if (active_ == nullptr || active_->engine == nullptr) return result;
    EngineSlot& slot = *active_;
    Engine& engine = *slot.engine;
    if (step.panic) {   // idempotent: two atomics per engine
        engine.panic();
        if (step.cues != nullptr) step.cues->panic();
    }

    for (std::size_t i = 0; i < slot.params.size() && i < slot.sent.size(); ++i) {
        if (slot.params[i] == nullptr) continue;
        const float v = slot.params[i]->load(std::memory_order_relaxed);
        if (!(v == slot.sent[i])) {
            engine.scene().setParameter(static_cast<int>(i), v);
            slot.sent[i] = v;
        }
    }

    if (static_cast<int>(step.source) != lastSource_) {
        // A new source starts from its own first sample: no angular velocity across the switch.
        tracker_.reset();
        engine.allOff();
        lastSource_ = static_cast<int>(step.source);
        lastOrientationSerial_ = 0;
    }
    const double dt = std::isfinite(step.dt) && step.dt > 0.0 ? step.dt : 0.0;
    clock_ += dt;

    ArmState arm;
    if (step.source == SourceKind::HostAutomation) {
        // Automation drives the scene through the same tracker as live movement (same features,
        // same angular velocity from successive orientations), so playback sounds as recorded.
        arm = tracker_.updateOrientation(clock_, poseToQuaternion(step.automation));
    } else {
        arm = fuse(input(step.source));
    }
    result.arm = arm;
    if (step.cues != nullptr && step.leftArm != nullptr && step.cues->twoArms()) result.levels = step.cues->control(arm, *step.leftArm, step.transport, dt);
    else if (step.cues != nullptr) result.levels = step.cues->control(arm, step.transport, dt);
    else if (step.leftArm != nullptr && engine.twoArms()) result.levels = engine.control(arm, *step.leftArm, step.transport, dt);
    else result.levels = engine.control(arm, step.transport, dt, step.motorOnTime);
    result.ran = true;
    return result;
}

void ControlLoop::render(float* left, float* right, int numSamples) noexcept
{
    if (active_ != nullptr && active_->engine != nullptr) active_->engine->renderAudio(left, right, numSamples);
}

void ControlLoop::processInput(const float* const* in, int channels, int numSamples) noexcept
{
    if (active_ != nullptr && active_->engine != nullptr) active_->engine->processInput(in, channels, numSamples);
}

void ControlLoop::processMidi(const MidiNoteEvent* events, int count) noexcept
{
    if (active_ != nullptr && active_->engine != nullptr) active_->engine->processMidi(events, count);
}

} // namespace armadillo::live
