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
#include <array>
#include <cstdint>
#include <functional>
#include <random>

namespace armadillo::navigation {

struct WalkerParams {
    double speedMps = 1.3;           ///< walking speed, m/s
    double reactionS = 0.25;         ///< from feeling a cue to acting on it, s
    double baseTurnDegS = 10.0;      ///< turn rate at the slowest clicks, deg/s
    double turnPerHzDegS = 1.6;      ///< extra turn rate per Hz of click rate, deg/s/Hz
    double maxTurnDegS = 45.0;
    double strapOffsetDeg = 20.0;    ///< the thumb points this much clockwise of the walking direction
    double tremorDeg = 1.5;          ///< hand tremor on the thumb's heading (std), deg
    double swingElevationDeg = 12.0; ///< arm swing amplitude in elevation, deg
    double swingYawDeg = 4.0;        ///< arm swing amplitude in heading, deg
    double swingHz = 0.9;            ///< one swing per two steps, Hz
    double gpsRateHz = 1.0;
    double gpsBiasM = 4.0;           ///< std of the slowly wandering error per axis, m
    double gpsBiasTauS = 60.0;       ///< its correlation time, s
    double gpsWhiteM = 1.0;          ///< white noise per fix per axis (std), m
    bool gpsCourse = true;           ///< the receiver reports course and speed (Doppler), else NaN
    double gpsCourseNoiseDeg = 6.0;  ///< std of that course at walking speed, deg
    /// A magnetic disturbance (steel, a parked car) from fromS to toS s of the walk: the thumb
    /// heading is bent by biasDeg; `flagged` says whether the fusion reports it (ArmState::magDisturbedS).
    struct Disturbance {
        double fromS = -1.0, toS = -1.0, biasDeg = 0.0;
        bool flagged = true;
    } disturbance {};
    std::uint64_t seed = 1;
};
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

/// The whole loop (tests, `navigate --simulate-walk`, the docs' figures): the scene in an Engine
/// (tactile shaping and safety stage), the walker feeling its levels, the walker's GPS feeding
/// the link, at `controlHz` until the route is finished or `maxSeconds` pass.
struct WalkResult {
    bool finished = false;
    double seconds = 0.0;
    std::vector<int> arrivals;          ///< waypoint indices (1-based) in the order reached
    double maxOffRouteM = 0.0;          ///< the true position's largest distance from the route's legs (after the start), m
    double medianHeadingErrorDeg = 0.0; ///< |walking direction − the bearing the compass shows| while guided, after settling
    double p90HeadingErrorDeg = 0.0;
    double learnedOffsetDeg = 0.0;      ///< the scene's offset at the end
    std::uint64_t steps = 0;
};
struct WalkOptions {
    double controlHz = 100.0;
    double maxSeconds = 3600.0;
    double settleS = 12.0;              ///< after each arrival (and the start) errors are not counted for this long, s
    double startHeadingDeg = 0.0;       ///< the walker's first body heading
    /// Called after every control step (t, the walker, the levels sent, the scene's status): logs.
    std::function<void(double, const SimulatedWalker&, const core::MotorLevels&, const NavigationStatus&)> observe;
};
WalkResult simulateWalk(const Route& route, const NavigationOptions& nav, const WalkerParams& walker, const WalkOptions& options,
                        std::shared_ptr<NavigationLink> link = nullptr);

} // namespace armadillo::navigation
