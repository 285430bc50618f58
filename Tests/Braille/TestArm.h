#pragma once
// Scripted arm motions for the braille tests: ArmState sequences built from poses with the one
// pose → quaternion conversion of Core (INTERFACES.md), sampled at the thesis's ~200 updates/s.
#include "Core/ArmState.h"
#include "Core/Pose.h"
#include <vector>

namespace armadillo::braille::test {

inline constexpr double kRate = 200.0;   // control updates per second
inline constexpr double kDt = 1.0 / kRate;

struct Motion {
    std::vector<core::ArmState> states;
    double t = 0.0;

    void add(const core::Pose& p)
    {
        core::ArmState s;
        s.t = t;
        s.q = poseToQuaternion(p);
        s.valid = true;
        states.push_back(s);
        t += kDt;
    }
    /// Holds a pose for `seconds`.
    void hold(const core::Pose& p, double seconds)
    {
        for (int i = 0, n = static_cast<int>(seconds * kRate); i < n; ++i) add(p);
    }
    /// Moves linearly in (elevation, azimuth, roll) from a to b over `seconds`.
    void move(const core::Pose& a, const core::Pose& b, double seconds)
    {
        const int n = static_cast<int>(seconds * kRate);
        for (int i = 1; i <= n; ++i) {
            const double f = static_cast<double>(i) / n;
            add({a.elevationDeg + f * (b.elevationDeg - a.elevationDeg), a.azimuthDeg + f * (b.azimuthDeg - a.azimuthDeg),
                 a.rollDeg + f * (b.rollDeg - a.rollDeg)});
        }
    }
};

/// The hanging arm (thesis §4.3: forearm pointing down) with the board's normal turned `roll`.
/// Azimuth 90 like level(), so raising the arm from one to the other is a pure elevation change.
inline core::Pose hanging(double roll, double tiltDeg = 0.0) { return {-90.0 + tiltDeg, 90.0, roll}; }
/// The forearm held level, pointing east, board rolled by `roll`.
inline core::Pose level(double roll, double elevation = 0.0) { return {elevation, 90.0, roll}; }

} // namespace armadillo::braille::test
