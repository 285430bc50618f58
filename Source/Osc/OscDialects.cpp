#include "Osc/OscDialects.h"
#include "Core/Types.h"
#include "Core/Json.h"
#include <cctype>
#include <cmath>
#include <cstring>

namespace armadillo::osc {

namespace {

constexpr const char* kNames[kOscFormatCount] = {"auto", "armadillo", "sensors2osc", "zigsim", "gyrosc", "touchosc", "ngimu"};

// Magnitudes no forearm produces; beyond them a message is refused as absurd (not clipped).
constexpr double kMaxGyro = 35.0;                      // rad/s (≈ 2000 °/s, the usual MEMS full scale)
constexpr double kMaxAccel = 16.0 * core::kStandardGravity; // m/s²
constexpr double kMaxFieldMicroTesla = 5000.0;         // µT (Earth: 25–65 µT; a fridge magnet up close ≈ 5000)
constexpr double kMaxFieldAnyUnit = 1e6;               // /armadillo/imu: "any consistent unit"

DecodeStatus fail(const char** why, DecodeStatus s, const char* text) noexcept
{
    if (why) *why = text;
    return s;
}

/// n numbers from argument `first` on; the message must have exactly `total` arguments (or at
/// least `total` when `atLeast`).
DecodeStatus numbers(const OscMessage& m, int total, bool atLeast, int n, double* v, const char** why, const char* wrongText) noexcept
{
    if (atLeast ? m.count < total : m.count != total) return fail(why, DecodeStatus::WrongTypes, wrongText);
    for (int i = 0; i < n; ++i) {
        const char t = m.args[i].type;
        if (t != 'f' && t != 'd' && t != 'i') return fail(why, DecodeStatus::WrongTypes, wrongText);
        m.args[i].asNumber(v[i]);
        if (!std::isfinite(v[i])) return fail(why, DecodeStatus::NonFinite, "NaN or infinity among the numbers");
    }
    return DecodeStatus::Reading;
}

Eigen::Vector3d vec(const double* v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

/// East-North-Up (Android's world frame; Core Motion's Z-vertical frames) → contract earth
/// (X east, Y up, Z south): X = E, Y = U, Z = −N, a −90° turn about X.
const Eigen::Quaterniond& enuToContract()
{
    static const Eigen::Quaterniond q(Eigen::AngleAxisd(-core::kPi / 2.0, Eigen::Vector3d::UnitX()));
    return q;
}

/// North-West-Up (the NGIMU's Earth frame) → contract earth: X = −W, Y = U, Z = −N.
const Eigen::Quaterniond& nwuToContract()
{
    static const Eigen::Quaterniond q = [] {
        Eigen::Matrix3d m;
        m << 0, -1, 0, 0, 0, 1, -1, 0, 0;
        return Eigen::Quaterniond(m).normalized();
    }();
    return q;
}

DecodeStatus gyroReading(const double* v, SensorReading& out, const char** why) noexcept
{
    out.kind = SensorReading::Kind::Gyro;
    out.gyro = vec(v);
    if (out.gyro.norm() > kMaxGyro) return fail(why, DecodeStatus::Absurd, "angular rate above 2000 deg/s");
    return DecodeStatus::Reading;
}

DecodeStatus accelReading(SensorReading::Kind kind, const Eigen::Vector3d& specificForce, SensorReading& out, const char** why) noexcept
{
    out.kind = kind;
    out.accel = specificForce;
    if (specificForce.norm() > kMaxAccel) return fail(why, DecodeStatus::Absurd, "acceleration above 16 g");
    return DecodeStatus::Reading;
}

DecodeStatus orientationReading(const Eigen::Quaterniond& frame, Eigen::Quaterniond q, bool hasHeading, SensorReading& out,
                                const char** why) noexcept
{
    const double n = q.norm();
    if (!(std::abs(n - 1.0) < 0.1)) return fail(why, DecodeStatus::Absurd, "orientation quaternion is far from unit length");
    out.kind = SensorReading::Kind::Orientation;
    out.q = (frame * q.normalized()).normalized();
    out.qHasHeading = hasHeading;
    return DecodeStatus::Reading;
}

bool equalsAny(std::string_view s, std::initializer_list<std::string_view> list) noexcept
{
    for (std::string_view x : list)
        if (s == x) return true;
    return false;
}

// --- ARMadillo's own ------------------------------------------------------------------------------

DecodeStatus decodeArmadillo(const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    double v[9];
    if (m.address == "/armadillo/imu") {
        const char* wrong = "/armadillo/imu needs 9 numbers (gx gy gz ax ay az mx my mz) or 6 without the magnetometer";
        if (m.count != 9 && m.count != 6) return fail(why, DecodeStatus::WrongTypes, wrong);
        const DecodeStatus s = numbers(m, m.count, false, m.count, v, why, wrong);
        if (s != DecodeStatus::Reading) return s;
        out.kind = SensorReading::Kind::Imu;
        out.gyro = vec(v);
        out.accel = vec(v + 3);
        out.mag = m.count == 9 ? vec(v + 6) : Eigen::Vector3d(core::kNaN, core::kNaN, core::kNaN);
        if (out.gyro.norm() > kMaxGyro) return fail(why, DecodeStatus::Absurd, "angular rate above 2000 deg/s");
        if (out.accel.norm() > kMaxAccel) return fail(why, DecodeStatus::Absurd, "acceleration above 16 g");
        if (m.count == 9 && out.mag.norm() > kMaxFieldAnyUnit) return fail(why, DecodeStatus::Absurd, "magnetic field absurdly large");
        return DecodeStatus::Reading;
    }
    if (m.address == "/armadillo/orientation") {
        const char* wrong = "/armadillo/orientation needs 4 finite numbers w x y z";
        const DecodeStatus s = numbers(m, 4, false, 4, v, why, wrong);
        if (s != DecodeStatus::Reading) return s;
        // A rotation: length 1 within 10 % (Core/Pose.h), as every dialect here and a motion file.
        return orientationReading(Eigen::Quaterniond::Identity(), Eigen::Quaterniond(v[0], v[1], v[2], v[3]), true, out, why);
    }
    if (m.address.substr(0, 11) == "/armadillo/") return DecodeStatus::Known;   // our own outputs looped back
    return DecodeStatus::NotMine;
}

// --- Sensors2OSC (Android) --------------------------------------------------------------------------
// One message per Android sensor event: "/" + the sensor's prefix, the SensorEvent.values as
// floats (Sensors2OSC Parameters.java, OscHandler.java). Android units: m/s², rad/s, µT; the
// accelerometer and gravity sensor give specific force (+9.81 on z lying screen up).

DecodeStatus decodeSensors2Osc(const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    double v[5];
    const std::string_view a = m.address;
    if (equalsAny(a, {"/accelerometer", "/gyroscope", "/magneticfield", "/gravity"})) {
        const DecodeStatus s = numbers(m, 3, true, 3, v, why, "Sensors2OSC sensor messages carry 3 floats");
        if (s != DecodeStatus::Reading) return s;
        if (a == "/gyroscope") return gyroReading(v, out, why);
        if (a == "/magneticfield") {
            out.kind = SensorReading::Kind::Mag;
            out.mag = vec(v);
            if (out.mag.norm() > kMaxFieldMicroTesla) return fail(why, DecodeStatus::Absurd, "magnetic field above 5000 uT");
            return DecodeStatus::Reading;
        }
        return accelReading(a == "/gravity" ? SensorReading::Kind::Gravity : SensorReading::Kind::Accel, vec(v), out, why);
    }
    if (equalsAny(a, {"/rotationvector", "/gamerotationvector", "/georotationvector"})) {
        // values: x·sin(θ/2), y·sin(θ/2), z·sin(θ/2), [cos(θ/2)], [heading accuracy] (Android
        // SensorEvent docs); world frame East-North-Up; maps device vectors into the world.
        const DecodeStatus s = numbers(m, 3, true, m.count >= 4 ? 4 : 3, v, why, "a rotation vector carries 3 to 5 floats");
        if (s != DecodeStatus::Reading) return s;
        const double xyz = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (xyz > 1.01) return fail(why, DecodeStatus::Absurd, "rotation vector longer than 1");
        const double w = m.count >= 4 ? v[3] : std::sqrt(std::max(0.0, 1.0 - xyz));
        return orientationReading(enuToContract(), Eigen::Quaterniond(w, v[0], v[1], v[2]), a != "/gamerotationvector", out, why);
    }
    if (equalsAny(a, {"/linearacceleration", "/orientation", "/inclination", "/light", "/pressure", "/proximity", "/temperature",
                      "/ambienttemperature", "/relativehumidity", "/magneticfielduncalibrated", "/gyroscopeuncalibrated",
                      "/accelerometeruncalibrated", "/stepcounter", "/stepdetector", "/significantmotion", "/heartrate",
                      "/deviceorientation", "/touch", "/nfc", "/location"}))
        return DecodeStatus::Known;
    return DecodeStatus::NotMine;
}

// --- ZIG SIM ----------------------------------------------------------------------------------------
// ZIGSIMPlus (iOS, 1-10/ZIGSIMPlus_iOS_Public): one bundle per tick (1–60 Hz, time tag not set),
// "/ZIGSIM/<uuid>/<name>" (older docs: "/<uuid>/<name>"), from Core Motion's device motion:
// accel = userAcceleration (G, gravity removed), gravity (G), gyro = rotationRate (rad/s),
// quaternion x y z w (attitude, reference frame: Core Motion's default, yaw arbitrary);
// compass = CLHeading.magneticHeading (deg) and 0 (portrait) / 1 (face up). Core Motion's
// accelerations are accelerations, not specific force: lying screen up gravity = (0, 0, −1).

constexpr std::string_view kZigMotion[] = {"accel", "gravity", "gyro", "quaternion", "compass", "deviceinfo"};

bool splitZig(std::string_view a, std::string_view& uuid, std::string_view& name, bool& prefixed) noexcept
{
    prefixed = a.substr(0, 8) == "/ZIGSIM/";
    std::string_view rest = prefixed ? a.substr(8) : a.substr(1);
    const auto slash = rest.find('/');
    if (slash == std::string_view::npos || slash == 0) return false;
    uuid = rest.substr(0, slash);
    name = rest.substr(slash + 1);
    if (name.empty() || name.find('/') != std::string_view::npos) return false;
    if (!prefixed) {
        bool known = false;
        for (auto k : kZigMotion) known = known || name == k;
        if (!known) return false;
    }
    return true;
}

/// Core Location's portrait heading: the compass direction perpendicular to the phone's x axis.
DecodeStatus zigHeading(double deg, SensorReading& out, const char** why) noexcept
{
    if (deg < -360.0 || deg > 720.0) return fail(why, DecodeStatus::Absurd, "compass heading outside 0..360 degrees");
    out.kind = SensorReading::Kind::Heading;
    out.headingDeg = deg;
    out.headingAxis = Eigen::Vector3d(1, 0, 0);
    out.headingNormalToAxis = true;
    return DecodeStatus::Reading;
}

std::uint64_t fnv1a(std::string_view s) noexcept
{
    std::uint64_t h = 1469598103934665603ull;
    for (const char c : s) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    return h == 0 ? 1 : h;
}

DecodeStatus decodeZigSim(const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    std::string_view uuid, name;
    bool prefixed = false;
    if (!splitZig(m.address, uuid, name, prefixed)) return DecodeStatus::NotMine;
    out.deviceKey = fnv1a(uuid);
    const std::size_t n = std::min(uuid.size(), sizeof out.device - 1);
    std::memcpy(out.device, uuid.data(), n);
    out.device[n] = 0;
    double v[4];
    const char* wrong3 = "ZIG SIM motion messages carry 3 floats x y z";
    if (name == "accel" || name == "gravity") {
        const DecodeStatus s = numbers(m, 3, false, 3, v, why, wrong3);
        if (s != DecodeStatus::Reading) return s;
        return accelReading(name == "accel" ? SensorReading::Kind::UserAccel : SensorReading::Kind::Gravity, -core::kStandardGravity * vec(v), out,
                            why);
    }
    if (name == "gyro") {
        const DecodeStatus s = numbers(m, 3, false, 3, v, why, wrong3);
        return s != DecodeStatus::Reading ? s : gyroReading(v, out, why);
    }
    if (name == "quaternion") {
        const DecodeStatus s = numbers(m, 4, false, 4, v, why, "ZIG SIM quaternion carries 4 floats x y z w");
        if (s != DecodeStatus::Reading) return s;
        return orientationReading(enuToContract(), Eigen::Quaterniond(v[3], v[0], v[1], v[2]), false, out, why);
    }
    if (name == "compass") {
        // heading (deg), then (newer versions) the app's heading-orientation setting: 0 portrait,
        // 1 face up (LocationService.swift: CLLocationManager.headingOrientation). Core Location
        // ignores the face-up, face-down and unknown orientations for headingOrientation
        // (Apple's CLLocationManager.h), so the value is the portrait heading either way: the
        // flag is read and not used.
        if (m.count != 1 && m.count != 2) return fail(why, DecodeStatus::WrongTypes, "ZIG SIM compass carries a heading (and an orientation flag)");
        double flag = 0.0;
        if (!m.args[0].asNumber(v[0]) || (m.count == 2 && !m.args[1].asNumber(flag)))
            return fail(why, DecodeStatus::WrongTypes, "ZIG SIM compass carries a heading (and an orientation flag)");
        if (!std::isfinite(v[0]) || !std::isfinite(flag)) return fail(why, DecodeStatus::NonFinite, "NaN or infinity among the numbers");
        return zigHeading(v[0], out, why);
    }
    return DecodeStatus::Known;   // deviceinfo, touch, battery, gps, …
}

// --- GyrOSC (iOS) -------------------------------------------------------------------------------------
// No vendor document was found; the addresses and units below are those its users' receivers
// rely on (see docs/SENSORS.md): /gyrosc/rrate = Core Motion rotationRate (rad/s),
// /gyrosc/grav = Core Motion gravity (G, pointing down), /gyrosc/comp = heading (deg).

DecodeStatus decodeGyrOsc(const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    if (m.address.substr(0, 8) != "/gyrosc/") return DecodeStatus::NotMine;
    const std::string_view name = m.address.substr(8);
    double v[3];
    if (name == "rrate") {
        const DecodeStatus s = numbers(m, 3, false, 3, v, why, "/gyrosc/rrate carries 3 floats (rad/s)");
        return s != DecodeStatus::Reading ? s : gyroReading(v, out, why);
    }
    if (name == "grav") {
        const DecodeStatus s = numbers(m, 3, false, 3, v, why, "/gyrosc/grav carries 3 floats (G)");
        return s != DecodeStatus::Reading ? s : accelReading(SensorReading::Kind::Gravity, -core::kStandardGravity * vec(v), out, why);
    }
    if (name == "comp") {
        const DecodeStatus s = numbers(m, 1, true, 1, v, why, "/gyrosc/comp carries a heading in degrees");
        if (s != DecodeStatus::Reading) return s;
        if (v[0] < -360.0 || v[0] > 720.0) return fail(why, DecodeStatus::Absurd, "compass heading outside 0..360 degrees");
        out.kind = SensorReading::Kind::Heading;
        out.headingDeg = v[0];
        out.headingAxis = Eigen::Vector3d(0, 1, 0);
        return DecodeStatus::Reading;
    }
    return DecodeStatus::Known;   // gyro (attitude angles), accel, quat (argument order differs between versions), button, …
}

// --- TouchOSC accelerometer ---------------------------------------------------------------------------
// /accxyz x y z in G with the iOS sign (lying screen up z = −1): tilt only, never heading.

DecodeStatus decodeTouchOsc(const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    if (m.address != "/accxyz") return DecodeStatus::NotMine;
    double v[3];
    const DecodeStatus s = numbers(m, 3, false, 3, v, why, "/accxyz carries 3 floats (G)");
    return s != DecodeStatus::Reading ? s : accelReading(SensorReading::Kind::Accel, -core::kStandardGravity * vec(v), out, why);
}

// --- x-io NGIMU ---------------------------------------------------------------------------------------
// NGIMU-Software-Public, NgimuApi/Data/SensorsData.cs: /sensors = 10 floats: gyroscope (deg/s),
// accelerometer (g), magnetometer (µT), barometer (hPa). QuaternionData.cs: /quaternion = w x y z,
// Earth frame North-West-Up (SettingDocumentation.xml). Its DIRECTION is x-io's: the conjugate of
// the rotation that takes sensor vectors into NWU — the GUI draws the board rotated by the
// INVERSE of the received quaternion (NgimuGui/3DView/Form3DView.cs), and Maths/Quaternion.cs
// builds it from Euler angles as Conjugate(textbook ZYX quaternion) and turns it into Euler
// angles and a matrix with the textbook formulas applied to its conjugate. So:
//   /quaternion w x y z  = conj(q sensor→NWU)
//   /euler roll pitch yaw (deg, EulerAnglesData.cs) = the ZYX angles of sensor→NWU: Rz(yaw)·Ry(pitch)·Rx(roll)
//   /matrix XX XY XZ YX … ZZ (RotationMatrixData.cs) = Quaternion.ToRotationMatrix(q) = R(sensor→NWU), row-major
// Sent in time-tagged bundles (the NGIMU's own clock).

DecodeStatus decodeNgimu(const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    double v[10];
    if (m.address == "/sensors") {
        const DecodeStatus s = numbers(m, 10, false, 10, v, why, "NGIMU /sensors carries 10 floats (gyro deg/s, accel g, mag uT, baro hPa)");
        if (s != DecodeStatus::Reading) return s;
        out.kind = SensorReading::Kind::Imu;
        out.gyro = core::degToRad(1.0) * vec(v);
        out.accel = core::kStandardGravity * vec(v + 3);
        out.mag = vec(v + 6);
        if (out.gyro.norm() > kMaxGyro) return fail(why, DecodeStatus::Absurd, "angular rate above 2000 deg/s");
        if (out.accel.norm() > kMaxAccel) return fail(why, DecodeStatus::Absurd, "acceleration above 16 g");
        if (out.mag.norm() > kMaxFieldMicroTesla) return fail(why, DecodeStatus::Absurd, "magnetic field above 5000 uT");
        return DecodeStatus::Reading;
    }
    if (m.address == "/quaternion") {
        const DecodeStatus s = numbers(m, 4, false, 4, v, why, "NGIMU /quaternion carries 4 floats w x y z");
        if (s != DecodeStatus::Reading) return s;
        return orientationReading(nwuToContract(), Eigen::Quaterniond(v[0], v[1], v[2], v[3]).conjugate(), true, out, why);
    }
    if (m.address == "/euler") {
        const DecodeStatus s = numbers(m, 3, false, 3, v, why, "NGIMU /euler carries 3 floats roll pitch yaw (deg)");
        if (s != DecodeStatus::Reading) return s;
        if (std::abs(v[0]) > 720.0 || std::abs(v[1]) > 720.0 || std::abs(v[2]) > 720.0)
            return fail(why, DecodeStatus::Absurd, "Euler angle beyond 720 degrees");
        const Eigen::Quaterniond q = Eigen::AngleAxisd(core::degToRad(v[2]), Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(core::degToRad(v[1]), Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(core::degToRad(v[0]), Eigen::Vector3d::UnitX());
        return orientationReading(nwuToContract(), q, true, out, why);
    }
    if (m.address == "/matrix") {
        const DecodeStatus s = numbers(m, 9, false, 9, v, why, "NGIMU /matrix carries 9 floats XX XY XZ YX YY YZ ZX ZY ZZ");
        if (s != DecodeStatus::Reading) return s;
        Eigen::Matrix3d r;
        r << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
        // A rotation: orthonormal with determinant +1 (within float rounding).
        if (!((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 0.05) || !(r.determinant() > 0.0))
            return fail(why, DecodeStatus::Absurd, "NGIMU /matrix is not a rotation");
        return orientationReading(nwuToContract(), Eigen::Quaterniond(r), true, out, why);
    }
    if (equalsAny(m.address, {"/earth", "/linear", "/altitude", "/temperature", "/humidity", "/battery", "/analogue", "/rssi", "/button",
                              "/magnitudes", "/ping", "/serial", "/error"}))
        return DecodeStatus::Known;
    return DecodeStatus::NotMine;
}

} // namespace

const char* oscFormatName(OscFormat f) noexcept
{
    const int i = static_cast<int>(f);
    return i >= 0 && i < kOscFormatCount ? kNames[i] : "?";
}

bool parseOscFormat(std::string_view name, OscFormat& out) noexcept
{
    for (int i = 0; i < kOscFormatCount; ++i) {
        const std::string_view n = kNames[i];
        if (n.size() != name.size()) continue;
        bool same = true;
        for (std::size_t k = 0; k < n.size(); ++k) same = same && std::tolower(static_cast<unsigned char>(name[k])) == n[k];
        if (same) {
            out = static_cast<OscFormat>(i);
            return true;
        }
    }
    return false;
}

std::string oscFormatNames()
{
    std::string s;
    for (const char* n : kNames) {
        if (!s.empty()) s += ", ";
        s += n;
    }
    return s;
}

const char* decodeStatusName(DecodeStatus s) noexcept
{
    switch (s) {
    case DecodeStatus::Reading: return "reading";
    case DecodeStatus::Known: return "unused";
    case DecodeStatus::NotMine: return "other address";
    case DecodeStatus::WrongTypes: return "wrong type tags";
    case DecodeStatus::NonFinite: return "NaN or infinity";
    case DecodeStatus::Absurd: return "absurd magnitude";
    }
    return "?";
}

DecodeStatus decodeOscReading(OscFormat format, const OscMessage& m, SensorReading& out, const char** why) noexcept
{
    out = SensorReading {};
    if (why) *why = nullptr;
    switch (format) {
    case OscFormat::Armadillo: return decodeArmadillo(m, out, why);
    case OscFormat::Sensors2Osc: return decodeSensors2Osc(m, out, why);
    case OscFormat::ZigSim: return decodeZigSim(m, out, why);
    case OscFormat::GyrOsc: return decodeGyrOsc(m, out, why);
    case OscFormat::TouchOsc: return decodeTouchOsc(m, out, why);
    case OscFormat::Ngimu: return decodeNgimu(m, out, why);
    case OscFormat::Auto: break;
    }
    return DecodeStatus::NotMine;
}

double parseIsoTimestamp(std::string_view s) noexcept
{
    auto digits = [&](std::size_t at, int n, int& v) {
        if (at + static_cast<std::size_t>(n) > s.size()) return false;
        v = 0;
        for (int i = 0; i < n; ++i) {
            const char c = s[at + static_cast<std::size_t>(i)];
            if (c < '0' || c > '9') return false;
            v = v * 10 + (c - '0');
        }
        return true;
    };
    int Y, Mo, D, h, mi, sec;
    if (!digits(0, 4, Y) || s.size() < 19 || s[4] != '-' || !digits(5, 2, Mo) || s[7] != '-' || !digits(8, 2, D) || (s[10] != 'T' && s[10] != ' ') ||
        !digits(11, 2, h) || s[13] != ':' || !digits(14, 2, mi) || s[16] != ':' || !digits(17, 2, sec))
        return core::kNaN;
    if (Mo < 1 || Mo > 12 || D < 1 || D > 31 || h > 23 || mi > 59 || sec > 60) return core::kNaN;
    std::size_t i = 19;
    double frac = 0.0;
    if (i < s.size() && s[i] == '.') {
        double scale = 0.1;
        for (++i; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i, scale *= 0.1) frac += (s[i] - '0') * scale;
    }
    double zone = 0.0;
    if (i < s.size() && s[i] == 'Z') {
        ++i;
    } else if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
        const double sign = s[i] == '-' ? -1.0 : 1.0;
        int zh = 0, zm = 0;
        if (!digits(i + 1, 2, zh)) return core::kNaN;
        std::size_t j = i + 3;
        if (j < s.size() && s[j] == ':') ++j;
        if (!digits(j, 2, zm)) return core::kNaN;
        zone = sign * (zh * 3600.0 + zm * 60.0);
        i = j + 2;
    } else {
        return core::kNaN;
    }
    if (i != s.size()) return core::kNaN;
    // Days since 1970-01-01 of a proleptic Gregorian date (the civil-from-days inverse).
    const int y = Y - (Mo <= 2 ? 1 : 0);
    const int era = (y >= 0 ? y : y - 399) / 400;
    const int yoe = y - era * 400;
    const int doy = (153 * (Mo + (Mo > 2 ? -3 : 9)) + 2) / 5 + D - 1;
    const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    const double days = static_cast<double>(era) * 146097.0 + doe - 719468.0;
    return days * 86400.0 + h * 3600.0 + mi * 60.0 + sec + frac - zone;
}

int decodeZigSimJson(std::string_view text, SensorReading* out, int capacity, double& senderSeconds, const char** why) noexcept
{
    senderSeconds = core::kNaN;
    try {
        const core::JsonValue root = core::parseJson(text, "ZIG SIM JSON");
        if (root.kind != core::JsonValue::Kind::Object) return fail(why, DecodeStatus::WrongTypes, "JSON that is not an object"), -1;
        const core::JsonValue* data = root.find("sensordata");
        if (!data || data->kind != core::JsonValue::Kind::Object)
            return fail(why, DecodeStatus::WrongTypes, "JSON without ZIG SIM's \"sensordata\" object"), -1;
        std::string_view uuid;
        if (const core::JsonValue* dev = root.find("device"); dev && dev->kind == core::JsonValue::Kind::Object)
            if (const core::JsonValue* u = dev->find("uuid"); u && u->kind == core::JsonValue::Kind::String) uuid = u->string;
        if (const core::JsonValue* ts = root.find("timestamp"); ts && ts->kind == core::JsonValue::Kind::String) senderSeconds = parseIsoTimestamp(ts->string);
        auto num = [](const core::JsonValue* o, const char* key, double& v) {
            const core::JsonValue* x = o ? o->find(key) : nullptr;
            if (!x || x->kind != core::JsonValue::Kind::Number) return false;
            v = x->number;
            return true;
        };
        int n = 0;
        const char* bad = nullptr;
        auto add = [&](SensorReading r) {
            if (n >= capacity) return;
            if (!uuid.empty()) {
                r.deviceKey = fnv1a(uuid);
                const std::size_t k = std::min(uuid.size(), sizeof r.device - 1);
                std::memcpy(r.device, uuid.data(), k);
                r.device[k] = 0;
            }
            out[n++] = r;
        };
        for (const char* name : {"accel", "gravity", "gyro", "quaternion"}) {
            const core::JsonValue* o = data->find(name);
            if (!o) continue;
            double v[4] {};
            const bool quat = std::strcmp(name, "quaternion") == 0;
            if (o->kind != core::JsonValue::Kind::Object || !num(o, "x", v[0]) || !num(o, "y", v[1]) || !num(o, "z", v[2]) || (quat && !num(o, "w", v[3]))) {
                bad = quat ? "ZIG SIM JSON quaternion needs numbers x y z w" : "ZIG SIM JSON motion values need numbers x y z";
                continue;
            }
            SensorReading r;
            DecodeStatus st;
            if (quat) st = orientationReading(enuToContract(), Eigen::Quaterniond(v[3], v[0], v[1], v[2]), false, r, &bad);
            else if (std::strcmp(name, "gyro") == 0) st = gyroReading(v, r, &bad);
            else st = accelReading(std::strcmp(name, "accel") == 0 ? SensorReading::Kind::UserAccel : SensorReading::Kind::Gravity,
                                   -core::kStandardGravity * vec(v), r, &bad);
            if (st == DecodeStatus::Reading) add(r);
        }
        if (const core::JsonValue* c = data->find("compass")) {
            double deg = core::kNaN;
            if (c->kind == core::JsonValue::Kind::Number) deg = c->number;
            else if (c->kind == core::JsonValue::Kind::Object) num(c, "compass", deg);
            SensorReading r;
            if (!std::isfinite(deg)) bad = "ZIG SIM JSON compass needs a heading in degrees";
            else if (zigHeading(deg, r, &bad) == DecodeStatus::Reading) add(r);
        }
        if (n == 0 && bad) return fail(why, DecodeStatus::WrongTypes, bad), -1;
        return n;
    } catch (const std::exception&) {
        if (why) *why = "a datagram starting with '{' that is not valid JSON";
        return -1;
    }
}

OscFormat detectOscFormat(const OscMessage& m) noexcept
{
    const std::string_view a = m.address;
    if (a == "/armadillo/imu" || a == "/armadillo/orientation") return OscFormat::Armadillo;
    if (a == "/gyrosc/rrate" || a == "/gyrosc/grav" || a == "/gyrosc/comp" || a == "/gyrosc/gyro" || a == "/gyrosc/quat") return OscFormat::GyrOsc;
    if (a == "/accxyz") return OscFormat::TouchOsc;
    if ((a == "/sensors" && m.count == 10) || (a == "/quaternion" && m.count == 4) || (a == "/euler" && m.count == 3) ||
        (a == "/matrix" && m.count == 9))
        return OscFormat::Ngimu;
    if (equalsAny(a, {"/accelerometer", "/gyroscope", "/magneticfield", "/rotationvector", "/gamerotationvector", "/georotationvector", "/gravity"}))
        return OscFormat::Sensors2Osc;
    std::string_view uuid, name;
    bool prefixed = false;
    if (splitZig(a, uuid, name, prefixed)) return OscFormat::ZigSim;
    return OscFormat::Auto;
}

} // namespace armadillo::osc
