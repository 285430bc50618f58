#pragma once
// The OSC dialects of the sensors people own, read from each project's own source or manual
// (docs/SENSORS.md says which document each fact came from): address scheme, type tags, units,
// axes. decodeOscReading turns one message into one SensorReading in SI units in the SENSOR's
// own axes (the mount turns those into the forearm's); the OscSampleMerger (OscInput.h) makes
// IMU samples of them. No allocation, no exceptions: this runs on the receiver thread.
#include "Osc/Osc.h"
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <string_view>

namespace armadillo::osc {

enum class OscFormat : std::uint8_t {
    Auto,         ///< detect from the first recognised message
    Armadillo,    ///< /armadillo/imu (9 or 6 numbers, SI, device frame), /armadillo/orientation (w x y z)
    Sensors2Osc,  ///< Android Sensors2OSC: /accelerometer, /gyroscope, /magneticfield, /rotationvector, …
    ZigSim,       ///< ZIG SIM: /ZIGSIM/<uuid>/accel|gravity|gyro|quaternion|compass (or /<uuid>/…)
    GyrOsc,       ///< GyrOSC (iOS): /gyrosc/rrate, /gyrosc/grav, /gyrosc/comp, …
    TouchOsc,     ///< TouchOSC accelerometer: /accxyz (tilt only)
    Ngimu,        ///< x-io NGIMU: /sensors (10 floats), /quaternion (w x y z: Earth NWU → sensor), /euler, /matrix
};
inline constexpr int kOscFormatCount = 7;

const char* oscFormatName(OscFormat f) noexcept;
/// "auto", "armadillo", "sensors2osc", "zigsim", "gyrosc", "touchosc", "ngimu" (case-insensitive).
bool parseOscFormat(std::string_view name, OscFormat& out) noexcept;
std::string oscFormatNames();

/// What one message carried. Vectors are in the sensor's axes, SI: rad/s, m/s² of SPECIFIC FORCE
/// (+g up at rest, whatever sign the sender uses), magnetometer in the sender's unit.
struct SensorReading {
    enum class Kind : std::uint8_t {
        None,
        Gyro,         ///< gyro
        Accel,        ///< accel: the full accelerometer
        Gravity,      ///< accel: the gravity part only (Android /gravity, Core Motion gravity)
        UserAccel,    ///< accel: the part without gravity (Core Motion userAcceleration)
        Mag,          ///< mag
        Imu,          ///< gyro + accel (+ mag, NaN when absent) in one message
        Orientation,  ///< q: sensor → contract earth frame (X east, Y up, Z south)
        Heading,      ///< headingDeg: compass heading of `headingAxis` (sensor axes), clockwise from magnetic north
    };
    Kind kind = Kind::None;
    Eigen::Vector3d gyro {0, 0, 0}, accel {0, 0, 0}, mag {0, 0, 0};
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    bool qHasHeading = true;           ///< false: the sender's yaw reference is arbitrary (Core Motion default, game rotation vector)
    double headingDeg = 0.0;
    Eigen::Vector3d headingAxis {0, 1, 0};
    /// true: the heading is that of the horizontal direction perpendicular to `headingAxis`
    /// (up × axis): Core Location's portrait heading, perpendicular to the phone's x axis, which is
    /// the top edge's heading lying flat and the back's held upright.
    bool headingNormalToAxis = false;
    std::uint64_t deviceKey = 0;       ///< hash of a device id carried in the address (ZIG SIM uuid); 0 = none
    char device[40] {};                ///< that id, NUL-terminated (truncated)
};

enum class DecodeStatus : std::uint8_t {
    Reading,     ///< `out` holds a sensor reading
    Known,       ///< an address of this dialect that carries nothing we use (battery, touch, …)
    NotMine,     ///< not this dialect's address
    WrongTypes,  ///< this dialect's address with the wrong argument count or types
    NonFinite,   ///< NaN or infinity among the numbers
    Absurd,      ///< magnitudes no arm makes (> 2000 °/s, > 16 g, a rotation vector longer than 1, …)
};
const char* decodeStatusName(DecodeStatus s) noexcept;

/// Decodes `m` as `format` (not Auto). `why` gets a static explanation for the refusals.
DecodeStatus decodeOscReading(OscFormat format, const OscMessage& m, SensorReading& out, const char** why) noexcept;
/// ZIG SIM's JSON mode (ZIGSIMPlus ServiceManager.getJSON, MotionService/LocationService
/// toJSON): {"device":{"uuid":…,…},"timestamp":"yyyy-MM-ddTHH:mm:ss.SSSZ","sensordata":{"accel":
/// {"x","y","z"},"gravity":{…},"gyro":{…},"quaternion":{"x","y","z","w"},"compass":{"compass":deg,
/// "faceup":0|1} (older versions: a bare number)}}, same units and axes as its OSC. Fills up to
/// `capacity` readings (all carrying the uuid as device); `senderSeconds` gets the timestamp as
/// seconds since 1970 (NaN when absent or unreadable). Returns the count, or −1 with `why` for
/// text that is not such an object. Allocates (the JSON reader): receiver thread only.
int decodeZigSimJson(std::string_view text, SensorReading* out, int capacity, double& senderSeconds, const char** why) noexcept;
/// Seconds since 1970 of "YYYY-MM-DDTHH:MM:SS[.fff](Z|±HH:MM|±HHMM)"; NaN when not that form.
double parseIsoTimestamp(std::string_view text) noexcept;

/// The dialect whose address scheme `m` belongs to, or Auto when none claims it.
OscFormat detectOscFormat(const OscMessage& m) noexcept;

} // namespace armadillo::osc
