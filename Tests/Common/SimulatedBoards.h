#pragma once
// Simulated boards the calibration tests share: one whose ADC is not the default calibration's,
// so a guided calibration has real numbers to find.
#include "Link/Simulator.h"

namespace armadillo::testing {

/// Sensor model of a board with its own bias and scale on every axis and a steady gyro bias of
/// zero (the procedure's still step then measures the ADC bias alone).
inline link::SensorModelParams boardWithItsOwnAdc()
{
    link::SensorModelParams p;
    p.adc.accel.bias = Eigen::Vector3d(2100, 1990, 2060);
    p.adc.accel.scale = Eigen::Vector3d(0.026, 0.022, 0.025);
    p.adc.gyro.bias = Eigen::Vector3d(2000, 2090, 2030);
    p.adc.gyro.scale = Eigen::Vector3d(0.0048, 0.0055, 0.0050);
    p.adc.mag.bias = Eigen::Vector3d(1900, 2200, 2010);
    p.adc.mag.scale = Eigen::Vector3d(0.0011, 0.0009, 0.00105);
    p.gyroBiasStart = p.gyroBiasSettled = Eigen::Vector3d::Zero();
    p.gyroBiasWalk = 0.0;
    return p;
}

} // namespace armadillo::testing
