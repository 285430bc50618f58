// The tactile engine: targets and patterns → drive shaping → mirroring → safety (thesis §3.2).
//
// Every packet covers the interval [T, T + dt) of engine time. Patterns are sampled at the
// middle of that interval; the jump-start spike is area-exact (the packet in which it ends
// carries the time-weighted mean of spike and target); fractional levels are dithered by error
// diffusion weighted by dt, so the mean level over time equals the requested level for any dt.
#include "Tactile/TactileEngine.h"
#include <algorithm>
#include <cmath>

namespace armadillo::tactile {

namespace {
std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b) noexcept
{
    std::uint64_t x = a ^ (b + 0x9E3779B97F4A7C15ull + (a << 6) + (a >> 2));
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

float sanitise(float level) noexcept
{
    if (!(level > 0.0f)) return 0.0f;   // NaN, negative, zero
    return std::min(level, float(core::kMaxLevel));
}
} // namespace

TactileEngine::TactileEngine() { prepare(TactileConfig {}); }
TactileEngine::~TactileEngine() = default;

void TactileEngine::prepare(const TactileConfig& config)
{
    config_ = config;
    config_.motorCount = std::clamp(config_.motorCount, 0, core::kMaxMotors);
    config_.jumpStartTime = std::max(0.0, config_.jumpStartTime);
    config_.jumpStartLevel = sanitise(config_.jumpStartLevel);
    safety_.prepare(config_.safety, config_.motorCount);
    // The profile is per physical motor; intents are in the right-arm layout, mirrored after
    // shaping for the left arm, so the gain of intent m is that of the motor it lands on.
    for (int m = 0; m < core::kMaxMotors; ++m) {
        int physical = m;
        if (config_.side == core::ArmSide::Left && m < core::kGridMotors && m % 3 != 1) physical = m % 3 == 0 ? m + 2 : m - 2;
        const float g = config_.motorGain[static_cast<std::size_t>(physical)];
        gain_[static_cast<std::size_t>(m)] = std::isfinite(g) && g >= 0.0f ? g : 1.0f;
    }
    for (auto& v : voices_) v = Voice {};
    clearDrive();
    triggerCount_ = 0;
    time_ = 0.0;
    forceOff_ = false;
}

void TactileEngine::setLevel(int motorIndex, float level)
{
    if (motorIndex < 0 || motorIndex >= core::kMaxMotors) return;
    target_[static_cast<std::size_t>(motorIndex)] = sanitise(level);
    softTargets_ = static_cast<std::uint16_t>(softTargets_ & ~(1u << motorIndex));
}

void TactileEngine::setSoftLevel(int motorIndex, float level)
{
    if (motorIndex < 0 || motorIndex >= core::kMaxMotors) return;
    target_[static_cast<std::size_t>(motorIndex)] = sanitise(level);
    softTargets_ = static_cast<std::uint16_t>(softTargets_ | (1u << motorIndex));
}

void TactileEngine::clearLevels()
{
    target_.fill(0.0f);
    softTargets_ = 0;
}

void TactileEngine::trigger(const core::PatternRequest& request)
{
    if (request.voice < 0 || request.voice >= core::kPatternVoices) return;
    Voice& v = voices_[static_cast<std::size_t>(request.voice)];
    const PatternParams& p = config_.patterns;
    const double length = patternLength(request, p);
    if (v.active && patternIsPeriodic(request.kind) && v.request.kind == request.kind
        && v.request.motors == request.motors && v.elapsed < v.length) {
        // The same running texture asked again (a scene updating its rate or level every control
        // step): keep its phase continuous instead of restarting it.
        const double oldRate = patternRate(v.request, p), newRate = patternRate(request, p);
        if (oldRate > 0.0 && newRate > 0.0) v.elapsed *= oldRate / newRate;
        v.request = request;
        v.request.duration = -1.0;   // the voice's length ends it; the shape does not depend on it
        v.length = v.elapsed + length;
        return;
    }
    v.request = request;
    v.elapsed = 0.0;
    v.length = length;
    v.seed = mixSeed(config_.seed, ++triggerCount_);
    v.active = length > 0.0;
}

void TactileEngine::stopVoice(int voice)
{
    if (voice < 0 || voice >= core::kPatternVoices) return;
    voices_[static_cast<std::size_t>(voice)].active = false;
}

bool TactileEngine::voiceActive(int voice) const noexcept
{
    return voice >= 0 && voice < core::kPatternVoices && voices_[static_cast<std::size_t>(voice)].active;
}

void TactileEngine::clearDrive() noexcept
{
    target_.fill(0.0f);
    softTargets_ = 0;
    slewed_.fill(0.0f);
    previous_.fill(0.0f);
    kickLeft_.fill(0.0);
    ditherError_.fill(0.0);
    ditherLevel_.fill(0.0);
    lastShaped_.fill(0);
}

void TactileEngine::allOff() noexcept
{
    for (auto& v : voices_) v.active = false;
    clearDrive();
    forceOff_ = true;
    safety_.allOff();
}

core::MotorLevels TactileEngine::tick(double dt, double motorOnTime) noexcept
{
    if (!(dt >= 0.0) || !std::isfinite(dt)) {
        allOff();
        return safety_.process(core::MotorLevels {}, dt); // the stage treats a bad dt as an error: all off
    }
    std::array<float, core::kMaxMotors> desired {};
    std::uint16_t smooth = 0;

    // Sustained targets, optionally slewed (a fade of 15 levels takes targetFadeIn/Out s).
    for (std::size_t m = 0; m < core::kMaxMotors; ++m) {
        const float goal = target_[m];
        float& s = slewed_[m];
        if (goal > s) s = config_.targetFadeIn > 0.0 ? std::min(goal, s + float(dt * core::kMaxLevel / config_.targetFadeIn)) : goal;
        else if (goal < s) s = config_.targetFadeOut > 0.0 ? std::max(goal, s - float(dt * core::kMaxLevel / config_.targetFadeOut)) : goal;
        desired[m] = s;
        if ((config_.targetFadeIn > 0.0 || (softTargets_ & (1u << m)) != 0) && s > 0.0f)
            smooth = static_cast<std::uint16_t>(smooth | (1u << m));
    }

    // Pattern voices, sampled at the middle of this packet; the loudest wins per motor.
    for (auto& v : voices_) {
        if (!v.active) continue;
        const double mid = std::min(v.elapsed + 0.5 * dt, v.length);
        const PatternSample sample = evaluatePattern(v.request, config_.patterns, mid, v.seed);
        // A click shorter than the spike (its on-time from this packet's start) plays at its
        // own level: a 30 ms spike would be all of it.
        const bool brief = sample.segmentLeft + 0.5 * dt <= config_.jumpStartTime + 1e-9;
        for (int m = 0; m < core::kMaxMotors; ++m) {
            const auto mi = static_cast<std::size_t>(m);
            if ((sample.active & (1u << m)) == 0 || !(sample.level[mi] > desired[mi])) continue;
            desired[mi] = sample.level[mi];
            const auto bit = static_cast<std::uint16_t>(1u << m);
            smooth = static_cast<std::uint16_t>(((sample.smooth & bit) || brief) ? (smooth | bit) : (smooth & ~bit));
        }
        v.elapsed += dt;
        if (v.elapsed >= v.length) v.active = false;
    }

    // The reader's touch profile: each motor's level scaled so all are felt alike (no-op at gain 1).
    for (std::size_t m = 0; m < core::kMaxMotors; ++m)
        if (gain_[m] != 1.0f) desired[m] = std::min(desired[m] * gain_[m], float(core::kMaxLevel));

    // Drive shaping: jump-start and dithering, per motor.
    core::MotorLevels shaped {};
    for (int m = 0; m < config_.motorCount; ++m) {
        const auto mi = static_cast<std::size_t>(m);
        const float x = forceOff_ ? 0.0f : desired[mi];
        const float before = previous_[mi];
        previous_[mi] = x;
        if (!(x > 0.0f)) {   // stop at once: no tail, no carried error
            kickLeft_[mi] = 0.0;
            ditherError_[mi] = 0.0;
            ditherLevel_[mi] = 0.0;
            lastShaped_[mi] = 0;
            continue;
        }
        const bool starts = before < config_.startThreshold && x >= config_.startThreshold;
        const bool jumps = x - before >= config_.jumpUpThreshold;
        if ((starts || jumps) && (smooth & (1u << m)) == 0) kickLeft_[mi] = config_.jumpStartTime;

        double level = static_cast<double>(x);
        if (kickLeft_[mi] > 0.0) {
            const double spike = std::max<double>(x, config_.jumpStartLevel);
            if (dt > 0.0) {
                const double k = std::min(kickLeft_[mi], dt);
                level = (k * spike + (dt - k) * static_cast<double>(x)) / dt;
                kickLeft_[mi] = std::max(0.0, kickLeft_[mi] - dt);
            } else {
                level = spike;
            }
        }
        // Error diffusion in level·s: each packet is one of the two integer levels around the
        // requested one, chosen so the time-weighted mean follows the request whatever dt is.
        // The previous packet's error is booked with the time it really stayed on (this dt).
        const double lo = std::floor(level), hi = std::ceil(level);
        double q = level;
        if (dt > 0.0) {
            ditherError_[mi] = std::clamp(ditherError_[mi] + (ditherLevel_[mi] - double(lastShaped_[mi])) * dt, -0.1, 0.1);
            q = std::clamp(std::round(level + ditherError_[mi] / dt), lo, hi);
        } else {
            q = std::round(level);
        }
        shaped[mi] = static_cast<std::uint8_t>(std::clamp(q, 0.0, double(core::kMaxLevel)));
        ditherLevel_[mi] = level;
        lastShaped_[mi] = shaped[mi];
    }
    forceOff_ = false;

    // Left arm: the grid's columns swap (the back motors run along the arm and stay).
    if (config_.side == core::ArmSide::Left)
        for (int row = 0; row < 3; ++row)
            std::swap(shaped[static_cast<std::size_t>(core::motorIndex(row, 0))], shaped[static_cast<std::size_t>(core::motorIndex(row, 2))]);

    time_ += dt;
    return safety_.process(shaped, motorOnTime >= 0.0 ? motorOnTime : dt);   // last, always
}

} // namespace armadillo::tactile
