#include "Live/Outputs/StepPublisher.h"

namespace armadillo::live {

ArmFrame StepPublisher::frameOf(double t, const core::ArmState& arm, const core::MotorLevels* motors, int motorCount) noexcept
{
    ArmFrame f;
    f.t = t;
    f.valid = arm.valid;
    f.q[0] = arm.q.w();
    f.q[1] = arm.q.x();
    f.q[2] = arm.q.y();
    f.q[3] = arm.q.z();
    f.pose[0] = arm.features.pose.elevationDeg;
    f.pose[1] = arm.features.pose.azimuthDeg;
    f.pose[2] = arm.features.pose.rollDeg;
    for (int i = 0; i < 3; ++i) f.gyro[i] = arm.gyro[i];
    if (motors != nullptr) f.motors = *motors;
    f.motorCount = motorCount;
    return f;
}

void StepPublisher::publish(ArmFrame frame, engine::Engine& engine) noexcept
{
    frame.serial = ++serial_;
    frame_.store(frame);
    steps_.fetch_add(1, std::memory_order_relaxed);
    stepGestureCount_ = 0;
    engine::GestureEvent g;
    while (engine.popGesture(g)) {
        if (! gestures_.push(g)) gesturesDropped_.fetch_add(1, std::memory_order_relaxed);
        lastGesture_.store(g.name, std::memory_order_relaxed);
        gestureCount_.fetch_add(1, std::memory_order_relaxed);
        if (stepGestureCount_ < kMaxGesturesPerStep) stepGestures_[static_cast<std::size_t>(stepGestureCount_++)] = mapping::GestureIn {g.name, g.value};
    }
}

} // namespace armadillo::live
