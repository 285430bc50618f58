// Senders written from each format's own documentation (docs/SENSORS.md) play a known forearm
// trajectory over UDP (loopback) to the real `armadillo play --osc-in PORT --log …`: the format
// must be detected without a flag and the logged orientation must be within 3° of the truth
// (median, after the first 2 s, contract frames); an accelerometer alone: the tilt within 3°.
// Senders use their own rates per sensor, send-time jitter and 5 % loss. The same NGIMU sender
// also drives the plugin's OSC source class (Source/Live/OscLink: plain C++, built here without
// JUCE). Sending is paced in real time (the receiver stamps arrivals); the assertions are on the
// logged results, never on timing.
#include "Common/FreePort.h"
#include "Core/Csv.h"
#include "Core/Pose.h"
#include "Core/Types.h"
#include "Link/Motion.h"
#include "Link/Mount.h"
#include "Osc/Osc.h"
#include "Osc/OscDialects.h"
#include "Live/Sources/OscLink.h"
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <fcntl.h>
#include <functional>
#include <array>
#include <cstring>
#include <memory>
#include <netinet/in.h>
#include <pty.h>
#include <termios.h>
#include <random>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;
using namespace armadillo::osc;
using Clock = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;

namespace {

constexpr double kFieldMicroTesla = 50.0;
constexpr double kDipDeg = 65.0;

class Udp {
public:
    explicit Udp(int port)
    {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        to_.sin_family = AF_INET;
        to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        to_.sin_port = htons(static_cast<std::uint16_t>(port));
    }
    ~Udp() { ::close(fd_); }
    void send(const Bytes& b) { ::sendto(fd_, b.data(), b.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_); }

private:
    int fd_ = -1;
    sockaddr_in to_ {};
};

/// The truth the senders measure: device frame (INTERFACES.md), then the sensor's own axes.
struct Truth {
    WanderingMotion motion {5};
    Mount mount;   // sensor → device, as the sender is strapped
    std::mt19937 rng {17};
    std::normal_distribution<double> n01 {0.0, 1.0};

    std::vector<std::pair<double, Pose>> holds;   // when set: still poses instead of the wandering arm
    double stillUntil = -1.0;                      // > 0: lies perfectly still (the arm's pose at 0) until then, then wanders on
    bool still(double t) const { return t < stillUntil; }
    MotionState at(double t) const
    {
        if (stillUntil > 0.0) {
            if (t >= stillUntil) return motion.at(3.0 + (t - stillUntil));
            MotionState s;
            s.q = motion.at(3.0).q;   // not turning, not accelerating
            return s;
        }
        if (holds.empty()) return motion.at(t + 3.0);   // start mid-movement
        MotionState s;
        for (const auto& [from, pose] : holds)
            if (t >= from) s.q = poseToQuaternion(pose);
        return s;
    }
    Eigen::Vector3d noise(double rms) { return rms * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)); }
    Eigen::Vector3d toSensor(const Eigen::Vector3d& vDevice) const { return mount.rotation.conjugate() * vDevice; }
    Eigen::Vector3d gyro(double t) { return toSensor(at(t).omega) + noise(0.003); }                       // rad/s
    Eigen::Vector3d specificForce(double t)                                                                // m/s²
    {
        const MotionState s = at(t);
        return toSensor(s.q.conjugate() * Eigen::Vector3d(0, kStandardGravity, 0) + s.linearAccel) + noise(0.03);
    }
    Eigen::Vector3d gravityOnly(double t) const { return toSensor(at(t).q.conjugate() * Eigen::Vector3d(0, kStandardGravity, 0)); }
    Eigen::Vector3d field(double t)   // µT
    {
        const double dip = degToRad(kDipDeg);
        const Eigen::Vector3d earth(0.0, -std::sin(dip) * kFieldMicroTesla, -std::cos(dip) * kFieldMicroTesla);
        return toSensor(at(t).q.conjugate() * earth) + noise(0.2);
    }
    /// q sensor → contract earth.
    Eigen::Quaterniond sensorQ(double t) const { return (at(t).q * mount.rotation).normalized(); }
    /// Compass heading of the horizontal direction perpendicular to a sensor axis (up × axis).
    double headingNormalTo(double t, const Eigen::Vector3d& axisSensor) const
    {
        const Eigen::Vector3d e = Eigen::Vector3d::UnitY().cross(sensorQ(t) * axisSensor);
        return wrapDeg360(radToDeg(std::atan2(e.x(), -e.z())));
    }
    /// Compass heading (deg, clockwise from north) of a sensor axis.
    double headingOf(double t, const Eigen::Vector3d& axisSensor) const
    {
        const Eigen::Vector3d e = sensorQ(t) * axisSensor;
        return wrapDeg360(radToDeg(std::atan2(e.x(), -e.z())));
    }
};

const Eigen::Quaterniond& enuFromContract()   // contract earth → East-North-Up
{
    static const Eigen::Quaterniond q(Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitX()));
    return q;
}
const Eigen::Quaterniond& nwuFromContract()   // contract earth → North-West-Up
{
    static const Eigen::Quaterniond q = [] {
        Eigen::Matrix3d m;   // rows: N, W, U in contract coordinates (X east, Y up, Z south)
        m << 0, 0, -1, -1, 0, 0, 0, 1, 0;
        return Eigen::Quaterniond(m).normalized();
    }();
    return q;
}

std::vector<OscArg> fl(const Eigen::Vector3d& v, double scale = 1.0)
{
    return {OscArg::float32(float(v.x() * scale)), OscArg::float32(float(v.y() * scale)), OscArg::float32(float(v.z() * scale))};
}

/// One sensor stream of a sender: its period and what it sends at sample time t.
struct Stream {
    double period;
    std::function<Bytes(Truth&, double)> make;
};

struct Scenario {
    std::string name;
    std::string expectFormat;
    std::string mountPreset;      ///< how the test sender is strapped (the format's default)
    std::vector<Stream> streams;
    double loss = 0.0;            ///< fraction of datagrams dropped
    double jitter = 0.0;          ///< s, uniform send delay (sample times unchanged)
    bool tiltOnly = false;
    double gapFrom = -1.0, gapTo = -1.0;   ///< s: nothing is sent in [gapFrom, gapTo) (a Wi-Fi dropout)
    std::string extraArgs;                 ///< more `play` options (one word)
    std::string extraValue;
    std::vector<std::pair<double, Pose>> holds;   ///< when set: the arm holds these poses (from each time on), still
    Eigen::Quaterniond strap = Eigen::Quaterniond::Identity();   ///< with holds: the sensor's rotation on the arm
    enum class Wire { Udp, Tcp, SlipPty } wire = Wire::Udp;      ///< how the bytes travel (SlipPty: `--port PTY --format ngimu-slip`)
    double stillUntil = -1.0;                                     ///< > 0: the sensor lies perfectly still until then
    bool checkStillPhase = false;                                 ///< also: the orientation from 1 s to stillUntil within 3°
    std::string expectWarning;                                    ///< not empty: a rate warning with this text is expected (no accuracy check)
};

Scenario make(std::string name, std::string format, std::string mount, std::vector<Stream> streams, double loss, double jitter,
              bool tiltOnly = false)
{
    Scenario s;
    s.name = std::move(name);
    s.expectFormat = std::move(format);
    s.mountPreset = std::move(mount);
    s.streams = std::move(streams);
    s.loss = loss;
    s.jitter = jitter;
    s.tiltOnly = tiltOnly;
    return s;
}

std::uint64_t ntp(double t) { return (std::uint64_t(3'900'000'000u) << 32) + static_cast<std::uint64_t>(t * 4294967296.0); }

std::vector<Scenario> scenarios()
{
    std::vector<Scenario> s;
    // ARMadillo's own address (INTERFACES.md): /armadillo/imu 9 floats SI, device frame.
    s.push_back(make("armadillo", "armadillo", "identity",
                 {{0.01, [](Truth& w, double t) {
                       std::vector<OscArg> a = fl(w.gyro(t));
                       for (auto& x : fl(w.specificForce(t))) a.push_back(x);
                       for (auto& x : fl(w.field(t))) a.push_back(x);
                       return encodeOscMessage("/armadillo/imu", a);
                   }}},
                 0.0, 0.0));
    // Sensors2OSC: one message per Android sensor event, SensorEvent.values as floats.
    s.push_back(make("sensors2osc", "sensors2osc", "phone-screen-up",
                 {{0.01, [](Truth& w, double t) { return encodeOscMessage("/gyroscope", fl(w.gyro(t))); }},
                  {0.02, [](Truth& w, double t) { return encodeOscMessage("/accelerometer", fl(w.specificForce(t))); }},
                  {0.04, [](Truth& w, double t) { return encodeOscMessage("/magneticfield", fl(w.field(t))); }}},
                 0.05, 0.003));
    // Sensors2OSC with the rotation vector only (x, y, z, w, accuracy; East-North-Up), sent as bundles.
    s.push_back(make("sensors2osc-rotationvector", "sensors2osc", "phone-screen-up",
                 {{0.02, [](Truth& w, double t) {
                       const Eigen::Quaterniond q = enuFromContract() * w.sensorQ(t);
                       return encodeOscBundle(1, {encodeOscMessage("/rotationvector", {OscArg::float32(float(q.x())), OscArg::float32(float(q.y())),
                                                                                        OscArg::float32(float(q.z())), OscArg::float32(float(q.w())),
                                                                                        OscArg::float32(0.05f)})});
                   }}},
                 0.05, 0.003));
    // ZIG SIM (ZIGSIMPlus MotionService/LocationService/ServiceManager): one bundle per tick.
    s.push_back(make("zigsim", "zigsim", "phone-screen-up",
                 {{1.0 / 60.0, [](Truth& w, double t) {
                       const std::string p = "/ZIGSIM/f00dbabe1234/";
                       const Eigen::Vector3d grav = -w.gravityOnly(t) / kStandardGravity;                  // G, Core Motion sign
                       const Eigen::Vector3d user = -(w.specificForce(t) - w.gravityOnly(t)) / kStandardGravity;
                       const Eigen::Quaterniond q = enuFromContract() * w.sensorQ(t);                     // reference frame (yaw arbitrary)
                       return encodeOscBundle(1, {encodeOscMessage("/f00dbabe1234/deviceinfo", {OscArg::string("iPhone"), OscArg::string("f00dbabe1234"),
                                                                                               OscArg::string("ios"), OscArg::string("17"),
                                                                                               OscArg::int32(390), OscArg::int32(844)}),
                                                  encodeOscMessage(p + "accel", fl(user)), encodeOscMessage(p + "gravity", fl(grav)),
                                                  encodeOscMessage(p + "gyro", fl(w.gyro(t))),
                                                  encodeOscMessage(p + "quaternion", {OscArg::float32(float(q.x())), OscArg::float32(float(q.y())),
                                                                                      OscArg::float32(float(q.z())), OscArg::float32(float(q.w()))}),
                                                  // Core Location's portrait heading (face up is ignored): perpendicular to the phone's x.
                                                  encodeOscMessage(p + "compass", {OscArg::float32(float(w.headingNormalTo(t, Eigen::Vector3d::UnitX()))),
                                                                                   OscArg::int32(1)})});
                   }}},
                 0.05, 0.003));
    // GyrOSC: rotation rate, gravity and compass as separate messages at their own rates.
    s.push_back(make("gyrosc", "gyrosc", "phone-screen-up",
                 {{0.01, [](Truth& w, double t) { return encodeOscMessage("/gyrosc/rrate", fl(w.gyro(t))); }},
                  {0.02, [](Truth& w, double t) { return encodeOscMessage("/gyrosc/grav", fl(-w.gravityOnly(t) / kStandardGravity)); }},
                  {0.1, [](Truth& w, double t) {
                       return encodeOscMessage("/gyrosc/comp", {OscArg::float32(float(w.headingOf(t, Eigen::Vector3d::UnitY())))});
                   }}},
                 0.05, 0.003));
    // TouchOSC accelerometer: /accxyz in G, iOS sign: tilt only.
    s.push_back(make("touchosc", "touchosc", "phone-screen-up",
                 {{0.02, [](Truth& w, double t) { return encodeOscMessage("/accxyz", fl(-w.specificForce(t) / kStandardGravity)); }}},
                 0.05, 0.003, true));
    // NGIMU: /sensors (deg/s, g, uT, hPa) and /quaternion (NWU) in time-tagged bundles.
    s.push_back(make("ngimu", "ngimu", "ngimu",
                 {{0.01, [](Truth& w, double t) {
                       std::vector<OscArg> a = fl(w.gyro(t), radToDeg(1.0));
                       for (auto& x : fl(w.specificForce(t), 1.0 / kStandardGravity)) a.push_back(x);
                       for (auto& x : fl(w.field(t))) a.push_back(x);
                       a.push_back(OscArg::float32(1013.25f));
                       return encodeOscBundle(ntp(t), {encodeOscMessage("/sensors", a)});
                   }},
                  {0.02, [](Truth& w, double t) {
                       // x-io's direction: the conjugate of sensor → NWU (docs/SENSORS.md).
                       const Eigen::Quaterniond q = (nwuFromContract() * w.sensorQ(t)).conjugate();
                       return encodeOscBundle(ntp(t), {encodeOscMessage("/quaternion", {OscArg::float32(float(q.w())), OscArg::float32(float(q.x())),
                                                                                        OscArg::float32(float(q.y())), OscArg::float32(float(q.z()))})});
                   }}},
                 0.05, 0.008));
    s.push_back(make("ngimu-quaternion", "ngimu", "ngimu",
                 {{0.02, [](Truth& w, double t) {
                       // x-io's direction: the conjugate of sensor → NWU (docs/SENSORS.md).
                       const Eigen::Quaterniond q = (nwuFromContract() * w.sensorQ(t)).conjugate();
                       return encodeOscBundle(ntp(t), {encodeOscMessage("/quaternion", {OscArg::float32(float(q.w())), OscArg::float32(float(q.x())),
                                                                                        OscArg::float32(float(q.y())), OscArg::float32(float(q.z()))})});
                   }}},
                 0.05, 0.008));
    return s;
}

/// Plays a scenario for `seconds` of real time: sample times on a fixed grid per stream, each
/// datagram sent at its sample time plus a random delay, some dropped.
// --- Held-out senders: written only from each vendor's own definitions ------------------------------
// Everything below encodes the truth the way the vendor's app does, from the vendor's documents
// and sources (docs/SENSORS.md cites them), with its own frame arithmetic: nothing of the
// project's conversion code (OscDialects, Mount, the merger) is called. The sensor is strapped
// with its axes on the forearm's (played with `--mount identity`), so sensor = device frame.
// Contract earth (INTERFACES.md): X east, Y up, Z south.

/// A rotation from the coordinates of the frame whose axes, written in contract coordinates,
/// are the ROWS of m (e.g. rows North, West, Up) — i.e. contract → that frame.
Eigen::Quaterniond frameFromContract(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
    Eigen::Matrix3d m;
    m.row(0) = a.transpose();
    m.row(1) = b.transpose();
    m.row(2) = c.transpose();
    return Eigen::Quaterniond(m).normalized();
}
const Eigen::Vector3d kEast(1, 0, 0), kUp(0, 1, 0), kNorth(0, 0, -1), kWest(-1, 0, 0);

std::vector<OscArg> f32(const Eigen::Vector3d& v) { return {OscArg::float32(float(v.x())), OscArg::float32(float(v.y())), OscArg::float32(float(v.z()))}; }

/// x-io NGIMU /quaternion (NgimuApi QuaternionData.cs, Quaternion.cs; NgimuGui Form3DView.cs):
/// w x y z = the CONJUGATE of the rotation taking sensor vectors into North-West-Up.
Bytes ngimuQuaternion(Truth& w, double t)
{
    const Eigen::Quaterniond sensorToNwu = frameFromContract(kNorth, kWest, kUp) * w.sensorQ(t);
    const Eigen::Quaterniond sent = sensorToNwu.conjugate();
    return encodeOscBundle(ntp(t), {encodeOscMessage("/quaternion", {OscArg::float32(float(sent.w())), OscArg::float32(float(sent.x())),
                                                                      OscArg::float32(float(sent.y())), OscArg::float32(float(sent.z()))})});
}

/// NGIMU /sensors (SensorsData.cs): gyroscope deg/s, accelerometer g (+1 on z lying flat),
/// magnetometer µT, barometer hPa; time-tagged bundles.
Bytes ngimuSensors(Truth& w, double t)
{
    std::vector<OscArg> a = f32(w.gyro(t) * (180.0 / kPi));
    for (auto& x : f32(w.specificForce(t) / kStandardGravity)) a.push_back(x);
    for (auto& x : f32(w.field(t))) a.push_back(x);
    a.push_back(OscArg::float32(1013.25f));
    return encodeOscBundle(ntp(t), {encodeOscMessage("/sensors", a)});
}

/// What ZIG SIM reads from Core Motion and Core Location at time t (MotionService.swift,
/// LocationService.swift): accelerations in G with Apple's sign (at rest the accelerometer reads
/// −1 G along up: gravity points down), rotation rate rad/s, attitude quaternion in the
/// xArbitraryZVertical reference (Z up, X a fixed but arbitrary horizontal direction), heading
/// in degrees clockwise from magnetic north of Core Location's portrait orientation: the
/// horizontal direction perpendicular to the phone's x axis (up × x: the top edge's lying flat,
/// the back's held upright). Magnetic north is true north in this world.
struct ZigTick {
    Eigen::Vector3d user, gravity, gyro;
    Eigen::Quaterniond attitude;
    double heading;
};
ZigTick zigTick(Truth& w, double t)
{
    ZigTick z;
    const Eigen::Quaterniond q = w.sensorQ(t);                               // sensor → contract
    const Eigen::Vector3d upInSensor = q.conjugate() * kUp;
    z.gravity = -upInSensor;                                                   // G: the direction gravity pulls
    z.user = -(w.specificForce(t) / kStandardGravity - upInSensor);            // G: Apple's sign, gravity removed
    z.gyro = w.gyro(t);
    const double arbitraryYaw = 1.234;                                         // Core Motion's reference: any fixed yaw
    const Eigen::Quaterniond refFromEnu(Eigen::AngleAxisd(arbitraryYaw, Eigen::Vector3d::UnitZ()));
    z.attitude = (refFromEnu * frameFromContract(kEast, kNorth, kUp) * q).normalized();
    const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();                    // the phone's x axis, contract coordinates
    const Eigen::Vector3d h = kUp.cross(x);                                    // horizontal, perpendicular to x
    z.heading = std::fmod(radToDeg(std::atan2(h.dot(kEast), h.dot(kNorth))) + 360.0, 360.0);
    return z;
}

/// ZIG SIM OSC (ServiceManager.getOSC, Service.osc): one bundle per tick, time tag "immediately".
Bytes zigOsc(Truth& w, double t, int compassSetting)
{
    const ZigTick z = zigTick(w, t);
    const std::string p = "/ZIGSIM/5EED0001/";
    return encodeOscBundle(1, {encodeOscMessage("/5EED0001/deviceinfo", {OscArg::string("iPhone14,2"), OscArg::string("5EED0001"), OscArg::string("ios"),
                                                                           OscArg::string("17.4"), OscArg::int32(390), OscArg::int32(844)}),
                               encodeOscMessage(p + "accel", f32(z.user)), encodeOscMessage(p + "gravity", f32(z.gravity)),
                               encodeOscMessage(p + "gyro", f32(z.gyro)),
                               encodeOscMessage(p + "quaternion", {OscArg::float32(float(z.attitude.x())), OscArg::float32(float(z.attitude.y())),
                                                                   OscArg::float32(float(z.attitude.z())), OscArg::float32(float(z.attitude.w()))}),
                               // Core Location ignores a face-up headingOrientation: the same value either way.
                               encodeOscMessage(p + "compass", {OscArg::float32(float(z.heading)), OscArg::int32(compassSetting)})});
}

/// ZIG SIM JSON (ServiceManager.getJSON; MotionService/LocationService toJSON): one object per tick.
Bytes zigJson(Truth& w, double t)
{
    const ZigTick z = zigTick(w, t);
    // Utils.getTimestamp: "yyyy-MM-dd'T'HH:mm:ss.SSSZZZZZ" in UTC; this sender's clock starts at 2024-03-01T10:00:00Z.
    const double ms = std::floor(t * 1000.0);
    const int sec = static_cast<int>(ms / 1000.0), milli = static_cast<int>(ms - 1000.0 * sec);
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "{\"device\":{\"name\":\"iPhone14,2\",\"uuid\":\"5EED0002\",\"os\":\"ios\",\"osversion\":\"17.4\",\"displaywidth\":390,"
                  "\"displayheight\":844},\"timestamp\":\"2024-03-01T10:%02d:%02d.%03dZ\",\"sensordata\":{"
                  "\"accel\":{\"x\":%.9g,\"y\":%.9g,\"z\":%.9g},\"gravity\":{\"x\":%.9g,\"y\":%.9g,\"z\":%.9g},"
                  "\"gyro\":{\"x\":%.9g,\"y\":%.9g,\"z\":%.9g},\"quaternion\":{\"x\":%.9g,\"y\":%.9g,\"z\":%.9g,\"w\":%.9g},"
                  "\"compass\":{\"compass\":%.9g,\"faceup\":0}}}",
                  sec / 60, sec % 60, milli, z.user.x(), z.user.y(), z.user.z(), z.gravity.x(), z.gravity.y(), z.gravity.z(), z.gyro.x(),
                  z.gyro.y(), z.gyro.z(), z.attitude.x(), z.attitude.y(), z.attitude.z(), z.attitude.w(), z.heading);
    return Bytes(buf, buf + std::strlen(buf));
}

/// Sensors2OSC (dispatch/SensorConfiguration.java sendingNotNeeded): a sensor's values are sent
/// only when one differs from the last values of that sensor, which start as zeros; Android
/// units (m/s² specific force, rad/s, µT), one message per sensor event. A phone lying perfectly
/// still reads the same floats every time (no noise while still).
struct Sensors2OscPhone {
    std::array<float, 3> last[3] {};   // gyroscope, accelerometer, magnetic field
    Bytes event(int sensor, const char* address, const Eigen::Vector3d& v)
    {
        const std::array<float, 3> now {float(v.x()), float(v.y()), float(v.z())};
        const bool changed = now != last[sensor];
        last[sensor] = now;
        if (!changed) return {};
        return encodeOscMessage(address, {OscArg::float32(now[0]), OscArg::float32(now[1]), OscArg::float32(now[2])});
    }
};
Eigen::Vector3d quiet(Truth& w, double t, const Eigen::Vector3d& noisy, const Eigen::Vector3d& exact) { return w.still(t) ? exact : noisy; }

std::vector<Scenario> vendorScenarios()
{
    std::vector<Scenario> out;
    auto add = [&](std::string name, std::string format, std::vector<Stream> streams, double loss, double jitter) {
        Scenario s = make(std::move(name), std::move(format), "", std::move(streams), loss, jitter);
        s.extraArgs = "--mount";
        s.extraValue = "identity";
        out.push_back(std::move(s));
        return &out.back();
    };
    for (const double loss : {0.0, 0.05}) {
        const std::string tag = loss > 0.0 ? "-loss5" : "-clean";
        add("vendor-ngimu-quaternion" + tag, "ngimu", {{0.02, ngimuQuaternion}}, loss, 0.008);
        add("vendor-zigsim-portrait" + tag, "zigsim", {{1.0 / 60.0, [](Truth& w, double t) { return zigOsc(w, t, 0); }}}, loss, 0.003);
        add("vendor-zigsim-faceup" + tag, "zigsim", {{1.0 / 60.0, [](Truth& w, double t) { return zigOsc(w, t, 1); }}}, loss, 0.003);
        add("vendor-zigsim-json" + tag, "zigsim", {{1.0 / 60.0, zigJson}}, loss, 0.003);
        auto phone = std::make_shared<Sensors2OscPhone>();
        Scenario* still = add("vendor-sensors2osc-still" + tag, "sensors2osc",
                              {{0.01, [phone](Truth& w, double t) {
                                    return phone->event(0, "/gyroscope", quiet(w, t, w.gyro(t), Eigen::Vector3d::Zero()));
                                }},
                               {0.02, [phone](Truth& w, double t) {
                                    return phone->event(1, "/accelerometer",
                                                        quiet(w, t, w.specificForce(t), w.at(t).q.conjugate() * Eigen::Vector3d(0, kStandardGravity, 0)));
                                }},
                               {0.04, [phone](Truth& w, double t) {
                                    const double dip = degToRad(kDipDeg);
                                    const Eigen::Vector3d earth(0.0, -std::sin(dip) * kFieldMicroTesla, -std::cos(dip) * kFieldMicroTesla);
                                    return phone->event(2, "/magneticfield", quiet(w, t, w.field(t), w.at(t).q.conjugate() * earth));
                                }}},
                              loss, 0.003);
        still->stillUntil = 4.0;
        still->checkStillPhase = true;
    }
    // The other wires: NGIMU over USB (SLIP on a pty) and ZIG SIM's TCP option, with loss as on Wi-Fi.
    Scenario* slip = add("vendor-ngimu-slip-pty", "ngimu", {{0.01, ngimuSensors}, {0.02, ngimuQuaternion}}, 0.05, 0.002);
    slip->wire = Scenario::Wire::SlipPty;
    Scenario* tcpJson = add("vendor-zigsim-tcp-json", "zigsim", {{1.0 / 60.0, zigJson}}, 0.0, 0.003);
    tcpJson->wire = Scenario::Wire::Tcp;
    Scenario* tcpOsc = add("vendor-zigsim-tcp-osc", "zigsim", {{1.0 / 60.0, [](Truth& w, double t) { return zigOsc(w, t, 1); }}}, 0.0, 0.003);
    tcpOsc->wire = Scenario::Wire::Tcp;
    // ZIG SIM's default rate (10 messages/s, AppSettingModel.messageRatePerSecond): too slow to fuse well, and said so.
    Scenario* slow = add("vendor-zigsim-10hz", "zigsim", {{0.1, [](Truth& w, double t) { return zigOsc(w, t, 0); }}}, 0.0, 0.003);
    slow->expectWarning = "MESSAGE RATE (PER SEC) to 60";
    return out;
}

/// The wire a sender writes to: a UDP datagram each, ZIG SIM's TCP connection (connected at the
/// first send, retried while the receiver is still starting), or SLIP frames on a pty's master.
class Wire {
public:
    Wire(Scenario::Wire kind, int port, int ptyMaster) : kind_(kind), udp_(port), port_(port), master_(ptyMaster) {}
    ~Wire()
    {
        if (tcp_ >= 0) ::close(tcp_);
    }
    void send(const Bytes& b)
    {
        if (kind_ == Scenario::Wire::Udp) return udp_.send(b);
        if (kind_ == Scenario::Wire::SlipPty) {   // RFC 1055, as the NGIMU frames OSC on USB
            Bytes f {0xC0};
            for (const std::uint8_t c : b) {
                if (c == 0xC0) f.insert(f.end(), {0xDB, 0xDC});
                else if (c == 0xDB) f.insert(f.end(), {0xDB, 0xDD});
                else f.push_back(c);
            }
            f.push_back(0xC0);
            if (::write(master_, f.data(), f.size()) < 0) return;
            return;
        }
        for (int attempt = 0; tcp_ < 0 && attempt < 200; ++attempt) {
            const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
            sockaddr_in a {};
            a.sin_family = AF_INET;
            a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            a.sin_port = htons(static_cast<std::uint16_t>(port_));
            if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
                tcp_ = fd;
                break;
            }
            ::close(fd);
            std::this_thread::sleep_for(std::chrono::milliseconds(10));   // the receiver is not listening yet
        }
        if (tcp_ >= 0) (void)::send(tcp_, b.data(), b.size(), MSG_NOSIGNAL);   // the app writes the payload as is, unframed
    }

private:
    Scenario::Wire kind_;
    Udp udp_;
    int port_;
    int master_;
    int tcp_ = -1;
};

void play(const Scenario& sc, int port, double seconds, Clock::time_point start, std::uint32_t seed, int ptyMaster = -1)
{
    Truth w;
    if (!sc.mountPreset.empty()) mountPreset(sc.mountPreset, w.mount);   // known preset names (checked by the scenarios' own test)
    w.stillUntil = sc.stillUntil;
    if (!sc.holds.empty()) {
        w.holds = sc.holds;
        w.mount.rotation = sc.strap;
    }
    w.rng.seed(seed);
    std::mt19937 rng(seed + 1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Wire wire(sc.wire, port, ptyMaster);
    struct Pending {
        double sendAt;
        Bytes bytes;
    };
    std::vector<Pending> queue;
    std::vector<double> next(sc.streams.size(), 0.0);
    for (;;) {
        std::size_t k = 0;
        for (std::size_t i = 1; i < next.size(); ++i)
            if (next[i] < next[k]) k = i;
        const double t = next[k];
        if (t > seconds) break;
        next[k] += sc.streams[k].period;
        Bytes b = sc.streams[k].make(w, t);
        if (b.empty()) continue;   // the app sent nothing (Sensors2OSC: an unchanged reading)
        if (u(rng) < sc.loss || (t >= sc.gapFrom && t < sc.gapTo)) continue;
        queue.push_back({t + sc.jitter * u(rng), std::move(b)});
    }
    std::stable_sort(queue.begin(), queue.end(), [](const Pending& a, const Pending& b) { return a.sendAt < b.sendAt; });
    for (const Pending& p : queue) {
        std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(p.sendAt)));
        wire.send(p.bytes);
    }
}

struct Outcome {
    int exitCode = -1;
    double longestGap = 0.0;   ///< s, between successive logged rows after the first
    double medianDeg = 1e9;
    double tiltDeg = 1e9;   ///< the tilt part alone, at the same clock offset
    double offset = 0.0;
    std::size_t rows = 0;
    double stillMedianDeg = 1e9;   ///< rows from 1 s to the end of a still phase
    std::size_t stillRows = 0;
    double firstRow = 1e9;         ///< s of sender time: the first logged orientation
    std::string err;
    std::string json;
};

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
    return radToDeg(std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
}

/// Median error of the logged orientation against the truth, after the first 2 s of rows. The
/// log's clock starts when the receiver does; the sender's when it started sending: the
/// constant between them is searched within [lo, hi] (the receiver started between the fork and
/// the first logged row), the same for every row.
Outcome evaluate(const std::string& logPath, bool tiltOnly, double lo, double hi, double stillUntil = -1.0)
{
    Outcome o;
    const CsvTable log = CsvTable::read(logPath);
    const int ct = log.requireColumn("t"), cw = log.requireColumn("qw"), cx = log.requireColumn("qx"), cy = log.requireColumn("qy"),
              cz = log.requireColumn("qz");
    std::vector<std::pair<double, Eigen::Quaterniond>> rows;
    for (std::size_t r = 0; r < log.rowCount(); ++r) {
        const double w = log.value(r, cw);
        if (!std::isfinite(w)) continue;
        rows.emplace_back(log.value(r, ct), Eigen::Quaterniond(w, log.value(r, cx), log.value(r, cy), log.value(r, cz)));
    }
    if (rows.empty()) return o;
    for (std::size_t i = 1; i < rows.size(); ++i) o.longestGap = std::max(o.longestGap, rows[i].first - rows[i - 1].first);
    const double t0 = rows.front().first;
    std::vector<std::pair<double, Eigen::Quaterniond>> used;
    for (const auto& r : rows)
        if (r.first - t0 >= 2.0) used.push_back(r);
    o.rows = used.size();
    if (used.empty()) return o;
    Truth w;
    w.stillUntil = stillUntil;
    auto median = [&](double offset, bool tilt = false) {
        std::vector<double> e;
        e.reserve(used.size());
        for (const auto& [t, q] : used) {
            const Eigen::Quaterniond truth = w.at(t - offset).q;
            if (tiltOnly || tilt) e.push_back(angleBetween(q.conjugate() * Eigen::Vector3d::UnitY(), truth.conjugate() * Eigen::Vector3d::UnitY()));
            else e.push_back(radToDeg(2.0 * std::acos(std::min(1.0, std::abs(q.normalized().dot(truth))))));
        }
        std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
        return e[e.size() / 2];
    };
    for (double c = lo; c <= hi; c += 0.01) {
        const double m = median(c);
        if (m < o.medianDeg) {
            o.medianDeg = m;
            o.offset = c;
        }
    }
    const double c0 = o.offset;
    for (double c = c0 - 0.01; c <= c0 + 0.01; c += 0.001) {
        const double m = median(c);
        if (m < o.medianDeg) {
            o.medianDeg = m;
            o.offset = c;
        }
    }
    o.tiltDeg = median(o.offset, true);
    o.firstRow = rows.front().first - o.offset;
    if (stillUntil > 0.0) {   // the still phase on its own, from its first second on
        std::vector<double> e;
        for (const auto& [t, q] : rows) {
            const double ts = t - o.offset;
            if (ts < 1.0 || ts >= stillUntil) continue;
            e.push_back(radToDeg(2.0 * std::acos(std::min(1.0, std::abs(q.normalized().dot(w.at(ts).q))))));
        }
        o.stillRows = e.size();
        if (!e.empty()) {
            std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
            o.stillMedianDeg = e[e.size() / 2];
        }
    }
    return o;
}

std::string slurp(const std::string& path)
{
    std::string s;
    if (FILE* f = std::fopen(path.c_str(), "rb")) {
        char buf[4096];
        std::size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
        std::fclose(f);
    }
    return s;
}

Outcome runScenarioOnce(const Scenario& sc, std::uint32_t seed)
{
    const int port = test::freeUdpPort();
    const std::string base = std::string(ARMADILLO_BINARY_DIR) + "/osc-sender-" + sc.name;
    const std::string log = base + ".csv", errPath = base + ".err", outPath = base + ".out";
    const double seconds = 7.0;
    int master = -1, slave = -1;
    std::string ptyPath;
    if (sc.wire == Scenario::Wire::SlipPty) {   // the NGIMU's USB port, played by a pseudo-terminal
        if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) return Outcome {};
        termios raw {};
        ::tcgetattr(slave, &raw);
        ::cfmakeraw(&raw);
        ::tcsetattr(slave, TCSANOW, &raw);
        ptyPath = ::ttyname(slave);
    }
    // Everything the child needs is built here: the scenarios run four at a time on threads, and
    // a child of a threaded process may only make async-signal-safe calls until it execs (an
    // allocation there can wait forever on a lock another thread held at the fork).
    const std::string bin = std::string(ARMADILLO_BINARY_DIR) + "/bin/armadillo";
    const std::string portText = std::to_string(port), secs = std::to_string(seconds);
    std::vector<const char*> argv {bin.c_str(), "play", "--scene", "monitor", "--seconds", secs.c_str(), "--log", log.c_str(), "--no-audio"};
    if (sc.wire == Scenario::Wire::SlipPty) argv.insert(argv.end(), {"--port", ptyPath.c_str(), "--format", "ngimu-slip"});
    else argv.insert(argv.end(), {"--osc-in", portText.c_str()});
    if (!sc.extraArgs.empty()) {
        argv.push_back(sc.extraArgs.c_str());
        argv.push_back(sc.extraValue.c_str());
    }
    argv.push_back(nullptr);
    const auto forked = Clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) return Outcome {};
    if (pid == 0) {
        const int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(err, 2);
        ::dup2(out, 1);
        ::execv(bin.c_str(), const_cast<char* const*>(argv.data()));
        ::_exit(127);
    }
    if (sc.stillUntil > 0.0) {
        // A phone lying still sends its readings once: a receiver not yet listening would lose
        // them for good (as with a real phone started before ARMadillo: docs/SENSORS.md). Start
        // once the receiver listens (its TCP socket on the same port answers a connect).
        for (int attempt = 0; attempt < 500; ++attempt) {
            const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
            sockaddr_in a {};
            a.sin_family = AF_INET;
            a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            a.sin_port = htons(static_cast<std::uint16_t>(port));
            const bool up = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
            ::close(fd);
            if (up) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    const auto start = Clock::now();
    play(sc, port, seconds + 0.5, start, seed, master);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (master >= 0) {
        ::close(master);
        ::close(slave);
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {   // no REQUIRE here: this runs on a sender thread
        Outcome failed;
        failed.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        failed.err = slurp(errPath);
        failed.json = slurp(outPath);
        return failed;
    }
    // log t = arrival − receiver start; sample time = arrival − start (+ latency): the constant
    // start − receiverStart lies within [start − forked − 1 s, start − forked].
    const double startAfterFork = std::chrono::duration<double>(start - forked).count();
    Outcome o = evaluate(log, sc.tiltOnly, startAfterFork - 1.0, startAfterFork + 0.05, sc.stillUntil);
    o.exitCode = 0;
    o.err = slurp(errPath);
    o.json = slurp(outPath);
    return o;
}

/// The port chosen as free can be taken before the binary binds it (another sender's ephemeral
/// port): that run says so and is repeated on another port.
Outcome runScenario(const Scenario& sc, std::uint32_t seed)
{
    Outcome o;
    for (int attempt = 0; attempt < 3; ++attempt) {
        o = runScenarioOnce(sc, seed);
        if (!(o.exitCode == 4 && o.err.find("cannot listen on UDP port") != std::string::npos)) break;
    }
    return o;
}

/// Runs the scenarios four at a time (each its own port, binary and log); seeds from `seed0`.
std::vector<Outcome> runBatched(const std::vector<Scenario>& all, std::uint32_t seed0)
{
    std::vector<Outcome> results(all.size());
    for (std::size_t batch = 0; batch < all.size(); batch += 4) {
        std::vector<std::thread> threads;
        for (std::size_t i = batch; i < std::min(all.size(), batch + 4); ++i)
            threads.emplace_back([&, i] { results[i] = runScenario(all[i], seed0 + static_cast<std::uint32_t>(i)); });
        for (auto& t : threads) t.join();
    }
    return results;
}

} // namespace

TEST_CASE("osc senders: each format detected without a flag, orientation within 3 degrees through `armadillo play`", "[osc][senders]")
{
    const auto all = scenarios();
    const std::vector<Outcome> results = runBatched(all, 100);
    for (std::size_t i = 0; i < all.size(); ++i) {
        const Scenario& sc = all[i];
        const Outcome& o = results[i];
        INFO(sc.name << ": median " << o.medianDeg << " deg over " << o.rows << " rows (clock offset " << o.offset << " s)\nstderr: " << o.err
                     << "\nstdout: " << o.json);
        std::printf("osc sender %-28s median %s error %.2f deg (tilt %.2f) over %zu rows\n", sc.name.c_str(),
                    sc.tiltOnly ? "tilt" : "orientation", o.medianDeg, o.tiltDeg, o.rows);
        CHECK(o.exitCode == 0);
        CHECK(o.err.find("OSC input: " + sc.expectFormat + " (detected)") != std::string::npos);
        CHECK(o.json.find("\"format\":\"" + sc.expectFormat + "\"") != std::string::npos);
        CHECK(o.rows > 100);
        CHECK(o.medianDeg < 3.0);
    }
}

TEST_CASE("osc senders: held-out senders written from the vendors' definitions give the truth within 3 degrees", "[osc][senders][vendor]")
{
    const auto all = vendorScenarios();
    const std::vector<Outcome> results = runBatched(all, 500);
    for (std::size_t i = 0; i < all.size(); ++i) {
        const Scenario& sc = all[i];
        const Outcome& o = results[i];
        INFO(sc.name << ": median " << o.medianDeg << " deg over " << o.rows << " rows (clock offset " << o.offset << " s)\nstderr: " << o.err
                     << "\nstdout: " << o.json);
        std::printf("vendor sender %-32s median error %.2f deg over %zu rows", sc.name.c_str(), o.medianDeg, o.rows);
        if (sc.checkStillPhase) std::printf("; still phase 1-4 s: %.2f deg over %zu rows, first row at %.2f s", o.stillMedianDeg, o.stillRows, o.firstRow);
        std::printf("\n");
        CHECK(o.exitCode == 0);
        CHECK(o.err.find("OSC input: " + sc.expectFormat + " (detected)") != std::string::npos);
        CHECK(o.err.find("OSC rates: ") != std::string::npos);
        if (!sc.expectWarning.empty()) {
            // The rate is measured from arrival times, so a loaded machine that delivers a backlog in
            // a burst reads a little faster than the sender's 10 Hz: the warning, not the figure, is checked.
            CHECK(o.err.find("warning: the sensor stream arrives at ") != std::string::npos);
            CHECK(o.err.find(sc.expectWarning) != std::string::npos);
            continue;
        }
        CHECK(o.err.find("too slow for good fusion") == std::string::npos);
        CHECK(o.rows > 100);
        CHECK(o.medianDeg < 3.0);
        if (sc.checkStillPhase) {
            CHECK(o.stillRows > 100);   // orientation all through the still phase, not only once it moves
            CHECK(o.stillMedianDeg < 3.0);
            CHECK(o.firstRow < 1.0);
            CHECK(o.json.find("\"unchanged\":0,") == std::string::npos);
        }
        if (sc.wire == Scenario::Wire::Tcp && sc.name.find("json") != std::string::npos) CHECK(o.json.find("\"json\":0,") == std::string::npos);
    }
}

TEST_CASE("osc senders: the plugin's OSC source detects the NGIMU and delivers device-frame samples", "[osc][senders][plugin]")
{
    live::LiveInput live;
    live::ArmSourceSlot slot;   // where an instrument keeps the source
    live::OscInput input(live, slot);
    const int port = test::freeUdpPort();
    std::string why;
    REQUIRE(input.configure(true, port, why));
    Truth w;
    REQUIRE(mountPreset("ngimu", w.mount));
    Udp udp(port);
    std::vector<live::LiveImu> got;
    const auto start = Clock::now();
    for (int k = 0; k < 200 && got.size() < 100; ++k) {
        const double t = 0.01 * k;
        std::vector<OscArg> a = fl(w.gyro(t), radToDeg(1.0));
        for (auto& x : fl(w.specificForce(t), 1.0 / kStandardGravity)) a.push_back(x);
        for (auto& x : fl(w.field(t))) a.push_back(x);
        a.push_back(OscArg::float32(1013.25f));
        std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t)));
        udp.send(encodeOscBundle(ntp(t), {encodeOscMessage("/sensors", a)}));
        live::LiveImu s;
        while (live.popImu(s)) got.push_back(s);
    }
    for (int i = 0; i < 100 && got.size() < 100; ++i) {   // the last datagrams may still be in flight
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        live::LiveImu s;
        while (live.popImu(s)) got.push_back(s);
    }
    REQUIRE(got.size() >= 100);
    CHECK(input.format() == OscFormat::Ngimu);
    // Gravity is in the device frame: |a| ≈ g and, with the NGIMU preset, the accelerometer's
    // own z (lid) reading is the device y.
    for (std::size_t i = 1; i < got.size(); ++i) CHECK(got[i].t - got[i - 1].t == Approx(0.01).margin(1e-4));   // the tags' own intervals
    const double a = std::hypot(got[5].a[0], got[5].a[1], got[5].a[2]);
    CHECK(a == Approx(kStandardGravity).margin(3.0));
    CHECK(input.stats().imu >= 100);
    CHECK(input.stats().bad == 0);
    CHECK(input.statusText().find("ngimu from 127.0.0.1:") != std::string::npos);

    // The plugin's settings: a forced format and a mount by name; bad names are refused with a reason.
    CHECK_FALSE(input.configure(true, port, "phonething", "", why));
    CHECK(why.find("unknown sender format") != std::string::npos);
    CHECK_FALSE(input.configure(true, port, "", "/nonexistent/mount.json", why));
    CHECK(why.find("cannot read mount file '/nonexistent/mount.json'") != std::string::npos);
    CHECK_FALSE(input.configure(true, port, "", "no-such-preset", why));
    CHECK(why.find("neither a mount preset") != std::string::npos);
    REQUIRE(input.configure(true, port, "zigsim", "phone-screen-up", why));
    CHECK(input.format() == OscFormat::ZigSim);
}

TEST_CASE("osc senders: a dropout stays a gap in the log; the mount calibration finds an arbitrary strap", "[osc][senders][mount]")
{
    const auto all = scenarios();
    Scenario dropout = all[1];   // Sensors2OSC, three rates, jitter, loss
    dropout.name = "sensors2osc-dropout";
    dropout.gapFrom = 3.0;
    dropout.gapTo = 4.0;

    // An NGIMU strapped on at an arbitrary rotation; the arm holds the three calibration poses.
    Scenario mount = all[6];
    mount.name = "ngimu-mount";
    mount.streams.resize(1);   // /sensors only
    mount.loss = 0.05;
    mount.strap = Eigen::Quaterniond(0.3, -0.5, 0.7, 0.2).normalized();
    mount.holds = {{0.0, Pose {2.0, 40.0, -1.0}}, {2.2, Pose {-89.0, 0.0, 0.0}}, {4.4, Pose {1.0, 40.0, 91.0}}};
    const std::string mountFile = std::string(ARMADILLO_BINARY_DIR) + "/osc-sender-mount.json";
    std::remove(mountFile.c_str());
    mount.extraArgs = "--calibrate-mount";
    mount.extraValue = mountFile;

    Outcome gap, cal;
    std::thread a([&] { gap = runScenario(dropout, 31); });
    std::thread b([&] { cal = runScenario(mount, 32); });
    a.join();
    b.join();

    INFO("dropout: stderr " << gap.err << " stdout " << gap.json);
    CHECK(gap.exitCode == 0);
    std::printf("osc sender dropout: longest gap between logged rows %.3f s (1 s cut); median error %.2f deg\n", gap.longestGap,
                gap.medianDeg);
    CHECK(gap.longestGap > 0.9);    // the filter sees the second without data as one
    CHECK(gap.longestGap < 1.2);

    INFO("mount calibration: stderr " << cal.err);
    REQUIRE(cal.exitCode == 0);
    CHECK(cal.err.find("mount calibration complete") != std::string::npos);
    const Mount solved = loadMount(mountFile);
    const double err = radToDeg(2.0 * std::acos(std::min(1.0, std::abs(solved.rotation.dot(mount.strap)))));
    std::printf("osc sender mount calibration: strap recovered within %.2f deg\n", err);
    CHECK(err < 3.0);
    CHECK(solved.device.find("127.0.0.1:") == 0);
}

TEST_CASE("osc senders: play refuses a bad --osc-format, --mount or --calibrate-mount with a clear exit code", "[osc][senders][cli]")
{
    const std::string port = std::to_string(test::freeUdpPort());
    auto run = [](const std::string& args) {
        const std::string cmd = std::string("'") + ARMADILLO_BINARY_DIR + "/bin/armadillo' play --scene monitor --no-audio --seconds 0.2 " + args +
                                " >/dev/null 2>&1";
        const int status = std::system(cmd.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    CHECK(run("--osc-in " + port + " --osc-format phonething") == 2);   // a valid port: only the format is wrong
    CHECK(run("--simulate --osc-format ngimu") == 2);
    CHECK(run("--simulate --mount ngimu") == 2);
    CHECK(run("--osc-in " + port + " --mount /nonexistent/mount.json") == 4);   // a missing file: I/O, as for every input (issue 24)
    CHECK(run("--osc-in " + port + " --mount no-such-preset") == 3);             // not a path, not a preset: bad input
    CHECK(run("--osc-in " + port + " --mount ngimu --calibrate-mount x.json") == 2);
    const std::string bad = std::string(ARMADILLO_BINARY_DIR) + "/osc-sender-badmount.json";
    if (FILE* f = std::fopen(bad.c_str(), "w")) {
        std::fputs("{\"mount\": {\"quaternion\": [1, 2, 3]}}", f);
        std::fclose(f);
    }
    CHECK(run("--osc-in " + port + " --mount '" + bad + "'") == 3);
    // Accepted: with no sender the session then ends by saying so (exit 4), unless told to wait.
    CHECK(run("--osc-in " + port + " --osc-format NGIMU --mount phone-screen-up --data-timeout 0") == 0);
    CHECK(run("--osc-in " + port + " --osc-format NGIMU --mount phone-screen-up") == 4);
    // The serial OSC format and the wait for a sender.
    CHECK(run("--simulate --format ngimu-slip") == 2);
    CHECK(run("--port /dev/null --format morse") == 2);
    CHECK(run("--port /dev/armadillo-no-such-port --format ngimu-slip --v2") == 2);
    CHECK(run("--port /dev/armadillo-no-such-port --format ngimu-slip") == 4);
    CHECK(run("--osc-in " + port + " --data-timeout -1") == 2);
    CHECK(run("--simulate --data-timeout 3") == 2);
}

TEST_CASE("osc senders: nothing usable within --data-timeout ends play with exit 4, naming what was heard", "[osc][senders][cli]")
{
    const int port = test::freeUdpPort();
    const std::string err = std::string(ARMADILLO_BINARY_DIR) + "/osc-sender-nothing.err";
    std::thread junk([port] {
        Udp udp(port);
        for (int k = 0; k < 40; ++k) {   // a text datagram and an address no sender app uses
            std::this_thread::sleep_for(std::chrono::milliseconds(25));
            udp.send(Bytes {'p', 'i', 'n', 'g'});
            udp.send(encodeOscMessage("/mixer/fader1", {OscArg::float32(0.5f)}));
        }
    });
    const std::string cmd = std::string("'") + ARMADILLO_BINARY_DIR + "/bin/armadillo' play --scene monitor --no-audio --seconds 20 --data-timeout 1.5 --osc-in " +
                            std::to_string(port) + " >/dev/null 2>'" + err + "'";
    const int status = std::system(cmd.c_str());
    junk.join();
    CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 4);
    const std::string text = slurp(err);
    INFO(text);
    CHECK(text.find("no usable sensor data on UDP/TCP port " + std::to_string(port) + " within 1.5 s") != std::string::npos);
    CHECK(text.find("/mixer/fader1") != std::string::npos);
    CHECK(text.find("70 69 6e 67") != std::string::npos);   // "ping"
    CHECK(text.find("127.0.0.1:") != std::string::npos);
}
