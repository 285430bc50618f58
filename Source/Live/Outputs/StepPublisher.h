#pragma once
// What a control step leaves for the rest of the program, written once for both clocks
// (LiveSession on the source's clock, BlockControl on the block clock; issue 45): the arm frame
// (ArmFrame: pose, orientation, gyro and the levels that went to the motors, one seqlock so a
// reader gets one step whole), the scene's gestures in order for one front-end reader (Pure
// Data's outlet, the app's OSC out; at most 128 wait, more are dropped and counted), the last
// gesture's name and how many there were, and this step's gestures as the mapping reads them.
//
// Threads: publish() on the step's thread (real-time: no allocation, lock or I/O); latest(),
// the counters and lastGesture() from any thread; popGesture() from one consumer thread.
#include "Core/SpscQueue.h"
#include "Engine/Engine.h"
#include "Live/Step/ArmFrame.h"
#include "Mapping/Mapper.h"
#include <array>
#include <atomic>
#include <cstdint>

namespace armadillo::live {

class StepPublisher {
public:
    static constexpr int kMaxGesturesPerStep = 32;

    /// The frame of a step's arm at time t; `motors` the levels that went out (null: none did).
    static ArmFrame frameOf(double t, const core::ArmState& arm, const core::MotorLevels* motors, int motorCount) noexcept;

    /// The step's thread, once per step: the frame (its serial set here) and the engine's new
    /// gestures (drained).
    void publish(ArmFrame frame, engine::Engine& engine) noexcept;

    /// The gestures of the last publish(), as the mapping takes them (step's thread).
    const mapping::GestureIn* stepGestures() const noexcept { return stepGestures_.data(); }
    int stepGestureCount() const noexcept { return stepGestureCount_; }

    /// Any thread: the newest frame (serial 0: none yet), steps published, gestures.
    ArmFrame latest() const noexcept { return frame_.load(); }
    std::uint64_t steps() const noexcept { return steps_.load(std::memory_order_relaxed); }
    const char* lastGesture() const noexcept { return lastGesture_.load(std::memory_order_relaxed); }
    std::uint64_t gestureCount() const noexcept { return gestureCount_.load(std::memory_order_relaxed); }
    std::uint64_t gesturesDropped() const noexcept { return gesturesDropped_.load(std::memory_order_relaxed); }
    /// One consumer thread: the gestures in order (GestureEvent::name a string literal).
    bool popGesture(engine::GestureEvent& g) noexcept { return gestures_.pop(g); }

private:
    core::SeqLock<ArmFrame> frame_;
    core::SpscQueue<engine::GestureEvent, 128> gestures_;
    std::atomic<const char*> lastGesture_ {""};
    std::atomic<std::uint64_t> gestureCount_ {0};
    std::atomic<std::uint64_t> gesturesDropped_ {0};
    std::atomic<std::uint64_t> steps_ {0};
    std::array<mapping::GestureIn, kMaxGesturesPerStep> stepGestures_ {};
    int stepGestureCount_ = 0;
    std::uint64_t serial_ = 0;
};

} // namespace armadillo::live
