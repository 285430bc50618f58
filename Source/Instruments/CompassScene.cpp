// The wearable compass (thesis §4.1): point the thumb toward a target heading. One motor, on
// the side the arm should turn toward, clicks like a Geiger counter, faster as the thumb nears
// the target; within the tolerance both side motors hold a steady touch.
#include "Core/Pose.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include "Tactile/Hysteresis.h"
#include <cmath>

namespace armadillo::instruments {
namespace {

enum CompassIndex : int { kHeading, kTolerance, kLevel, kMaxRate };

std::vector<core::ParamSpec> compassSpecs()
{
    return {
        {"compass.target", "Target heading", 0.0f, 360.0f, 0.0f, "deg", {}},
        {"compass.tolerance", "On-target tolerance", 1.0f, 30.0f, 5.0f, "deg", {}},
        {"compass.level", "Vibration level", 0.0f, 15.0f, 5.0f, "", {}},
        {"compass.maxRate", "Fastest click rate", 2.0f, 30.0f, 15.0f, "Hz", {}},
    };
}

class CompassScene final : public core::Scene {
public:
    CompassScene() : params_(compassSpecs()) {}
    std::string_view name() const override { return "compass"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    void prepare(const core::SceneConfig& config) override
    {
        side_ = config.side;
        reset();
    }
    void reset() override
    {
        state_ = State::Unknown;
        clickRate_ = 0.0;
        onTarget_.reset(false);
        clearPending_ = true;
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        if (clearPending_) {   // entering the scene: nothing left over from before
            out.motors.clearLevels();
            out.motors.stopVoice(0);
            clearPending_ = false;
        }
        const double tolerance = params_.get(kTolerance);
        onTarget_.setThresholds(tolerance, tolerance + 2.0);   // on below tol, off above tol + 2°
        if (!in.arm.valid) {
            show(State::Unknown, 0.0, out);
            return;
        }
        // The thumb side of the forearm: device −z on the right arm, +z on the left.
        const Eigen::Vector3d thumb = in.arm.q.normalized() * Eigen::Vector3d(0.0, 0.0, side_ == core::ArmSide::Right ? -1.0 : 1.0);
        const double horizontal = std::hypot(thumb.x(), thumb.z());
        if (horizontal < 0.3) {   // thumb pointing up or down: no heading to show
            show(State::Unknown, 0.0, out);
            return;
        }
        const double heading = core::wrapDeg360(core::radToDeg(std::atan2(thumb.x(), -thumb.z())));
        const double error = core::wrapDeg180(params_.get(kHeading) - heading); // + = turn clockwise
        if (onTarget_.update(std::fabs(error))) {
            show(State::OnTarget, 0.0, out);
            return;
        }
        // Geiger counter: 1 Hz when facing away, maxRate at the edge of the tolerance.
        const double closeness = 1.0 - std::clamp((std::fabs(error) - tolerance) / (180.0 - tolerance), 0.0, 1.0);
        const double rate = 1.0 + (params_.get(kMaxRate) - 1.0) * closeness * closeness;
        // Facing straight away both ways are equally short: keep the side already shown within
        // 10° of the far point so the clicks do not jump from arm side to arm side.
        State side = error > 0.0 ? State::TurnRight : State::TurnLeft;
        if ((state_ == State::TurnLeft || state_ == State::TurnRight) && std::fabs(error) > 170.0) side = state_;
        show(side, rate, out);
    }

private:
    enum class State { Unknown, TurnLeft, TurnRight, OnTarget };

    void show(State s, double rate, core::SceneOutput& out)
    {
        const auto level = static_cast<float>(params_.get(kLevel));
        const int left = core::motorIndex(1, 0), right = core::motorIndex(1, 2);
        if (s != state_) {
            out.motors.stopVoice(0);
            out.motors.setLevel(left, s == State::OnTarget ? 0.6f * level : 0.0f);
            out.motors.setLevel(right, s == State::OnTarget ? 0.6f * level : 0.0f);
            if (s == State::OnTarget) out.events.emit("onTarget", 1.0f);
            clickRate_ = 0.0;
        }
        state_ = s;
        if (s != State::TurnLeft && s != State::TurnRight) return;
        // Re-trigger only when the rate moved by 10%: a request restarts the pattern.
        if (clickRate_ > 0.0 && std::fabs(rate - clickRate_) < 0.1 * clickRate_) return;
        // Scenes write the right-arm layout, whose columns are the arm's sides (column 0 = the
        // thumb side); the engine mirrors them for the left arm. The cue belongs on the side of
        // the body the arm should turn toward: with the palm down that is the fifth-finger side
        // (column 2) for a clockwise turn on the right arm, but the thumb side (column 0) on the
        // left arm, whose thumb points to the body's right.
        const bool turnRight = s == State::TurnRight;
        const int motor = (turnRight == (side_ == core::ArmSide::Right)) ? right : left;
        core::PatternRequest geiger;
        geiger.kind = core::PatternKind::Geiger;
        geiger.motors = static_cast<std::uint16_t>(1u << motor);
        geiger.level = level;
        geiger.rate = rate;
        geiger.duration = -1.0;
        geiger.voice = 0;
        out.motors.trigger(geiger);
        clickRate_ = rate;
    }

    ParameterSet params_;
    core::ArmSide side_ = core::ArmSide::Right;
    State state_ = State::Unknown;
    double clickRate_ = 0.0;            ///< Hz of the running Geiger pattern (0 = none)
    bool clearPending_ = true;
    tactile::Hysteresis onTarget_ {5.0, 7.0}; ///< downward boundary on |error|, deg
};

} // namespace

std::unique_ptr<core::Scene> makeCompassScene() { return std::make_unique<CompassScene>(); }

} // namespace armadillo::instruments
