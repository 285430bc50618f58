#pragma once
// Motions that drive the simulated forearm: the orientation q (device → earth, INTERFACES.md),
// the angular velocity in the device frame and the linear acceleration of the board.
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::link {

struct MotionState {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();   ///< device → earth
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();         ///< rad/s, device frame
    Eigen::Vector3d linearAccel = Eigen::Vector3d::Zero();   ///< m/s², device frame (gravity excluded)
};

class MotionSource {
public:
    virtual ~MotionSource() = default;
    /// The motion at time t (s since the simulator started). Any t ≥ 0; deterministic.
    virtual MotionState at(double t) const = 0;
};

/// Angular velocity (device frame) between two orientations h seconds apart.
Eigen::Vector3d angularVelocity(const Eigen::Quaterniond& q0, const Eigen::Quaterniond& q1, double h);

/// A built-in wandering arm: slow sums of sines on elevation (±60°), azimuth (±70° around north)
/// and roll (±90°), with "punches" (half-sine linear-acceleration transients along the forearm,
/// ~1.5 g for 120 ms, then as sharp a stop that brings the velocity back to zero) every
/// few seconds. Deterministic for a seed.
class WanderingMotion final : public MotionSource {
public:
    explicit WanderingMotion(std::uint64_t seed = 1);
    MotionState at(double t) const override;

private:
    Eigen::Quaterniond orientation(double t) const;
    double phase_[6] {};
    std::vector<double> punchTimes_;   ///< s, one cycle of punches (repeats every kPunchCycle)
};

/// Orientations given as a function of time (tests, scripted calibration moves).
class FunctionMotion final : public MotionSource {
public:
    explicit FunctionMotion(std::function<Eigen::Quaterniond(double)> q,
                            std::function<Eigen::Vector3d(double)> linearAccel = {});
    MotionState at(double t) const override;

private:
    std::function<Eigen::Quaterniond(double)> q_;
    std::function<Eigen::Vector3d(double)> accel_;
};

/// A quaternion or pose file (INTERFACES.md formats), interpolated with slerp and held at its
/// ends; looped when `loop`. Throws InputError for IMU files (they need fusion, not replay) and
/// for files with fewer than one row.
class FileMotion final : public MotionSource {
public:
    explicit FileMotion(const std::string& path, bool loop = true);
    MotionState at(double t) const override;
    double duration() const noexcept { return times_.empty() ? 0.0 : times_.back() - times_.front(); }

private:
    Eigen::Quaterniond orientation(double t) const;
    std::vector<double> times_;
    std::vector<Eigen::Quaterniond> qs_;
    bool loop_;
};

} // namespace armadillo::link
