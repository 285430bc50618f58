#pragma once
// Mounting: the rotation from a sensor's own axes to the forearm's device frame (INTERFACES.md:
// x along the forearm toward the hand, y out of the back of the forearm, z = x × y), so any IMU
// strapped on any way becomes the forearm. Presets for the usual straps, a file format, and the
// guided two- or three-pose calibration that finds the rotation from the accelerometer alone.
// Plain C++ and Eigen; the solver allocates nothing after construction.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::link {

/// v_device = rotation · v_sensor. Orientations: q_device→earth = q_sensor→earth · rotation⁻¹.
struct Mount {
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();   ///< sensor → device frame
    std::string name = "identity";                                   ///< preset name or "file"/"calibrated"
    std::string device;                                              ///< the device it was calibrated for ("" = any)

    Eigen::Vector3d toDevice(const Eigen::Vector3d& v) const { return rotation * v; }
    /// q maps sensor-frame vectors into the earth frame; the result maps device-frame vectors.
    Eigen::Quaterniond orientation(const Eigen::Quaterniond& qSensorToEarth) const
    {
        return (qSensorToEarth * rotation.conjugate()).normalized();
    }
};

/// The presets by name: "identity" (also "thesis": the thesis board as designed, and
/// "armadillo"), "phone-screen-up" (a phone strapped screen up along the forearm, top toward
/// the hand), "phone-screen-up-top-to-elbow", "ngimu" (the NGIMU strapped with its x axis toward the hand and the
/// lid (z) out of the back of the forearm). False for an unknown name.
bool mountPreset(std::string_view name, Mount& out);
/// "identity, thesis, phone-screen-up, …" for messages.
std::string mountPresetNames();
/// The preset a format's sensor is usually strapped with (phones: phone-screen-up).
const char* defaultMountPresetForFormat(std::string_view formatName);

/// Mount JSON: {"mount":{"quaternion":[w,x,y,z],"name":"…","device":"…"}} (extra keys ignored).
/// loadMount throws InputError (file, message) for a bad file; saveMount writes atomically.
Mount loadMount(const std::string& path);
/// The same from the file's text (`source` names it in errors).
Mount parseMount(std::string_view json, const std::string& source);
void saveMount(const std::string& path, const Mount& mount);
/// A preset name or a file path (anything that is not a preset name).
Mount mountFromArgument(const std::string& presetOrPath);

/// The guided mount calibration: hold each pose still until it has enough data. Poses:
///  1. LevelForward: arm level pointing forward, palm down (the back of the forearm up) → gravity
///     (specific force, pointing up) along +y of the device frame.
///  2. HangingDown: arm hanging straight down, relaxed → up is −x (the hand points down).
///  3. RolledRight (optional): arm level forward, turned 90° clockwise seen from the elbow
///     (the back of the forearm faces right) → up is −z.
/// Feed sensor-frame accelerometer (and gyroscope, for the stillness test) samples; finishStep()
/// takes the mean of the still samples; solve() is Wahba's problem (SVD) over the poses.
class MountCalibration {
public:
    enum class Pose { LevelForward = 0, HangingDown = 1, RolledRight = 2, Done = 3 };
    struct Params {
        double stillGyro = 0.15;        ///< rad/s: faster than this is moving (sample skipped)
        double stillAccelDev = 0.6;     ///< m/s²: |a| further than this from g is moving
        int samplesNeeded = 60;         ///< still samples per pose
        double minSeparationDeg = 45.0; ///< two pose directions closer than this cannot fix a rotation (and a
                                        ///< sample this close to a finished pose is not the next pose yet)
    };
    MountCalibration();
    explicit MountCalibration(const Params& p);

    Pose pose() const noexcept { return pose_; }
    static const char* poseName(Pose p);
    static const char* instruction(Pose p);
    /// One sample in the sensor frame (accel m/s² specific force; gyro rad/s, NaN when absent).
    void feed(const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro);
    /// Enough still samples for the current pose.
    bool ready() const noexcept { return count_ >= params_.samplesNeeded; }
    /// How far the current pose is toward ready(), 0..1 (for a progress bar).
    double progress() const noexcept
    {
        return params_.samplesNeeded <= 0 ? 1.0 : std::min(1.0, static_cast<double>(count_) / params_.samplesNeeded);
    }
    /// Keeps the current pose's mean and moves to the next pose (RolledRight → Done).
    void finishStep();
    /// Skips the optional third pose.
    void skipRoll();
    /// The mount from the finished poses (at least the first two). False with a reason when the
    /// poses do not determine a rotation (too few, or two poses pointing the same way).
    bool solve(Mount& out, std::string& why) const;
    /// Wahba's problem: the rotation R minimising Σ w‖R·a_i − b_i‖² (unit vectors), by SVD with
    /// the determinant fixed to +1. Exposed for tests.
    static Eigen::Quaterniond wahba(const Eigen::Vector3d* sensor, const Eigen::Vector3d* device, const double* weights, int n);

private:
    Params params_;
    Pose pose_ = Pose::LevelForward;
    Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
    int count_ = 0;
    std::array<Eigen::Vector3d, 3> means_ {};
    std::array<bool, 3> have_ {};
};

} // namespace armadillo::link
