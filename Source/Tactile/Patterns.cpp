// The pattern library (thesis §3.2.6, §3.3.2, §3.4–3.6, §4.1). Each pattern is a pure function of
// the time since it started; see Patterns.h and docs/TACTILE.md for the shapes.
#include "Tactile/Patterns.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace armadillo::tactile {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct NamedKind {
    std::string_view name;
    core::PatternKind kind;
};
constexpr NamedKind kNames[kPatternKinds] = {
    {"point", core::PatternKind::Point},           {"pulse", core::PatternKind::Pulse},
    {"fade-in-pulse", core::PatternKind::FadeInPulse}, {"fade-out-pulse", core::PatternKind::FadeOutPulse},
    {"breathing", core::PatternKind::Breathing},   {"jolt", core::PatternKind::Jolt},
    {"tickle", core::PatternKind::Tickle},         {"massage", core::PatternKind::Massage},
    {"twist", core::PatternKind::Twist},           {"broken-glass", core::PatternKind::BrokenGlass},
    {"accent", core::PatternKind::Accent},         {"gear-pull", core::PatternKind::GearPull},
    {"geiger", core::PatternKind::Geiger},
};

std::uint64_t mix(std::uint64_t x) noexcept   // splitmix64 finaliser: a stateless random choice
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

float clampLevel(float level) noexcept
{
    if (!(level >= 0.0f)) return 0.0f;   // NaN and negatives
    return std::min(level, float(core::kMaxLevel));
}

double rateOr(const core::PatternRequest& r, double fallback) noexcept
{
    return (r.rate > 0.0 && std::isfinite(r.rate)) ? r.rate : fallback;
}

void put(PatternSample& s, int index, float level, bool smooth) noexcept
{
    if (index < 0 || index >= core::kMaxMotors || !(level > 0.0f)) return;
    const auto i = static_cast<std::size_t>(index);
    s.level[i] = std::max(s.level[i], std::min(level, float(core::kMaxLevel)));
    s.active = static_cast<std::uint16_t>(s.active | (1u << index));
    if (smooth) s.smooth = static_cast<std::uint16_t>(s.smooth | (1u << index));
}

void putMask(PatternSample& s, std::uint16_t mask, float level, bool smooth) noexcept
{
    for (int i = 0; i < core::kMaxMotors; ++i)
        if (mask & (1u << i)) put(s, i, level, smooth);
}

// The motors of `mask` in the order a touch travels around the arm: the grid's ring (wrist row
// left→right, down the right column, elbow row right→left, up the left column), then the centre,
// then the back and spare motors.
int ringOrder(std::uint16_t mask, std::array<int, core::kMaxMotors>& order) noexcept
{
    static constexpr int kRing[] = {0, 1, 2, 5, 8, 7, 6, 3, 4, 9, 10, 11, 12, 13, 14, 15};
    int n = 0;
    for (int index : kRing)
        if (mask & (1u << index)) order[static_cast<std::size_t>(n++)] = index;
    return n;
}

// Broken glass (thesis Figure 3-18): events travelling from the elbow to the wrist; the arrival at
// the wrist lasts longer and is stronger, which is what makes it read as motion. The mirrored
// pass swaps the left and right columns.
constexpr int kGlassPath[] = {core::motorIndex(2, 2), core::motorIndex(2, 1), core::motorIndex(1, 1), core::motorIndex(1, 0), core::motorIndex(0, 0)};
constexpr int kGlassEvents = 5;

int mirrorColumn(int index) noexcept
{
    if (index < 0 || index >= core::kGridMotors) return index;
    const int row = index / 3, col = index % 3;
    return core::motorIndex(row, 2 - col);
}

} // namespace

std::string_view patternName(core::PatternKind kind) noexcept
{
    for (const auto& n : kNames)
        if (n.kind == kind) return n.name;
    return "unknown";
}

std::optional<core::PatternKind> patternKindFromName(std::string_view name) noexcept
{
    for (const auto& n : kNames)
        if (n.name == name) return n.kind;
    return std::nullopt;
}

bool patternIsPeriodic(core::PatternKind kind) noexcept
{
    switch (kind) {
    case core::PatternKind::Breathing:
    case core::PatternKind::Tickle:
    case core::PatternKind::Massage:
    case core::PatternKind::Twist:
    case core::PatternKind::BrokenGlass:
    case core::PatternKind::GearPull:
    case core::PatternKind::Geiger: return true;
    default: return false;
    }
}

double patternRate(const core::PatternRequest& r, const PatternParams& p) noexcept
{
    switch (r.kind) {
    case core::PatternKind::Breathing: return rateOr(r, p.breathingRate);
    case core::PatternKind::Tickle: return rateOr(r, 1.0 / p.tickleStep);
    case core::PatternKind::Massage: return rateOr(r, p.massageRate);
    case core::PatternKind::Twist: return rateOr(r, p.twistRate);
    case core::PatternKind::BrokenGlass: return rateOr(r, 1.0 / p.glassEvent);
    case core::PatternKind::GearPull: return rateOr(r, p.gearRate);
    case core::PatternKind::Geiger: return rateOr(r, p.geigerRate);
    default: return 0.0;
    }
}

double brokenGlassCycle(const PatternParams& p) noexcept
{
    return 2.0 * p.glassEvent * (kGlassEvents - 1 + p.glassArrivalStretch);
}

double patternLength(const core::PatternRequest& r, const PatternParams& p) noexcept
{
    if (r.duration > 0.0) return r.duration;
    if (r.duration < 0.0 || std::isnan(r.duration)) return r.duration < 0.0 ? kInfinity : 0.0;
    switch (r.kind) {
    case core::PatternKind::Point: return p.pointTime;
    case core::PatternKind::Pulse: return p.pulseTime;
    case core::PatternKind::FadeInPulse:
    case core::PatternKind::FadeOutPulse: return p.fadeTime;
    case core::PatternKind::Jolt: return p.joltTime;
    case core::PatternKind::Accent: return p.accentTime;
    default: return kInfinity;
    }
}

PatternSample evaluatePattern(const core::PatternRequest& r, const PatternParams& p, double t, std::uint64_t seed) noexcept
{
    PatternSample s;
    const double length = patternLength(r, p);
    if (!(t >= 0.0) || !(t < length)) return s;
    const float level = clampLevel(r.level);
    const std::uint16_t mask = r.motors;
    switch (r.kind) {
    case core::PatternKind::Point:
    case core::PatternKind::Jolt:
    case core::PatternKind::Accent:
        putMask(s, mask, level, false);
        s.segmentLeft = length - t;
        break;

    case core::PatternKind::Pulse: {
        const double attack = std::min(p.pulseAttack, 0.5 * length);
        const double v = t < attack ? t / attack : 1.0 - (t - attack) / (length - attack);
        putMask(s, mask, level * float(v), false);
        s.segmentLeft = length - t;
        break;
    }
    case core::PatternKind::FadeInPulse:
        if (std::isfinite(length)) putMask(s, mask, level * float(t / length), true);
        else putMask(s, mask, level, true);
        break;
    case core::PatternKind::FadeOutPulse: // a fade: it cuts in at its level, never with a spike
        if (std::isfinite(length)) putMask(s, mask, level * float(1.0 - t / length), true);
        else putMask(s, mask, level, true);
        break;

    case core::PatternKind::Breathing: {
        const double phase = t * rateOr(r, p.breathingRate);
        const double swell = 0.5 * (1.0 - std::cos(2.0 * core::kPi * phase));
        const double floor = static_cast<double>(p.breathingFloor);
        const double v = floor + (1.0 - floor) * swell;
        putMask(s, mask, level * float(v), true);
        break;
    }
    case core::PatternKind::Tickle: {
        // Touches at random motors, one per step (thesis Figure 3-13: chaotic, very quick).
        std::array<int, core::kMaxMotors> order {};
        const int n = ringOrder(mask, order);
        if (n == 0) break;
        const double step = 1.0 / rateOr(r, 1.0 / p.tickleStep);
        const double k = std::floor(t / step);
        const double touch = std::min(p.tickleTouch, step);
        if (t - k * step >= touch) break;
        s.segmentLeft = touch - (t - k * step);
        const auto pick = mix(seed ^ mix(static_cast<std::uint64_t>(k))) % static_cast<std::uint64_t>(n);
        put(s, order[static_cast<std::size_t>(pick)], level * p.tickleScale, true);
        break;
    }
    case core::PatternKind::Massage: {
        // Slow swells travelling around the arm, each overlapping its neighbours (Figure 3-14).
        std::array<int, core::kMaxMotors> order {};
        const int n = ringOrder(mask, order);
        if (n == 0) break;
        const double position = std::fmod(t * rateOr(r, p.massageRate) * n, double(n));
        constexpr double kHalfWidth = 1.5;   // motors: each swell reaches the next motor's peak
        for (int i = 0; i < n; ++i) {
            double d = std::fabs(position - i);
            d = std::min(d, n - d);
            if (d < kHalfWidth)
                put(s, order[static_cast<std::size_t>(i)], level * float(0.5 * (1.0 + std::cos(core::kPi * d / kHalfWidth))), true);
        }
        break;
    }
    case core::PatternKind::Twist: {
        // Helical stripes wound around the arm: stripe k = {(row, (row + k) mod 3)}. Each fades
        // into the next, so the stripe turns around the arm (thesis §3.3.2, Figure 3-17).
        const double position = t * rateOr(r, p.twistRate);
        const double k = std::floor(position);
        const double f = position - k;
        const int a = static_cast<int>(std::fmod(k, 3.0)), b = (a + 1) % 3;
        for (int row = 0; row < 3; ++row) {
            const int ia = core::motorIndex(row, (row + a) % 3), ib = core::motorIndex(row, (row + b) % 3);
            if (mask & (1u << ia)) put(s, ia, level * float(std::cos(0.5 * core::kPi * f)), true);
            if (mask & (1u << ib)) put(s, ib, level * float(std::sin(0.5 * core::kPi * f)), true);
        }
        break;
    }
    case core::PatternKind::BrokenGlass: {
        const double event = 1.0 / rateOr(r, 1.0 / p.glassEvent);
        PatternParams q = p;
        q.glassEvent = event;
        const double cycle = brokenGlassCycle(q);
        double u = std::fmod(t, cycle);
        const bool mirrored = u >= 0.5 * cycle;
        if (mirrored) u -= 0.5 * cycle;
        const double step = u / event;
        if (!(step >= 0.0)) break;   // a cycle too short to represent: nothing sensible to show
        const int e = static_cast<int>(std::min(double(kGlassEvents - 1), step));
        const int index = mirrored ? mirrorColumn(kGlassPath[e]) : kGlassPath[e];
        const bool arrival = e == kGlassEvents - 1;
        if ((mask & (1u << index)) == 0) break;
        put(s, index, arrival ? clampLevel(level + p.glassArrivalBoost) : level, false);
        s.segmentLeft = (arrival ? 0.5 * cycle - u : (e + 1) * event - u);
        break;
    }
    case core::PatternKind::GearPull: {
        // Pulling against a gear train: short pulses alternating between the outer rows (wrist
        // and elbow) and the middle row, like teeth slipping one by one.
        const double position = t * rateOr(r, p.gearRate);
        const double k = std::floor(position);
        if (position - k >= p.gearDuty) break;
        s.segmentLeft = (p.gearDuty - (position - k)) / rateOr(r, p.gearRate);
        const bool outer = std::fmod(k, 2.0) < 0.5;
        const std::uint16_t rows = outer ? (motors::kWristRow | motors::kElbowRow) : motors::kMiddleRow;
        putMask(s, static_cast<std::uint16_t>(mask & rows), level, false);
        break;
    }
    case core::PatternKind::Geiger: {
        const double period = 1.0 / rateOr(r, p.geigerRate);
        const double u = t - std::floor(t / period) * period;
        const double click = std::min(p.geigerClick, 0.5 * period);
        if (u < click) {
            putMask(s, mask, level, false);
            s.segmentLeft = click - u;
        }
        break;
    }
    }
    if (r.soft) s.smooth = s.active;   // the intent asked for a soft start
    return s;
}

} // namespace armadillo::tactile
