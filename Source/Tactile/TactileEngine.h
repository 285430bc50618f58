#pragma once
// The tactile engine (thesis §3.2, ARMADILLO.md §6): every scene writes its intents here, and the
// only levels that ever leave are those of tick(), after the drive shaping and the safety stage.
//
//   sustained targets ─┐
//                      ├─ max ─→ drive shaping ─→ left-arm mirroring ─→ SafetyStage ─→ MotorLevels
//   pattern voices ────┘        (fades, jump-start,
//                                dithering)
//
// Everything runs on the control thread. prepare() allocates; tick() and the MotorCanvas calls do
// not. Times are seconds, levels are 0..15 PWM steps (level 5 = the motors' 3 V rating).
#include "Core/Scene.h"
#include "Core/Types.h"
#include "Tactile/Patterns.h"
#include <array>
#include <cstdint>
#include <vector>

namespace armadillo::tactile {

/// The overheating rules of thesis §3.2.3, as bounds on the output of every motor.
struct SafetyParams {
    int ratedLevel = core::kRatedLevel;   ///< level; above it the motor heats up (duty 0.33 of 9 V)
    double maxAboveRatingRun = 0.300;     ///< s: longest uninterrupted run above ratedLevel
    double aboveRatingWindow = 2.0;       ///< s: sliding window for the duty limit below
    double maxAboveRatingFraction = 0.30; ///< fraction of any aboveRatingWindow spent above rating
    double powerWindow = 10.0;            ///< s: sliding window for the mean-power limit
    double maxMeanPower = (5.0 / 15.0) * (5.0 / 15.0); ///< mean of (level/15)² over any powerWindow
    double maxOnRun = 60.0;               ///< s: longest uninterrupted run at any level > 0 (soft too)
    double restAfterOnRun = 5.0;          ///< s: forced silence after a motor reached maxOnRun
    /// s: how long the stage assumes a packet stays on. Each decision is planned for
    /// max(maxHoldTime, dt); the bounds are guaranteed while no packet is held longer than that.
    double maxHoldTime = 0.025;
};
inline constexpr SafetyParams kDefaultSafetyParams {};

/// The last stage before every motor packet. Exact sliding-window accounting of what it has put
/// out; each motor's level is the highest one ≤ the request that keeps every bound true for the
/// whole time the packet may stay on. Can be driven alone (property tests do).
class SafetyStage {
public:
    SafetyStage();
    /// Not real-time: sizes the per-motor history. Clears all history.
    void prepare(const SafetyParams& params, int motorCount = core::kMaxMotors);
    /// `dt` s since the previous call (the time the previous output was on); `requested` levels
    /// 0..15 (larger values clamp to 15). Returns the levels to send now. A non-finite or
    /// negative dt is an error: everything off. Allocates nothing.
    core::MotorLevels process(const core::MotorLevels& requested, double dt) noexcept;
    /// The next process() call returns all zeros whatever is requested; the heat history is kept.
    void allOff() noexcept { forceOff_ = true; }
    const SafetyParams& params() const noexcept { return params_; }
    int motorCount() const noexcept { return motorCount_; }
    /// Levels of the last process() call.
    const core::MotorLevels& lastOutput() const noexcept { return last_; }
    /// How many levels were lowered in the last process() call (0 = nothing limited).
    int limitedCount() const noexcept { return limited_; }

private:
    struct History;
    std::uint64_t seek(int m, double t, std::uint64_t& cursor) const noexcept;
    void push(int m, std::uint8_t level) noexcept;
    void dropOld(int m) noexcept;

    SafetyParams params_ {};
    int motorCount_ = core::kMaxMotors;
    std::size_t capacity_ = 0;                 ///< records per motor (power of two)
    // Per-motor run-length history of the output: record r starts at start_[r] with level level_[r];
    // cumE_/cumA_ = integral of level² / of (level > rated) from time 0 to start_[r].
    std::vector<double> start_, cumE_, cumA_;
    std::vector<std::uint8_t> level_;
    std::array<std::uint64_t, core::kMaxMotors> oldest_ {}, newest_ {};
    std::array<std::uint64_t, core::kMaxMotors> powerCursor_ {}, dutyCursor_ {}; ///< window-edge search starts
    std::array<double, core::kMaxMotors> aboveRun_ {}, onRun_ {}, rest_ {};
    core::MotorLevels last_ {};
    double now_ = 0.0;
    bool forceOff_ = false;
    int limited_ = 0;
};

struct TactileConfig {
    int motorCount = core::kGridMotors;   ///< 9, 12 with the back motors, up to 16
    core::ArmSide side = core::ArmSide::Right; ///< Left mirrors the grid's columns (back motors stay)
    SafetyParams safety {};
    PatternParams patterns {};            ///< timings and shapes of the pattern library
    std::uint64_t seed = 1;               ///< random patterns (tickle) derive from this
    // Drive shaping (thesis §3.2.2).
    double jumpStartTime = 0.030;         ///< s at jumpStartLevel when a motor starts or jumps up
    float jumpStartLevel = 15.0f;         ///< level of the start spike (9 V)
    float startThreshold = 0.5f;          ///< level; a motor "starts" when rising from below this
    float jumpUpThreshold = 4.0f;         ///< levels; a rise at least this big within one packet kicks too
    double targetFadeIn = 0.0;            ///< s for a sustained target to rise 15 levels (0 = step)
    double targetFadeOut = 0.0;           ///< s for a sustained target to fall 15 levels (0 = step)
    /// The reader's touch profile (issue 26, docs/TACTILE.md "Touch fitted to the reader"): a gain
    /// per motor in the order of the motor packet (m1 at index 0, the physical motor, whichever
    /// arm), so that every motor is felt alike. Applied to the requested level before the drive
    /// shaping and the safety stage (the result is clamped to 15; the safety stage still has the
    /// last word). All 1 = no profile. Non-finite or negative gains count as 1.
    std::array<float, core::kMaxMotors> motorGain = unitMotorGains();

    static constexpr std::array<float, core::kMaxMotors> unitMotorGains() noexcept
    {
        std::array<float, core::kMaxMotors> g {};
        for (float& x : g) x = 1.0f;
        return g;
    }
};

class TactileEngine final : public core::MotorCanvas {
public:
    TactileEngine();
    ~TactileEngine() override;
    /// Not real-time: allocates, resets everything (targets, voices, shaping, safety history).
    void prepare(const TactileConfig& config);
    /// Advances dt s (the time since the previous tick, i.e. how long the previous packet was
    /// on) and returns the levels of the packet that starts now. Sustained targets and pattern
    /// voices → drive shaping → mirroring → SafetyStage (last). Allocates nothing.
    /// `motorOnTime` (≥ 0) is how long the previous packet really stayed on the motor when that
    /// differs from dt: a front end whose link schedules levels on the wall clock (the plugin:
    /// Link/LevelSchedule.h) passes it after a host stall, so the safety stage charges what the
    /// motor got, not the audio timeline's tick. Negative: the same as dt.
    core::MotorLevels tick(double dt, double motorOnTime = -1.0) noexcept;
    /// Stop, disconnect or error: everything off at once; patterns and targets cleared. The
    /// next tick returns zeros; the safety stage keeps its heat history.
    void allOff() noexcept;

    // MotorCanvas (indices in the right-arm layout; the engine mirrors for the left arm).
    void setLevel(int motorIndex, float level) override;
    void setSoftLevel(int motorIndex, float level) override;
    void clearLevels() override;
    void trigger(const core::PatternRequest& request) override;
    void stopVoice(int voice) override;

    const TactileConfig& config() const noexcept { return config_; }
    const SafetyStage& safety() const noexcept { return safety_; }
    bool voiceActive(int voice) const noexcept;
    double time() const noexcept { return time_; }   ///< s of engine time (sum of dt)

private:
    struct Voice {
        core::PatternRequest request {};
        double elapsed = 0.0;      ///< s since the pattern started (at the start of the next packet)
        double length = 0.0;       ///< s; infinity = until stopped
        std::uint64_t seed = 0;
        bool active = false;
    };
    /// Forgets every sustained target and all shaping state (prepare and allOff share this).
    void clearDrive() noexcept;

    TactileConfig config_ {};
    SafetyStage safety_;
    std::array<Voice, core::kPatternVoices> voices_ {};
    std::array<float, core::kMaxMotors> gain_ {};  ///< config_.motorGain in the right-arm layout
    std::array<float, core::kMaxMotors> target_ {}; ///< sustained targets (right-arm layout)
    std::uint16_t softTargets_ = 0;                ///< targets set by setSoftLevel (never kicked)
    std::array<float, core::kMaxMotors> slewed_ {}; ///< targets after targetFadeIn/Out
    std::array<float, core::kMaxMotors> previous_ {}; ///< desired level of the previous packet
    std::array<double, core::kMaxMotors> kickLeft_ {}; ///< s of jump-start spike still to give
    std::array<double, core::kMaxMotors> ditherError_ {};///< level·s carried by the error diffusion
    std::array<double, core::kMaxMotors> ditherLevel_ {};///< level the previous packet stood for
    core::MotorLevels lastShaped_ {};              ///< the previous packet, before mirroring
    std::uint64_t triggerCount_ = 0;
    double time_ = 0.0;
    bool forceOff_ = false;
};

} // namespace armadillo::tactile
