#pragma once
// The board protects the skin by itself (issue 15; thesis §3.2.3 "never overheat"). A second line
// behind the host's SafetyStage, deliberately looser than it so it never acts on a healthy host:
//  - link watchdog: no valid motor packet for linkTimeoutMs ⇒ every motor off (host crashed, link
//    lost, cable pulled). Power-on and reset start in that state: off until the first packet.
//  - heat limit per motor: a leaky bucket of time above the motors' rating (level 5 = 3 V of a
//    9 V supply, ARMADILLO.md §6). It fills at 1 ms/ms above the rating and drains at
//    1/coolDivisor ms/ms at or below it; when it holds maxAboveMs the motor is held at its rating
//    until the bucket is empty again. With the defaults (1 s, ÷2) no motor spends more than 1 s in
//    a row, or more than a third of any long stretch, above its rating. The host's stage allows
//    0.3 s runs and 30 % of any 2 s, which stays inside this bucket.
// Integer milliseconds only (the ATmega2560 has no FPU); plain C++ for host unit tests.
#include <stdint.h>
#include "Protocol.h"

namespace armfw {

struct SafetyParams {
    uint16_t linkTimeoutMs = 50;   ///< ms without a valid motor packet ⇒ all off
    uint8_t ratedLevel = 5;        ///< level 0..15: above it the motor heats up
    uint16_t maxAboveMs = 1000;    ///< ms: bucket size (longest run above the rating from cold)
    uint8_t coolDivisor = 2;       ///< the bucket drains this many times slower than it fills
};

class MotorSafety {
public:
    explicit MotorSafety(const SafetyParams& params = SafetyParams()) : params_(params) { reset(0); }
    /// Power-on / reset: every motor off, buckets empty, no packet yet.
    void reset(uint32_t nowMs);
    /// A valid motor packet arrived at nowMs with these requested levels (values > 15 clamp to 15).
    void onPacket(const uint8_t levels[kMotors], uint32_t nowMs);
    /// The levels to drive now. Call often (every main-loop pass); time only moves forward.
    void output(uint32_t nowMs, uint8_t out[kMotors]);

    /// Status bits for the v2 frame; reading clears the watchdog bit.
    uint8_t takeStatus();
    bool linkAlive(uint32_t nowMs) const;
    bool heatLimited(uint8_t motor) const { return latched_[motor]; }
    uint32_t heatMs(uint8_t motor) const { return heat_[motor] / params_.coolDivisor; }
    const SafetyParams& params() const { return params_; }

private:
    SafetyParams params_;
    uint8_t requested_[kMotors] = {};
    uint8_t last_[kMotors] = {};       ///< what output() returned last time (it was on since then)
    uint32_t heat_[kMotors] = {};      ///< above-rating time in ms × coolDivisor
    bool latched_[kMotors] = {};
    bool havePacket_ = false;
    bool watchdogTripped_ = false;
    uint32_t lastPacketMs_ = 0;
    uint32_t lastOutputMs_ = 0;
};

} // namespace armfw
