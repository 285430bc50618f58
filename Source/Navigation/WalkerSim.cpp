#include "Navigation/WalkerSim.h"
#include "Core/Pose.h"
#include "Engine/Engine.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace armadillo::navigation {

namespace {
constexpr int kLeftSide = 3;    // motorIndex(1, 0): the compass's counter-clockwise cue on the right arm
constexpr int kRightSide = 5;   // motorIndex(1, 2): clockwise
constexpr std::uint16_t kUnderside = (1u << 1) | (1u << 4) | (1u << 7);
} // namespace

SimulatedWalker::SimulatedWalker(const LatLon& start, double headingDeg, const WalkerParams& p)
    : p_(p), pos_(start), heading_(wrap360(headingDeg)), speed_(p.speedMps), rng_(p.seed)
{
    biasX_ = p_.gpsBiasM * normal_(rng_);
    biasY_ = p_.gpsBiasM * normal_(rng_);
}

void SimulatedWalker::feel(double t, const core::MotorLevels& levels) noexcept
{
    t_ = t;
    std::uint16_t on = 0;
    for (int m = 0; m < core::kGridMotors; ++m)
        if (levels[static_cast<std::size_t>(m)] > 0) on |= static_cast<std::uint16_t>(1u << m);
    std::uint16_t was = 0;
    for (int m = 0; m < core::kGridMotors; ++m)
        if (prev_[static_cast<std::size_t>(m)] > 0) was |= static_cast<std::uint16_t>(1u << m);
    const std::uint16_t onsets = on & ~was;
    prev_ = levels;

    // All nine at once: an arrival. Read until the "your turn" double tap (the underside line
    // alone, twice), or the route's end swells, or 40 s.
    if (on == 0x1FF) {
        if (!reading_) ++arrivals_;
        reading_ = true;
        readingSince_ = lastAllNine_ = t;
        undersideTaps_ = 0;
        nameComing_ = false;
    }
    if (reading_) {
        if (on == (1u << 1) && was == 0) nameComing_ = true;   // the "next" sweep starts at the wrist: a name follows
        if (on == kUnderside && was != kUnderside) ++undersideTaps_;
        // Over after the "your turn" double tap; at once when no name follows the arrival pulses.
        if (undersideTaps_ >= 2 || (!nameComing_ && t - lastAllNine_ > 1.2) || t - readingSince_ > 60.0) reading_ = false;
    }

    Cue cue;
    if (!reading_) {
        if (onsets & (1u << kLeftSide)) {
            if (onsetL_ > 0.0) rateL_ = 1.0 / std::max(t - onsetL_, 1e-3);
            onsetL_ = t;
        }
        if (onsets & (1u << kRightSide)) {
            if (onsetR_ > 0.0) rateR_ = 1.0 / std::max(t - onsetR_, 1e-3);
            onsetR_ = t;
        }
        const bool both = (on & (1u << kLeftSide)) && (on & (1u << kRightSide));
        bothSince_ = both ? (bothSince_ < 0.0 ? t : bothSince_) : -1.0;
        const double fresh = 1.3;   // a side whose last click is older than this no longer counts, s
        if (bothSince_ >= 0.0 && t - bothSince_ > 0.05) {
            cue = {0, 0.0};   // on course: hold
            lastCueT_ = t;
        } else if (t - onsetR_ < fresh && onsetR_ >= onsetL_) {
            cue = {+1, rateR_};
            lastCueT_ = t;
        } else if (t - onsetL_ < fresh && onsetL_ > onsetR_) {
            cue = {-1, rateL_};
            lastCueT_ = t;
        }
    }
    delay_[static_cast<std::size_t>(delayHead_)] = cue;
    delayT_[static_cast<std::size_t>(delayHead_)] = t;
    delayHead_ = (delayHead_ + 1) % kDelay;
}

void SimulatedWalker::advance(double dt) noexcept
{
    // The cue felt reactionS ago (the newest one at least that old).
    Cue act;
    for (int i = 1; i <= kDelay; ++i) {
        const auto k = static_cast<std::size_t>((delayHead_ - i + kDelay) % kDelay);
        if (delayT_[k] <= t_ - p_.reactionS) {
            act = delay_[k];
            break;
        }
    }
    if (act.dir != 0) {
        const double rate = std::min(p_.maxTurnDegS, p_.baseTurnDegS + p_.turnPerHzDegS * act.rate);
        heading_ = wrap360(heading_ + act.dir * rate * dt);
    }
    // Slower while reading a name or with no guidance for a while (a careful walker).
    const bool guided = t_ - lastCueT_ < 2.0;
    const double target = reading_ ? 0.5 * p_.speedMps : guided ? p_.speedMps : 0.4 * p_.speedMps;
    speed_ += (target - speed_) * std::min(1.0, dt / 0.8);
    pos_ = destination(pos_, heading_, speed_ * dt);
    swingPhase_ = std::fmod(swingPhase_ + 2.0 * 3.14159265358979323846 * p_.swingHz * dt * (speed_ / std::max(p_.speedMps, 0.1)), 2.0 * 3.14159265358979323846);
    // Tremor: first-order low-passed noise (a few Hz), std ≈ tremorDeg.
    const double a = std::min(1.0, dt * 2.0 * 3.14159265358979323846 * 4.0);
    tremor_ += a * (p_.tremorDeg * std::sqrt(2.0 / std::max(a, 1e-6)) * normal_(rng_) - tremor_);
}

core::ArmState SimulatedWalker::arm(double t) noexcept
{
    core::ArmState s;
    s.t = t;
    s.valid = true;
    double thumb = heading_ + p_.strapOffsetDeg + p_.swingYawDeg * std::sin(swingPhase_) + tremor_;
    if (t >= p_.disturbance.fromS && t < p_.disturbance.toS) {
        thumb += p_.disturbance.biasDeg;
        if (p_.disturbance.flagged) s.magDisturbedS = t - p_.disturbance.fromS + 1.0;
    }
    core::Pose pose;
    pose.azimuthDeg = wrap360(thumb + 90.0);   // the right thumb lies 90° counter-clockwise of the forearm, palm down
    pose.elevationDeg = -10.0 + p_.swingElevationDeg * std::cos(swingPhase_);
    pose.rollDeg = 0.0;
    s.q = poseToQuaternion(pose);
    return s;
}

bool SimulatedWalker::gps(double t, PositionFix& out) noexcept
{
    if (t < nextFixT_) return false;
    const double period = 1.0 / std::max(p_.gpsRateHz, 0.01);
    nextFixT_ = std::max(nextFixT_ + period, t);
    const double phi = std::exp(-period / std::max(p_.gpsBiasTauS, 1e-3));
    const double k = std::sqrt(1.0 - phi * phi) * p_.gpsBiasM;
    biasX_ = phi * biasX_ + k * normal_(rng_);
    biasY_ = phi * biasY_ + k * normal_(rng_);
    LocalPlane plane {pos_};
    out = {};
    out.pos = plane.fromXY(biasX_ + p_.gpsWhiteM * normal_(rng_), biasY_ + p_.gpsWhiteM * normal_(rng_));
    out.quality = FixQuality::Fix2D;
    out.accuracyM = std::hypot(p_.gpsBiasM, p_.gpsWhiteM);
    out.sourceTime = t;
    if (p_.gpsCourse) {
        out.speedMps = std::max(0.0, speed_ + 0.1 * normal_(rng_));
        out.courseDeg = wrap360(heading_ + p_.gpsCourseNoiseDeg * normal_(rng_));
    }
    return true;
}

WalkResult simulateWalk(const Route& route, const NavigationOptions& nav, const WalkerParams& walkerParams, const WalkOptions& options,
                        std::shared_ptr<NavigationLink> link)
{
    if (!link) link = std::make_shared<NavigationLink>();
    engine::EngineConfig config;
    config.scene = "navigate";
    config.sceneConfig.controlRateHz = options.controlHz;
    engine::Engine engine(config, makeNavigationScene(route, link, nav));
    SimulatedWalker walker(route.points.front().pos, options.startHeadingDeg, walkerParams);
    const double dt = 1.0 / options.controlHz;
    WalkResult r;
    std::vector<double> errors;
    double settleUntil = options.settleS;
    int lastArrivals = 0;
    for (double t = 0.0; t < options.maxSeconds; t += dt) {
        PositionFix fix;
        if (walker.gps(t, fix)) link->position.store(fix);
        const core::ArmState arm = walker.arm(t);
        const core::MotorLevels levels = engine.control(arm, core::Transport {}, dt);
        ++r.steps;
        const NavigationStatus st = link->status.load();
        walker.feel(t, levels);
        walker.advance(dt);
        if (options.observe) options.observe(t, WalkerView {walker.position(), walker.bodyHeadingDeg(), walker.reading()}, levels, st);
        if (st.arrivals != lastArrivals) {
            for (int a = lastArrivals; a < st.arrivals; ++a) r.arrivals.push_back(st.waypoint - (st.arrivals - a));
            lastArrivals = st.arrivals;
            settleUntil = t + options.settleS;
        }
        // The true distance from the route (legs up to the one being walked).
        if (!st.finished && st.waypoint >= 2) {
            double best = 1e300;
            for (int k = 1; k < std::min(st.waypoint, static_cast<int>(route.points.size())); ++k)
                best = std::min(best, legDistanceM(route.points[static_cast<std::size_t>(k - 1)].pos, route.points[static_cast<std::size_t>(k)].pos, walker.position()));
            r.maxOffRouteM = std::max(r.maxOffRouteM, best);
            // The compass's own error: where the person walks (the strap removed) against the
            // direction the compass shows (the bearing from the receiver's position).
            if (t >= settleUntil && st.sensation == Sensation::Compass && st.distanceM > 15.0)
                errors.push_back(std::fabs(wrap180(walker.bodyHeadingDeg() - st.bearingDeg)));
        }
        if (st.finished && st.sensation != Sensation::End) {
            r.finished = true;
            r.seconds = t;
            r.learnedOffsetDeg = st.offsetDeg;
            break;
        }
        r.seconds = t;
        r.learnedOffsetDeg = st.offsetDeg;
    }
    if (!errors.empty()) {
        std::sort(errors.begin(), errors.end());
        r.medianHeadingErrorDeg = errors[errors.size() / 2];
        r.p90HeadingErrorDeg = errors[errors.size() * 9 / 10];
    }
    return r;
}

} // namespace armadillo::navigation

namespace armadillo::navigation {

std::string walkResultJson(const WalkResult& r, const Route& route, const WalkerParams& walker)
{
    char json[400];
    std::snprintf(json, sizeof json,
                  "{\"finished\":%s,\"seconds\":%.1f,\"arrivals\":%zu,\"waypoints\":%zu,\"max_off_route_m\":%.2f,\"median_heading_error_deg\":%.2f,"
                  "\"learned_offset_deg\":%.2f,\"strap_offset_deg\":%.2f}",
                  r.finished ? "true" : "false", r.seconds, r.arrivals.size(), route.points.empty() ? std::size_t {0} : route.points.size() - 1,
                  r.maxOffRouteM, r.medianHeadingErrorDeg, r.learnedOffsetDeg, walker.strapOffsetDeg);
    return json;
}

} // namespace armadillo::navigation
