#include "Procedures/TouchTest.h"
#include <algorithm>
#include <ctime>
#include <sstream>

namespace armadillo::procedures {

// Right-arm layout: index i = motor m(i+1), the profile's order.
TouchTest::TouchTest() : TouchTest(Params {}) {}

TouchTest::TouchTest(const Params& params) : params_(params), player_(tactile::TactileConfig {}, params.packetPeriod) {}

void TouchTest::begin(std::uint64_t seed, bool comfort)
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

void TouchTest::next()
{
    if (order_.empty()) {
        for (int m = 0; m < link::kProfileMotors; ++m)
            if (! stairs_[static_cast<std::size_t>(m)].done()) order_.push_back(m);
        if (order_.empty()) {
            if (! askComfort_ || comfortStep_) {
                state_ = State::Done;
                return;
            }
            // The comfortable level: from the comfort motor's threshold + 1 upwards; at the top
            // level it is taken without asking.
            comfortStep_ = true;
            motor_ = link::TouchProfile {}.comfortMotor - 1;
            level_ = std::min(core::kMaxLevel, stairs_[static_cast<std::size_t>(motor_)].threshold() + 1);
            if (level_ >= core::kMaxLevel) {
                comfort_ = core::kMaxLevel;
                state_ = State::Done;
                return;
            }
            present();
            return;
        }
        // Fisher-Yates with `%` (std::shuffle differs between standard libraries): a seed gives
        // the same order everywhere.
        for (std::size_t i = order_.size(); i > 1; --i) std::swap(order_[i - 1], order_[static_cast<std::size_t>(rng_() % i)]);
        if (order_.size() > 1 && order_.front() == previous_) std::swap(order_.front(), order_.back());
    }
    motor_ = order_.front();
    order_.erase(order_.begin());
    level_ = stairs_[static_cast<std::size_t>(motor_)].level();
    present();
}

void TouchTest::present()
{
    const auto m = static_cast<std::size_t>(motor_);
    access::TactileSegment s;
    s.at = std::max(0.0, lastStart_[m] + params_.restSeconds - player_.clock());
    s.duration = params_.onSeconds;
    s.motors = static_cast<std::uint16_t>(1u << motor_);
    s.level = static_cast<float>(level_);
    s.soft = true;   // no jump-start spike: the level asked is the level felt
    lastStart_[m] = player_.clock() + s.at;
    waitingFor_ = player_.play({s}, params_.gapSeconds);
    ++stimuli_;
    state_ = State::Presenting;
}

bool TouchTest::poll()
{
    if (state_ != State::Presenting || player_.completed() < waitingFor_) return false;
    state_ = State::Asking;
    return true;
}

void TouchTest::answer(bool felt)
{
    if (state_ != State::Asking) return;
    if (comfortStep_) {   // felt = "comfortable"
        if (felt || level_ + 1 >= core::kMaxLevel) {
            comfort_ = felt ? level_ : core::kMaxLevel;
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

void TouchTest::again()
{
    if (state_ == State::Asking) present();
}

std::string TouchTest::question() const
{
    if (state_ != State::Asking) return {};
    return "motor m" + std::to_string(motor_ + 1) + ", level " + std::to_string(level_) + (comfortStep_ ? ": comfortable?" : ": felt it?");
}

int TouchTest::loweredTo() const noexcept
{
    if (state_ != State::Asking || motor_ < 0) return 0;
    const int sent = player_.maxLevel(motor_);
    return sent < level_ ? sent : 0;
}

link::TouchProfile TouchTest::profile() const
{
    link::TouchProfile p;
    for (std::size_t m = 0; m < link::kProfileMotors; ++m) {
        p.threshold[m] = stairs_[m].threshold();
        p.felt[m] = stairs_[m].felt();
    }
    p.comfort = comfort_;
    p.stimuli = stimuli_;
    p.stimulusSeconds = stimuli_ * (params_.onSeconds + params_.gapSeconds);
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    p.date = date;
    return p;
}

void TouchTest::save(const std::string& path) const { link::saveTouchProfile(path, profile()); }

namespace {
std::string thresholdList(const link::TouchProfile& p)
{
    std::string out;
    for (std::size_t m = 0; m < link::kProfileMotors; ++m) out += (m ? "," : "") + std::to_string(p.threshold[m]);
    return out;
}
} // namespace

std::string TouchTest::summary() const
{
    const link::TouchProfile p = profile();
    return "thresholds " + thresholdList(p) + (p.comfort ? ", comfortable level " + std::to_string(p.comfort) : "");
}

std::string TouchTest::summaryJson() const
{
    const link::TouchProfile p = profile();
    std::ostringstream o;
    o << "{\"stimuli\":" << p.stimuli << ",\"stimulus_seconds\":" << p.stimulusSeconds << ",\"threshold\":[" << thresholdList(p)
      << "],\"comfort\":" << p.comfort << "}";
    return o.str();
}

} // namespace armadillo::procedures
