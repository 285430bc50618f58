#pragma once
// The pattern library: the sensations of thesis §3.2.6 (and the pulse shapes the applications of
// §3.3–4.1 need) as pure functions of time. A pattern is evaluated at any time t since it started,
// so its timing does not depend on how often anyone looks at it. Motor indices use the right-arm
// layout (row 0 = wrist, 2 = elbow; col 0 = left, 1 = underside, 2 = right); the engine mirrors.
#include "Core/Scene.h"
#include "Core/Types.h"
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

namespace armadillo::tactile {

/// Named motor sets (bit i = motor index i). The anchors are the motors lying on bone (thesis
/// §3.2.6, [CCB01]): both sides of the wrist, and the two side columns along radius and ulna.
namespace motors {
constexpr std::uint16_t bit(int index) noexcept { return static_cast<std::uint16_t>(1u << index); }
constexpr std::uint16_t row(int r) noexcept { return static_cast<std::uint16_t>(0x7u << (3 * r)); }
constexpr std::uint16_t column(int c) noexcept
{
    return static_cast<std::uint16_t>(bit(core::motorIndex(0, c)) | bit(core::motorIndex(1, c)) | bit(core::motorIndex(2, c)));
}
inline constexpr std::uint16_t kGrid = 0x01FF;
inline constexpr std::uint16_t kBack = 0x0E00;             ///< motors 10..12
inline constexpr std::uint16_t kWristRow = row(0);
inline constexpr std::uint16_t kMiddleRow = row(1);
inline constexpr std::uint16_t kElbowRow = row(2);
inline constexpr std::uint16_t kLeftColumn = column(0);
inline constexpr std::uint16_t kUndersideColumn = column(1);
inline constexpr std::uint16_t kRightColumn = column(2);
/// Wrist-bone anchors: felt as two distinct points even together (thesis Figure 3-11).
inline constexpr std::uint16_t kWristAnchors = bit(core::motorIndex(0, 0)) | bit(core::motorIndex(0, 2));
/// Every motor lying on bone: the wrist pair and both side columns (radius and ulna).
inline constexpr std::uint16_t kBoneAnchors = kLeftColumn | kRightColumn;
} // namespace motors

/// Tunable timings and shapes. Every field in seconds, Hz or levels as named.
struct PatternParams {
    double pointTime = 0.20;        ///< s: Point default duration
    double pulseAttack = 0.010;     ///< s: Pulse rise
    double pulseTime = 0.15;        ///< s: Pulse default duration (attack + linear decay)
    double fadeTime = 0.30;         ///< s: FadeInPulse / FadeOutPulse default duration
    double breathingRate = 0.25;    ///< Hz: breaths per second
    float breathingFloor = 0.0f;    ///< fraction of `level` at the bottom of a breath
    double joltTime = 0.060;        ///< s: Jolt default duration (a shove)
    double tickleStep = 0.040;      ///< s between tickle touches
    double tickleTouch = 0.025;     ///< s per touch
    float tickleScale = 0.6f;       ///< fraction of `level` per touch (light)
    double massageRate = 0.5;       ///< Hz: trips around the motors per second
    double twistRate = 0.5;         ///< Hz: configurations per second (each fades into the next)
    double glassEvent = 0.25;       ///< s per broken-glass event
    double glassArrivalStretch = 1.6; ///< the wrist (arrival) event lasts this many events
    float glassArrivalBoost = 2.0f; ///< levels added to the arrival event
    double accentTime = 0.10;       ///< s: Accent default duration
    double gearRate = 6.0;          ///< Hz: GearPull steps per second (two steps per alternation)
    double gearDuty = 0.6;          ///< fraction of a GearPull step that is on
    double geigerRate = 4.0;        ///< Hz: Geiger clicks per second
    double geigerClick = 0.020;     ///< s per Geiger click
};
inline constexpr PatternParams kDefaultPatternParams {};

/// Stable names used by score files and docs: "point", "pulse", "fade-in-pulse",
/// "fade-out-pulse", "breathing", "jolt", "tickle", "massage", "twist", "broken-glass",
/// "accent", "gear-pull", "geiger".
std::string_view patternName(core::PatternKind kind) noexcept;
std::optional<core::PatternKind> patternKindFromName(std::string_view name) noexcept;
inline constexpr int kPatternKinds = 13;

/// True for patterns that repeat until stopped when `duration` is 0.
bool patternIsPeriodic(core::PatternKind kind) noexcept;
/// The pattern's length in s: request.duration when > 0, infinity when < 0 (until stopped),
/// else the pattern's default (infinity for periodic patterns, BrokenGlass included).
double patternLength(const core::PatternRequest& request, const PatternParams& params) noexcept;
/// The rate in Hz a periodic pattern runs at (request.rate, or the pattern's default); the
/// phase of a periodic pattern is t × this rate. 0 for one-shot patterns.
double patternRate(const core::PatternRequest& request, const PatternParams& params) noexcept;
/// Length in s of one broken-glass sequence (shown once, then mirrored).
double brokenGlassCycle(const PatternParams& params) noexcept;

/// One instant of a pattern.
struct PatternSample {
    std::array<float, core::kMaxMotors> level {}; ///< 0..15 per motor (right-arm layout)
    std::uint16_t active = 0;                 ///< motors this pattern drives now (level > 0)
    std::uint16_t smooth = 0;                 ///< motors whose rise is a fade (no jump-start)
    /// s from t until the current on-segment of the active motors ends (a click, a touch, a
    /// one-shot's end); infinity when it lasts until stopped. The engine gives no jump-start to
    /// a segment shorter than its spike: such a click plays at its own level.
    double segmentLeft = std::numeric_limits<double>::infinity();
};

/// The pattern at time t s after it started (t may be any value in [0, length)). `seed` picks
/// the random choices (tickle); the same seed gives the same touches.
PatternSample evaluatePattern(const core::PatternRequest& request, const PatternParams& params, double t,
                              std::uint64_t seed) noexcept;

} // namespace armadillo::tactile
