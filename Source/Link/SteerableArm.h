#pragma once
// The simulated arm a user can take (the plugin's "simulator" source): it wanders along the
// device simulator's path (WanderingMotion, the same motion the simulated forearm's sensors
// measure) with a quick roll flick every few seconds so gesture scenes have something to react
// to; when steered (mouse/keyboard in the arm view) it eases to the requested pose (80 ms time
// constant) and stays there until wandering is switched back on.
//
// Not thread-safe: one owner advances it (the plugin's control clock, under its own lock).
#include "Core/Pose.h"
#include "Link/Motion.h"
#include <Eigen/Geometry>
#include <memory>

namespace armadillo::link {

class SteerableArm {
public:
    explicit SteerableArm(std::uint64_t seed = 1) : path_(seed) {}

    /// Advances the arm by dt s (clamped to 0..0.1) and returns its orientation (device → earth).
    Eigen::Quaterniond advance(double dt);
    /// The user steers: ease toward this pose and stop wandering.
    void steerTo(const core::Pose& target) noexcept;
    void setWandering(bool on) noexcept
    {
        motion_.reset();
        wandering_ = on;
    }
    /// The arm follows `motion` (a pose or quaternion file, FileMotion: `simulate FILE` of Pure
    /// Data's [armadillo~]) from its start, at the pace advance() is called with; null: it
    /// wanders again (issue 46). Steering takes it off the motion as it takes it off the path.
    void follow(std::shared_ptr<const MotionSource> motion) noexcept;
    bool following() const noexcept { return motion_ != nullptr; }
    bool wandering() const noexcept { return wandering_; }
    core::Pose pose() const noexcept { return current_; }
    double time() const noexcept { return t_; }

    static constexpr double kFlickEvery = 7.0;    ///< s between roll flicks while wandering
    static constexpr double kFlickLength = 0.4;   ///< s; ±45° (thesis §3.4: select by a quick roll)

private:
    WanderingMotion path_;
    std::shared_ptr<const MotionSource> motion_;
    double motionStart_ = 0.0;   ///< t_ when the motion began (its time 0; t_ itself never goes back)
    double t_ = 0.0;
    bool wandering_ = true;
    core::Pose target_ {};
    core::Pose current_ {20.0, 0.0, 0.0};
};

} // namespace armadillo::link
