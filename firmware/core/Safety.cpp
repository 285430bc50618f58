#include "Safety.h"

namespace armfw {

void MotorSafety::reset(uint32_t nowMs)
{
    for (uint8_t m = 0; m < kMotors; ++m) {
        requested_[m] = 0;
        last_[m] = 0;
        heat_[m] = 0;
        latched_[m] = false;
    }
    havePacket_ = false;
    watchdogTripped_ = false;
    lastPacketMs_ = nowMs;
    lastOutputMs_ = nowMs;
}

void MotorSafety::onPacket(const uint8_t levels[kMotors], uint32_t nowMs)
{
    for (uint8_t m = 0; m < kMotors; ++m) requested_[m] = levels[m] > 15 ? 15 : levels[m];
    havePacket_ = true;
    lastPacketMs_ = nowMs;
}

bool MotorSafety::linkAlive(uint32_t nowMs) const
{
    // Signed difference: a packet stamped after `nowMs` (it arrived in an interrupt after the caller
    // read its clock) is fresh, not 49 days old. Found by the simavr loop: the unsigned form switched
    // every motor off for one packet whenever a packet landed during the I2C read.
    return havePacket_ && static_cast<int32_t>(nowMs - lastPacketMs_) <= static_cast<int32_t>(params_.linkTimeoutMs);
}

void MotorSafety::output(uint32_t nowMs, uint8_t out[kMotors])
{
    // Account for the time the previous output was on (unsigned difference: wraps safely).
    const uint32_t dt = static_cast<uint32_t>(nowMs - lastOutputMs_);
    lastOutputMs_ = nowMs;
    const uint32_t full = static_cast<uint32_t>(params_.maxAboveMs) * params_.coolDivisor;
    for (uint8_t m = 0; m < kMotors; ++m) {
        if (last_[m] > params_.ratedLevel) {
            const uint32_t add = dt * params_.coolDivisor;
            heat_[m] = (full - heat_[m] < add) ? full : heat_[m] + add;
        } else {
            heat_[m] = heat_[m] > dt ? heat_[m] - dt : 0;
        }
        if (heat_[m] >= full) latched_[m] = true;
        else if (heat_[m] == 0) latched_[m] = false;
    }

    const bool alive = linkAlive(nowMs);
    if (!alive && havePacket_) {
        watchdogTripped_ = true;   // reported once in the next v2 frame
        havePacket_ = false;       // stays off until a new valid packet
    }
    for (uint8_t m = 0; m < kMotors; ++m) {
        uint8_t level = alive ? requested_[m] : 0;
        if (latched_[m] && level > params_.ratedLevel) level = params_.ratedLevel;
        out[m] = level;
        last_[m] = level;
    }
}

uint8_t MotorSafety::takeStatus()
{
    uint8_t s = 0;
    if (watchdogTripped_) s |= kStatusWatchdog;
    for (uint8_t m = 0; m < kMotors; ++m)
        if (latched_[m]) s |= kStatusHeatLimit;
    watchdogTripped_ = false;
    return s;
}

} // namespace armfw
