#pragma once
// Active reading by rolling the forearm (thesis §4.3): turns absolute orientation into "advance
// one step" events. Roll is measured from the orientation itself, never from integrated gyro
// (the thesis: drift would advance text with no input, which startles and breaks concentration).
//
//  - Forearm within 30° of vertical (hanging, as the thesis's reader stands): reading forward;
//    the roll angle is the heading of the board's normal vector in the horizontal plane.
//  - Forearm within 30° of horizontal: reading backward; the roll angle is the normal's rotation
//    about the forearm axis, measured from "up".
//  - Anywhere else (or no valid orientation): nothing advances.
//  - A turn of `stepDeg` either way from the anchor advances one step and re-arms the two
//    thresholds ±stepDeg around the angle at that moment. After an advance nothing advances for
//    `deadTime` (vibration transients must not read as movement).
#include "Core/ArmState.h"
#include <Eigen/Core>
#include <cstdint>

namespace armadillo::braille {

enum class ReadingPosture : std::uint8_t { Invalid, Forward, Backward };
const char* postureName(ReadingPosture p) noexcept;   ///< "invalid", "forward", "backward"

struct RollReaderParams {
    double stepDeg = 15.0;             ///< deg of roll per advance (thesis §4.3.1)
    double verticalZoneDeg = 30.0;     ///< forearm axis within this of vertical ⇒ forward
    double horizontalZoneDeg = 30.0;   ///< forearm axis within this of horizontal ⇒ backward
    double zoneHysteresisDeg = 3.0;    ///< a zone is entered this far inside its limit and left this far outside
    double deadTime = 0.12;            ///< s after an advance during which nothing advances
};

struct RollUpdate {
    ReadingPosture posture = ReadingPosture::Invalid;
    bool advanced = false;             ///< one step in the posture's direction
    bool directionChanged = false;     ///< entered the other reading posture than the last valid one
    double rollDeg = 0.0;              ///< the posture's roll angle (deg); 0 when invalid
    double turnDeg = 0.0;              ///< signed roll from the anchor (deg) before this update's decision
};

class RollReader {
public:
    explicit RollReader(const RollReaderParams& params = {}) : params_(params) {}
    void setParams(const RollReaderParams& params) noexcept { params_ = params; }
    const RollReaderParams& params() const noexcept { return params_; }
    /// Forget the anchor, the posture and the dead time.
    void reset() noexcept;

    /// One control update at time t (s). `axis` and `normal` are the forearm axis (device x) and
    /// board normal (device y) in the earth frame (Y up); `valid` false ⇒ nothing advances.
    RollUpdate update(double t, const Eigen::Vector3d& axis, const Eigen::Vector3d& normal, bool valid) noexcept;
    /// Same, from an ArmState's orientation quaternion.
    RollUpdate update(const core::ArmState& arm) noexcept;

    ReadingPosture posture() const noexcept { return posture_; }
    ReadingPosture lastValidPosture() const noexcept { return lastValid_; }

    /// Posture of an axis with no history (no hysteresis): for tests and the training log.
    static ReadingPosture classify(const Eigen::Vector3d& axis, const RollReaderParams& params) noexcept;
    /// The roll angle (deg, −180..180) a posture measures; NaN when it is undefined.
    static double rollAngle(ReadingPosture posture, const Eigen::Vector3d& axis, const Eigen::Vector3d& normal) noexcept;

private:
    ReadingPosture nextPosture(const Eigen::Vector3d& axis) const noexcept;

    RollReaderParams params_;
    ReadingPosture posture_ = ReadingPosture::Invalid;
    ReadingPosture lastValid_ = ReadingPosture::Invalid;
    double anchorDeg_ = 0.0;
    double quietUntil_ = -1e300;
};

} // namespace armadillo::braille
