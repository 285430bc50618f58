#include "Access/TactilePlayer.h"
#include <algorithm>
#include <cmath>
#include <chrono>
#include <stdexcept>
#include <thread>

namespace armadillo::access {

TactilePlayer::TactilePlayer(const tactile::TactileConfig& config, double packetPeriod) : packetPeriod_(packetPeriod)
{
    engine_.prepare(config);
    for (auto& g : gains_) g.store(1.0f);
}

void TactilePlayer::setMotorGains(const std::array<float, core::kMaxMotors>& gains) noexcept
{
    for (std::size_t m = 0; m < gains_.size(); ++m) gains_[m].store(std::isfinite(gains[m]) && gains[m] >= 0.0f ? gains[m] : 1.0f);
}

int TactilePlayer::play(std::vector<TactileSegment> segments, double after)
{
    double length = 0.0;
    for (const auto& s : segments) length = std::max(length, s.at + s.duration);
    TactileSegment end;
    end.at = length + after;
    end.end = true;
    segments.push_back(end);
    if (segments.size() > active_.size()) throw std::length_error("tactile sequence too long");
    for (const auto& s : segments)
        while (!queue_.push(s)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return queued_.fetch_add(1) + 1;
}

core::MotorLevels TactilePlayer::onPacket(double t, double rollRate) noexcept
{
    if (const ArmGesture g = twist_.update(t, rollRate); g == ArmGesture::Repeat) repeats_.fetch_add(1, std::memory_order_relaxed);
    else if (g == ArmGesture::Skip) skips_.fetch_add(1, std::memory_order_relaxed);
    double dt = packetPeriod_;
    if (packetPeriod_ <= 0.0) dt = lastT_ < 0.0 ? 0.0 : std::clamp(t - lastT_, 0.0, 0.1);
    lastT_ = t;
    const double now = clock_.load() + dt;
    clock_.store(now);
    packets_.fetch_add(1);
    // Take what the main thread queued (the next sequence starts when the last one is over).
    TactileSegment s;
    while ((!running_ || endAt_ < 0.0) && activeCount_ < static_cast<int>(active_.size()) && queue_.pop(s)) {
        if (!running_) {
            running_ = true;
            anchor_ = now;
            max_.fill(0);
        }
        if (s.end) endAt_ = anchor_ + s.at;
        else active_[static_cast<std::size_t>(activeCount_++)] = s;
    }
    std::array<float, core::kMaxMotors> level {};
    std::uint16_t soft = 0;
    if (running_)
        for (int i = 0; i < activeCount_; ++i) {
            const TactileSegment& a = active_[static_cast<std::size_t>(i)];
            if (now < anchor_ + a.at || now >= anchor_ + a.at + a.duration) continue;
            for (int m = 0; m < core::kMaxMotors; ++m)
                if ((a.motors >> m) & 1u) {
                    level[static_cast<std::size_t>(m)] = std::max(level[static_cast<std::size_t>(m)], a.level);
                    if (a.soft) soft = static_cast<std::uint16_t>(soft | (1u << m));
                }
        }
    for (int m = 0; m < core::kMaxMotors; ++m) {
        const float l = std::min(level[static_cast<std::size_t>(m)] * gains_[static_cast<std::size_t>(m)].load(std::memory_order_relaxed),
                                 static_cast<float>(core::kMaxLevel));
        if ((soft >> m) & 1u) engine_.setSoftLevel(m, l);
        else engine_.setLevel(m, l);
    }
    const core::MotorLevels out = engine_.tick(dt);
    if (running_) {
        for (int m = 0; m < core::kMaxMotors; ++m) max_[static_cast<std::size_t>(m)] = std::max<int>(max_[static_cast<std::size_t>(m)], out[static_cast<std::size_t>(m)]);
        if (endAt_ >= 0.0 && now >= endAt_) {
            for (int m = 0; m < core::kMaxMotors; ++m) maxSent_[static_cast<std::size_t>(m)].store(max_[static_cast<std::size_t>(m)]);
            running_ = false;
            endAt_ = -1.0;
            activeCount_ = 0;
            completed_.fetch_add(1, std::memory_order_release);
        }
    }
    return out;
}

} // namespace armadillo::access
