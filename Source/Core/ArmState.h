#pragma once
// What a scene knows about the arm at one control update (thesis §2.6.3 features).
// Filled by the fusion stage (Fusion/ArmFeatures.h) or, under host automation, from a pose.
#include "Core/Pose.h"
#include "Core/Types.h"
#include <Eigen/Geometry>

namespace armadillo::core {

/// Features of thesis §2.6.3, vectors in the earth frame (X east, Y up, Z south).
struct ArmFeatures {
    Eigen::Vector3d axis {0.0, 0.0, -1.0};   ///< forearm axis (device x) in earth, unit
    Eigen::Vector3d normal {0.0, 1.0, 0.0};  ///< board face normal (device y) in earth, unit
    Eigen::Vector3d edge {1.0, 0.0, 0.0};    ///< edge normal (device z) in earth, unit
    Pose pose {};                            ///< elevation / azimuth / roll, degrees
    double fluxFace = 0.0;                   ///< N₁·ω: face normal · angular velocity, rad/s
    double fluxEdge = 0.0;                   ///< N₂·ω: edge normal · angular velocity, rad/s
    double rollTrigger = 0.0;                ///< (x·ω)/√(flux₁²+flux₂²), guarded; dimensionless
    double punch = 0.0;                      ///< forearm-axis linear acceleration while ω is small, m/s² (0 otherwise)
};

struct ArmState {
    double t = 0.0;                                        ///< s, source clock
    Eigen::Quaterniond q = restOrientation();              ///< device → earth
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();        ///< rad/s, device frame (bias removed)
    Eigen::Vector3d accel {kNaN, kNaN, kNaN};              ///< m/s², device frame; NaN when unknown
    ArmFeatures features {};
    /// s since the magnetometer last agreed with the learned field (Fusion's MagneticFieldTracker):
    /// > 0 while the field looks disturbed and the heading rests on the gyro alone; 0 when trusted,
    /// or for sources without a magnetometer of ours (orientations, poses).
    double magDisturbedS = 0.0;
    bool valid = false;                                    ///< false until the source has produced a pose
};

} // namespace armadillo::core
