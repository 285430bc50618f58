#pragma once
// A simulated blind walker guided only by the motors (issue 34's "Done when"): a person who
// walks, feels the compass's clicks on one side and turns toward it after a reaction time, a
// turn rate that grows with the click rate, hand tremor, the arm swinging with the steps and a
// strap turned on the forearm; and a GPS receiver with a slowly wandering error and a little
// white noise at 1 Hz. It never reads the route or the scene: only the motor levels that left
// the safety stage. Used by tests_navigation, `armadillo navigate --simulate-walk` and the
// figures of docs/NAVIGATION.md. Deterministic for a seed.
#include "Core/ArmState.h"
#include "Core/Types.h"
#include "Navigation/NavigationScene.h"
#include "Navigation/WalkRehearsal.h"
#include <array>
#include <cstdint>
#include <functional>
#include <random>

namespace armadillo::navigation {

inline constexpr WalkerParams kDefaultWalkerParams {};

class SimulatedWalker {
public:
    SimulatedWalker(const LatLon& start, double headingDeg, const WalkerParams& p = kDefaultWalkerParams);
    /// The motor levels (after the safety stage) felt at time t.
    void feel(double t, const core::MotorLevels& levels) noexcept;
    /// Moves the body on by dt (turning as decided reactionS ago, walking).
    void advance(double dt) noexcept;
    /// The forearm's state at time t (thumb heading = body + strap + swing + tremor; swinging elevation).
    core::ArmState arm(double t) noexcept;
    /// A position report when one is due at time t (every 1/gpsRateHz s).
    bool gps(double t, PositionFix& out) noexcept;

    LatLon position() const noexcept { return pos_; }
    double bodyHeadingDeg() const noexcept { return heading_; }
    bool reading() const noexcept { return reading_; }
    int cellsFelt() const noexcept { return arrivals_; }   ///< arrival sensations felt

private:
    struct Cue { int dir = 0; double rate = 0.0; };   // −1 counter-clockwise, +1 clockwise
    WalkerParams p_;
    LatLon pos_ {};
    double heading_ = 0.0, speed_ = 0.0, t_ = 0.0;
    std::mt19937_64 rng_;
    std::normal_distribution<double> normal_ {0.0, 1.0};
    // Perception.
    std::array<std::uint8_t, core::kMaxMotors> prev_ {};
    double onsetL_ = -1e9, onsetR_ = -1e9, rateL_ = 0.0, rateR_ = 0.0, bothSince_ = -1.0;
    bool reading_ = false, nameComing_ = false;
    double lastAllNine_ = -1e9;
    int undersideTaps_ = 0, arrivals_ = 0;
    double readingSince_ = 0.0, lastCueT_ = -1e9;
    static constexpr int kDelay = 1024;
    std::array<Cue, kDelay> delay_ {};
    std::array<double, kDelay> delayT_ {};
    int delayHead_ = 0;
    double tremor_ = 0.0;
    double biasX_ = 0.0, biasY_ = 0.0, nextFixT_ = 0.0;
    double swingPhase_ = 0.0;
};

} // namespace armadillo::navigation
