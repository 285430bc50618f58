#pragma once
// What one control step publishes for everyone who is not the step (the UIs, OSC out, Pure Data,
// the web page): the arm and the motor levels that went out, as one value read whole through a
// seqlock (live::StepPublisher), so a reader never mixes two steps' pose and levels.
#include "Core/Types.h"
#include <cstdint>

namespace armadillo::live {

struct ArmFrame {
    double t = 0.0;                          ///< s, control clock
    double q[4] {1.0, 0.0, 0.0, 0.0};        ///< w x y z, device → earth
    double pose[3] {};                       ///< elevation, azimuth, roll (deg)
    double gyro[3] {};                       ///< rad/s, device frame
    core::MotorLevels motors {};             ///< after the safety stage
    int motorCount = core::kGridMotors;
    bool valid = false;
    std::uint64_t serial = 0;                ///< increments with each control update
};

} // namespace armadillo::live
