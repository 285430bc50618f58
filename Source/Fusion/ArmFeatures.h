#pragma once
// Arm features of thesis §2.6.3 from an orientation, the angular velocity and the accelerometer:
// orientation/normal/edge vectors, pose, flux through face and edge, the roll-trigger metric and
// the punch ("button push") signal. Pure functions: tested alone, used by ArmTracker.
#include "Core/ArmState.h"
#include "Core/Types.h"
#include <Eigen/Geometry>

namespace armadillo::fusion {

/// Below this flux magnitude (rad/s) the roll trigger's denominator is held here: the division by
/// zero the thesis warns about, and noise-sized sweeps cannot make the ratio explode.
inline constexpr double kRollTriggerFluxFloor = 0.05;
/// Punch counts only while |ω| is below this (rad/s): otherwise centripetal acceleration (thesis).
inline constexpr double kPunchMaxRate = 1.0;

/// features: vectors in the earth frame (X east, Y up, Z south), q device → earth,
/// gyroDevice rad/s (bias removed), accelDevice m/s² specific force (NaN ⇒ punch = 0).
core::ArmFeatures computeArmFeatures(const Eigen::Quaterniond& q, const Eigen::Vector3d& gyroDevice,
                               const Eigen::Vector3d& accelDevice);

/// The side of the forearm that leads a movement (thesis §2.6.3, §3.6 crash cymbal).
enum class FluxSide { None, Thumb, Palm, FifthFinger, Back };

/// Leading side from the flux: the hand moves along ω × x = (0, fluxEdge, −fluxFace) in the
/// device frame; the larger component picks face/palm (±y) or the thumb/fifth-finger edge (±z),
/// its sign the side. Which edge is the thumb depends on the arm (right arm, palm down: −z).
/// Returns None while max(|flux|) < minRate (rad/s).
FluxSide leadingSide(const core::ArmFeatures& f, core::ArmSide arm = core::ArmSide::Right, double minRate = 0.2);

} // namespace armadillo::fusion
