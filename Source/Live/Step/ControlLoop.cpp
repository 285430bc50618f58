#include "Live/Step/ControlLoop.h"
#include "Engine/RenderSettings.h"
#include "Live/Stage/SetList.h"
#include <array>
#include <cmath>
#include <limits>

namespace armadillo::live {

ControlLoop::ControlLoop() = default;

ControlLoop::~ControlLoop() = default;

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

void ControlLoop::replace(std::unique_ptr<EngineSlot> slot) noexcept
{
    engines_.replace(std::move(slot));
    tracker_.reset();
    lastSource_ = -1;
}

// Control side ------------------------------------------------------------------------------------

void ControlLoop::swapInPending() noexcept
{
    if (engines_.takeOffered()) {
        tracker_.reset();   // a new scene starts from the next sample, not from the old one's history
        swaps_.fetch_add(1, std::memory_order_relaxed);
    }
}

void ControlLoop::resetArm() noexcept
{
    tracker_.reset();
    lastSource_ = -1;
}

core::ArmState ControlLoop::fuse(LiveInput& in, double cutoff) noexcept
{
    return fuseStep(in, tracker_, lastOrientation_, lastOrientationSerial_, &droppedImu_, cutoff);
}

core::ArmState fuseStep(LiveInput& in, fusion::ArmTracker& tracker, LiveOrientation& last, std::uint64_t& lastUsedSerial,
                  std::atomic<std::uint64_t>* dropped, double cutoff) noexcept
{
    // Bounded: of the samples due (arrived by `cutoff`), at most kMaxImuPerStep, the newest, are
    // fused; older ones are dropped and counted. The loop takes at most what was waiting when it
    // began, so a producer that keeps pushing cannot keep it going.
    constexpr std::size_t kMax = static_cast<std::size_t>(ControlLoop::kMaxImuPerStep);
    std::array<LiveImu, kMax> newest {};
    std::size_t due = 0;
    LiveImu imu;
    for (std::size_t budget = in.imuWaiting(); budget > 0 && in.peekImu(imu) && imu.arrival <= cutoff; --budget) {
        in.popImu(imu);
        if (due >= kMax && dropped != nullptr) dropped->fetch_add(1, std::memory_order_relaxed);
        newest[due % kMax] = imu;
        ++due;
    }
    core::ArmState arm = tracker.state();
    for (std::size_t i = due > kMax ? due - kMax : 0; i < due; ++i) arm = tracker.update(toImuSample(newest[i % kMax]));
    if (due == 0) {
        last = in.latest(last);
        if (last.serial != 0 && last.serial != lastUsedSerial && last.arrival <= cutoff) {
            lastUsedSerial = last.serial;
            arm = tracker.updateOrientation(last.t, Eigen::Quaterniond(last.w, last.x, last.y, last.z));
        }
    }
    return arm;
}

core::ArmState fuseRecorded(const RecordedRows& rows, fusion::ArmTracker& tracker)
{
    if (rows.first >= rows.end) return tracker.state();
    for (std::size_t i = rows.first; i + 1 < rows.end; ++i) rows.rows->apply(tracker, i);
    return rows.rows->apply(tracker, rows.end - 1);
}

double ControlLoop::nextArrival(SourceKind source) noexcept
{
    if (!isLiveSource(source)) return std::numeric_limits<double>::infinity();
    LiveInput& in = input(source);
    LiveImu imu;
    if (in.peekImu(imu)) return imu.arrival;
    // A new source starts its serials afresh at its first tick (lastSource_ below).
    const std::uint64_t used = static_cast<int>(source) == lastSource_ ? lastOrientationSerial_ : 0;
    lastOrientation_ = in.latest(lastOrientation_);
    if (lastOrientation_.serial != 0 && lastOrientation_.serial != used) return lastOrientation_.arrival;
    return std::numeric_limits<double>::infinity();
}

ControlResult ControlLoop::tick(const ControlStep& step) noexcept
{
    ControlResult result;
    const std::uint64_t swapsBefore = swaps_.load(std::memory_order_relaxed);
    swapInPending();
    result.swapped = swaps_.load(std::memory_order_relaxed) != swapsBefore;
    EngineSlot* const current = engines_.active();
    if (current == nullptr || current->engine == nullptr) return result;
    EngineSlot& slot = *current;
    engine::Engine& engine = *slot.engine;
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
        // A switch (not the first source) is another arm: what the old arm drove goes off, and the
        // scene starts afresh, so what it took from the old arm (the theremin's reference heading)
        // is taken again from the new one, as an instance that played this source from the start
        // has it (a DAW session reopened). The first source's first step plays as any other (the
        // offline clock's first row as `play`'s first packet).
        if (lastSource_ >= 0) {
            engine.allOff();
            engine.restart();
            if (step.cues != nullptr) step.cues->restart();
        }
        lastSource_ = static_cast<int>(step.source);
        lastOrientationSerial_ = 0;
    }
    const double dt = std::isfinite(step.dt) && step.dt > 0.0 ? step.dt : 0.0;
    clock_ += dt;

    core::ArmState arm;
    if (step.source == SourceKind::HostAutomation) {
        // Automation drives the scene through the same tracker as live movement (same features,
        // same angular velocity from successive orientations), so playback sounds as recorded.
        arm = tracker_.updateOrientation(clock_, poseToQuaternion(step.automation));
    } else if (step.recorded.rows != nullptr) {
        arm = fuseRecorded(step.recorded, tracker_);
    } else {
        arm = fuse(input(step.source), step.arrivalCutoff);
    }
    result.arm = arm;
    if (!step.panicGesture) {
        panicGesture_.reset();
    } else if (panicGesture_.update(clock_, arm)) {   // once per hang; motors off from this step
        engine.panic();
        if (step.cues != nullptr) step.cues->panic();
        result.gesturePanic = true;
    }
    if (step.cues != nullptr && step.leftArm != nullptr && step.cues->twoArms()) result.levels = step.cues->control(arm, *step.leftArm, step.transport, dt);
    else if (step.cues != nullptr) result.levels = step.cues->control(arm, step.transport, dt);
    else if (step.leftArm != nullptr && engine.twoArms()) result.levels = engine.control(arm, *step.leftArm, step.transport, dt);
    else result.levels = engine.control(arm, step.transport, dt, step.motorOnTime);
    result.ran = true;
    return result;
}

void ControlLoop::render(float* left, float* right, int numSamples) noexcept
{
    if (EngineSlot* slot = engines_.active(); slot != nullptr && slot->engine != nullptr) slot->engine->renderAudio(left, right, numSamples);
}

void ControlLoop::processInput(const float* const* in, int channels, int numSamples) noexcept
{
    if (EngineSlot* slot = engines_.active(); slot != nullptr && slot->engine != nullptr) slot->engine->processInput(in, channels, numSamples);
}

void ControlLoop::processMidi(const core::MidiNoteEvent* events, int count) noexcept
{
    if (EngineSlot* slot = engines_.active(); slot != nullptr && slot->engine != nullptr) slot->engine->processMidi(events, count);
}

} // namespace armadillo::live
