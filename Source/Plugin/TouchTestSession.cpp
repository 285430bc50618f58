#include "Plugin/TouchTestSession.h"
#include <algorithm>

namespace armadillo::plugin {

// Right-arm layout: index i = motor m(i+1), as the CLI's touch-profile (the profile's order).
TouchTestSession::TouchTestSession() : player_(TactileConfig {}, 0.0) {}

void TouchTestSession::begin(std::uint64_t seed, bool comfort)
{
    askComfort_ = comfort;
    comfortStep_ = false;
    comfort_ = 0;
    stairs_ = {};
    lastStart_.fill(-1e9);
    order_.clear();
    rng_.seed(seed);
    previous_ = -1;
    stimuli_ = 0;
    state_ = State::Presenting;
    next();
}

void TouchTestSession::next()
{
    if (order_.empty()) {
        for (int m = 0; m < device::kProfileMotors; ++m)
            if (! stairs_[static_cast<std::size_t>(m)].done()) order_.push_back(m);
        if (order_.empty()) {
            if (! askComfort_ || comfortStep_) {
                state_ = State::Done;
                return;
            }
            // The comfortable level (CmdTouchProfile.cpp): from the comfort motor's threshold + 1
            // upwards; at the top level it is taken without asking.
            comfortStep_ = true;
            motor_ = device::TouchProfile {}.comfortMotor - 1;
            level_ = std::min(kMaxLevel, stairs_[static_cast<std::size_t>(motor_)].threshold() + 1);
            if (level_ >= kMaxLevel) {
                comfort_ = kMaxLevel;
                state_ = State::Done;
                return;
            }
            present();
            return;
        }
        // Fisher-Yates with `%` as the CLI does: a seed gives the same order everywhere.
        for (std::size_t i = order_.size(); i > 1; --i) std::swap(order_[i - 1], order_[static_cast<std::size_t>(rng_() % i)]);
        if (order_.size() > 1 && order_.front() == previous_) std::swap(order_.front(), order_.back());
    }
    motor_ = order_.front();
    order_.erase(order_.begin());
    level_ = stairs_[static_cast<std::size_t>(motor_)].level();
    present();
}

void TouchTestSession::present()
{
    const auto m = static_cast<std::size_t>(motor_);
    access::TactileSegment s;
    s.at = std::max(0.0, lastStart_[m] + kRestSeconds - player_.clock());
    s.duration = kOnSeconds;
    s.motors = static_cast<std::uint16_t>(1u << motor_);
    s.level = static_cast<float>(level_);
    s.soft = true;   // no jump-start spike: the level asked is the level felt
    lastStart_[m] = player_.clock() + s.at;
    waitingFor_ = player_.play({s}, kGapSeconds);
    ++stimuli_;
    state_ = State::Presenting;
}

bool TouchTestSession::poll()
{
    if (state_ != State::Presenting || player_.completed() < waitingFor_) return false;
    state_ = State::Asking;
    return true;
}

void TouchTestSession::answer(bool felt)
{
    if (state_ != State::Asking) return;
    if (comfortStep_) {   // felt = "comfortable"
        if (felt || level_ + 1 >= kMaxLevel) {
            comfort_ = felt ? level_ : kMaxLevel;
            state_ = State::Done;
            return;
        }
        ++level_;
        present();
        return;
    }
    stairs_[static_cast<std::size_t>(motor_)].answer(felt);
    previous_ = motor_;
    next();
}

void TouchTestSession::again()
{
    if (state_ == State::Asking) present();
}

std::string TouchTestSession::question() const
{
    if (state_ != State::Asking) return {};
    return "motor m" + std::to_string(motor_ + 1) + ", level " + std::to_string(level_) + (comfortStep_ ? ": comfortable?" : ": felt it?");
}

device::TouchProfile TouchTestSession::profile() const
{
    device::TouchProfile p;
    for (std::size_t m = 0; m < device::kProfileMotors; ++m) {
        p.threshold[m] = stairs_[m].threshold();
        p.felt[m] = stairs_[m].felt();
    }
    p.comfort = comfort_;
    p.stimuli = stimuli_;
    p.stimulusSeconds = stimuli_ * (kOnSeconds + kGapSeconds);
    return p;
}

} // namespace armadillo::plugin
