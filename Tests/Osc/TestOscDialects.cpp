// The sender dialects (OscDialects), the merger (OscInput) and the mount (Mount): messages built
// as each sender's own source or manual says it builds them (docs/SENSORS.md), decoded into SI
// values in the contract frames; honest timing; bad input counted and kept off the orientation.
#include "Core/Pose.h"
#include "Core/Types.h"
#include "Link/Mount.h"
#include "Osc/Osc.h"
#include "Osc/OscDialects.h"
#include "Osc/OscInput.h"
#include <catch2/catch.hpp>
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include <random>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;
using namespace armadillo::osc;

namespace {

std::vector<OscArg> floats(std::initializer_list<double> v)
{
    std::vector<OscArg> out;
    for (double x : v) out.push_back(OscArg::float32(static_cast<float>(x)));
    return out;
}

/// Decodes one encoded message with the dialect.
DecodeStatus decodeAs(OscFormat f, const std::vector<std::uint8_t>& bytes, SensorReading& r, OscFormat* detected = nullptr)
{
    DecodeStatus status = DecodeStatus::NotMine;
    std::function<void(const OscMessage&)> on = [&](const OscMessage& m) {
        if (detected) *detected = detectOscFormat(m);
        status = decodeOscReading(f, m, r, nullptr);
    };
    REQUIRE(decodeOscPacket(bytes.data(), bytes.size(), on));
    return status;
}

double angleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b)
{
    return radToDeg(2.0 * std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))));
}

/// What the merger delivered.
struct Collected {
    std::vector<ImuSample> imu;
    std::vector<std::pair<double, Eigen::Quaterniond>> q;
};

void attach(OscSampleMerger& m, Collected& c)
{
    m.setSinks([](void* x, const ImuSample& s) { static_cast<Collected*>(x)->imu.push_back(s); },
               [](void* x, double t, const Eigen::Quaterniond& q) { static_cast<Collected*>(x)->q.emplace_back(t, q); }, &c);
}

void feed(OscSampleMerger& m, const std::vector<std::uint8_t>& bytes, double t, std::uint64_t sender = 7)
{
    m.handleDatagram(bytes.data(), bytes.size(), t, sender, "10.0.0.7:9000");
}

} // namespace

TEST_CASE("osc dialects: each sender's addresses, units and frames", "[device][osc][dialects]")
{
    SensorReading r;
    OscFormat d = OscFormat::Auto;

    // NGIMU /sensors: gyro deg/s, accel g, mag uT, baro hPa (10 floats).
    REQUIRE(decodeAs(OscFormat::Ngimu, encodeOscMessage("/sensors", floats({90, 0, -180, 0, 0, 1, 20, 0, -40, 1013})), r, &d) ==
            DecodeStatus::Reading);
    CHECK(d == OscFormat::Ngimu);
    CHECK(r.kind == SensorReading::Kind::Imu);
    CHECK(r.gyro.isApprox(Eigen::Vector3d(kPi / 2, 0, -kPi), 1e-6));
    CHECK(r.accel.z() == Approx(kStandardGravity).epsilon(1e-6));
    CHECK(r.mag.x() == Approx(20.0));
    CHECK(decodeAs(OscFormat::Ngimu, encodeOscMessage("/sensors", floats({1, 2, 3})), r) == DecodeStatus::WrongTypes);
    // NGIMU /quaternion (w x y z, NWU): identity = sensor x north, y west, z up. In the contract
    // frame (X east, Y up, Z south) sensor x must map to north (−Z), z to up (+Y).
    REQUIRE(decodeAs(OscFormat::Ngimu, encodeOscMessage("/quaternion", floats({1, 0, 0, 0})), r) == DecodeStatus::Reading);
    CHECK((r.q * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-9));
    CHECK((r.q * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));
    CHECK((r.q * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX(), 1e-9));   // west
    // x-io's quaternion is the conjugate of sensor→NWU (NgimuGui/3DView/Form3DView.cs draws the
    // board by its inverse; Maths/Quaternion.cs FromEulerAngles returns Conjugate(ZYX)). A board
    // yawed 90° to the left (sensor x toward west): sensor→NWU = 90° about up, (cos 45°, 0, 0,
    // sin 45°); x-io sends its conjugate (cos 45°, 0, 0, −sin 45°).
    const double c45 = std::cos(kPi / 4);
    REQUIRE(decodeAs(OscFormat::Ngimu, encodeOscMessage("/quaternion", floats({c45, 0, 0, -c45})), r) == DecodeStatus::Reading);
    CHECK((r.q * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-6));   // west = −X east
    CHECK((r.q * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-6));    // sensor y → south
    // /euler roll pitch yaw (deg) of the same board: yaw +90°; and a board pitched nose-down by
    // 30° (ZYX: pitch about y, positive turns x toward −z): sensor x → north, 30° below the horizon.
    REQUIRE(decodeAs(OscFormat::Ngimu, encodeOscMessage("/euler", floats({0, 0, 90})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::Ngimu);
    CHECK((r.q * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-6));
    REQUIRE(decodeAs(OscFormat::Ngimu, encodeOscMessage("/euler", floats({0, 30, 0})), r) == DecodeStatus::Reading);
    CHECK((r.q * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(0, -0.5, -std::sqrt(0.75)), 1e-6));
    // /matrix = ToRotationMatrix(q) (Quaternion.cs): XY = 2(xy + wz) with x-io's q; for the
    // yawed board (w = c45, z = −c45): XX = 0, XY = −1, YX = 1, ZZ = 1 → sensor x = (0, 1, 0) NWU = west.
    REQUIRE(decodeAs(OscFormat::Ngimu, encodeOscMessage("/matrix", floats({0, -1, 0, 1, 0, 0, 0, 0, 1})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::Ngimu);
    CHECK((r.q * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-6));
    CHECK(decodeAs(OscFormat::Ngimu, encodeOscMessage("/matrix", floats({2, 0, 0, 0, 1, 0, 0, 0, 1})), r) == DecodeStatus::Absurd);

    // Sensors2OSC: Android values as floats, m/s² and rad/s; rotation vector in East-North-Up.
    REQUIRE(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/accelerometer", floats({0, 0, 9.81})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::Sensors2Osc);
    CHECK(r.kind == SensorReading::Kind::Accel);
    CHECK(r.accel.z() == Approx(9.81));
    // A rotation vector of 90° about Android z (up): the phone's y (top) points west.
    const double s45 = std::sin(kPi / 4);
    REQUIRE(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/rotationvector", floats({0, 0, s45, s45, 0.1})), r) == DecodeStatus::Reading);
    CHECK((r.q * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX(), 1e-6));
    CHECK((r.q * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY(), 1e-6));
    CHECK(r.qHasHeading);
    // Older Androids send 3 values: w = √(1 − |xyz|²).
    REQUIRE(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/rotationvector", floats({0, 0, s45})), r) == DecodeStatus::Reading);
    CHECK((r.q * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX(), 1e-6));
    CHECK(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/rotationvector", floats({0.9, 0.9, 0})), r) == DecodeStatus::Absurd);
    CHECK(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/light", floats({300})), r) == DecodeStatus::Known);

    // ZIG SIM: /ZIGSIM/<uuid>/gravity in G with Core Motion's sign (screen up: z = −1) → specific force +g.
    REQUIRE(decodeAs(OscFormat::ZigSim, encodeOscMessage("/ZIGSIM/abc123/gravity", floats({0, 0, -1})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::ZigSim);
    CHECK(r.kind == SensorReading::Kind::Gravity);
    CHECK(r.accel.z() == Approx(kStandardGravity));
    CHECK(std::string(r.device) == "abc123");
    CHECK(r.deviceKey != 0);
    REQUIRE(decodeAs(OscFormat::ZigSim, encodeOscMessage("/ZIGSIM/abc123/compass", {OscArg::float32(90.0f), OscArg::int32(1)}), r) ==
            DecodeStatus::Reading);
    CHECK(r.kind == SensorReading::Kind::Heading);
    // Core Location ignores a face-up headingOrientation (CLLocationManager.h): the flag changes
    // nothing; the heading is the portrait one, perpendicular to the phone's x axis.
    CHECK(r.headingAxis == Eigen::Vector3d(1, 0, 0));
    CHECK(r.headingNormalToAxis);
    SensorReading portrait;
    REQUIRE(decodeAs(OscFormat::ZigSim, encodeOscMessage("/ZIGSIM/abc123/compass", {OscArg::float32(90.0f), OscArg::int32(0)}), portrait) ==
            DecodeStatus::Reading);
    CHECK(portrait.headingAxis == r.headingAxis);
    CHECK(portrait.headingDeg == r.headingDeg);
    REQUIRE(decodeAs(OscFormat::ZigSim, encodeOscMessage("/abc123/compass", floats({45})), r) == DecodeStatus::Reading);   // older: heading alone
    CHECK(r.headingDeg == Approx(45.0));
    CHECK(decodeAs(OscFormat::ZigSim, encodeOscMessage("/ZIGSIM/abc123/deviceinfo", {OscArg::string("iPhone")}), r) == DecodeStatus::Known);
    CHECK(decodeAs(OscFormat::ZigSim, encodeOscMessage("/abc123/gyro", floats({0.1, 0, 0})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::ZigSim);   // the older address form without /ZIGSIM

    // GyrOSC and TouchOSC.
    REQUIRE(decodeAs(OscFormat::GyrOsc, encodeOscMessage("/gyrosc/rrate", floats({0, 1, 0})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::GyrOsc);
    CHECK(r.gyro.y() == Approx(1.0));
    REQUIRE(decodeAs(OscFormat::TouchOsc, encodeOscMessage("/accxyz", floats({0, 0, -1})), r, &d) == DecodeStatus::Reading);
    CHECK(d == OscFormat::TouchOsc);
    CHECK(r.accel.z() == Approx(kStandardGravity));

    // Refusals are named: wrong tags, NaN, absurd.
    CHECK(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/gyroscope", {OscArg::string("x"), OscArg::float32(0), OscArg::float32(0)}), r) ==
          DecodeStatus::WrongTypes);
    CHECK(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/gyroscope", floats({std::nan(""), 0, 0})), r) == DecodeStatus::NonFinite);
    CHECK(decodeAs(OscFormat::Sensors2Osc, encodeOscMessage("/gyroscope", floats({100, 0, 0})), r) == DecodeStatus::Absurd);
    CHECK(decodeAs(OscFormat::Ngimu, encodeOscMessage("/sensors", floats({0, 0, 0, 0, 0, 40, 0, 0, 0, 1000})), r) == DecodeStatus::Absurd);
    OscFormat parsed;
    CHECK(parseOscFormat("NGIMU", parsed));
    CHECK(parsed == OscFormat::Ngimu);
    CHECK_FALSE(parseOscFormat("gyro", parsed));
}

TEST_CASE("osc merger: separate sensors at their own rates become samples at their own times", "[device][osc][merger]")
{
    OscSampleMerger m;
    Collected c;
    attach(m, c);
    // Sensors2OSC phone lying screen up, still: accel 50 Hz, gyro 100 Hz, mag 20 Hz, arrival times.
    for (int k = 0; k < 200; ++k) {
        const double t = 0.01 * k + 0.0003 * (k % 3);   // some jitter
        if (k % 5 == 0) feed(m, encodeOscMessage("/magneticfield", floats({0, 20, -40})), t);
        if (k % 2 == 0) feed(m, encodeOscMessage("/accelerometer", floats({0, 0, 9.81})), t);
        feed(m, encodeOscMessage("/gyroscope", floats({0, 0, 0.1})), t + 0.0001);
    }
    CHECK(m.format() == OscFormat::Sensors2Osc);
    CHECK(m.mount().name == "phone-screen-up");
    // The first 0.3 s only show which sensors the phone sends (warm-up); then one sample per gyro.
    REQUIRE(c.imu.size() == 170);
    // Each sample keeps its gyro message's own time (no synthetic clock).
    for (std::size_t i = 0; i < c.imu.size(); ++i) {
        const double k = double(i + 30);
        CHECK(c.imu[i].t == Approx(0.01 * k + 0.0003 * double((i + 30) % 3) + 0.0001));
    }
    // Phone screen up, top toward the hand: phone z (up) is device y, phone z-rate is device y-rate.
    CHECK(c.imu[10].accel.isApprox(Eigen::Vector3d(0, 9.81, 0), 1e-6));
    CHECK(c.imu[10].gyro.isApprox(Eigen::Vector3d(0, 0.1, 0), 1e-6));
    CHECK(c.imu[10].mag.isApprox(Eigen::Vector3d(20, -40, 0), 1e-6));   // phone (x, y, z) → device (y, z, x)
    const OscInputStats s = m.stats();
    CHECK(s.imu == 170);
    CHECK(s.bad == 0);

    // A gap is a gap: nothing for 1.5 s, then samples at their arrival times again.
    feed(m, encodeOscMessage("/accelerometer", floats({0, 0, 9.81})), 3.5);
    feed(m, encodeOscMessage("/gyroscope", floats({0, 0, 0.1})), 3.51);
    REQUIRE(c.imu.size() == 171);
    CHECK(c.imu.back().t == Approx(3.51));
    // Sensors2OSC resends a reading only when it changed (SensorConfiguration.sendingNotNeeded):
    // the magnetometer not heard since is unchanged, held — not stale.
    CHECK(c.imu.back().mag.isApprox(Eigen::Vector3d(20, -40, 0), 1e-6));
}

TEST_CASE("osc merger: bundle time tags are the sample times, mapped onto the receiver's clock", "[device][osc][merger]")
{
    OscSampleMerger m;
    Collected c;
    attach(m, c);
    const std::uint64_t epoch = (std::uint64_t(3900000000u) << 32);   // the NGIMU's own clock
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> delay(0.0, 0.02);
    for (int k = 0; k < 100; ++k) {
        const double sampleT = 0.01 * k;
        const std::uint64_t tag = epoch + static_cast<std::uint64_t>(sampleT * 4294967296.0);
        const auto msg = encodeOscMessage("/sensors", floats({0, 0, 0, 0, 0, 1, 20, 0, -40, 1000}));
        feed(m, encodeOscBundle(tag, {msg}), 100.0 + sampleT + delay(rng));   // arrivals jitter by up to 20 ms
    }
    REQUIRE(c.imu.size() == 70);   // after the 0.3 s warm-up
    // Intervals are the tags' (10 ms), whatever the arrival jitter.
    for (std::size_t i = 1; i < c.imu.size(); ++i) CHECK(c.imu[i].t - c.imu[i - 1].t == Approx(0.01).margin(1e-5));
    CHECK(c.imu[0].t >= 100.3);
    CHECK(c.imu[0].t <= 100.321);
    // NGIMU axes (x toward the hand, z out of the back of the forearm): z-up gravity is device y.
    CHECK(c.imu[0].accel.isApprox(Eigen::Vector3d(0, kStandardGravity, 0), 1e-6));
    // A repeated (late) bundle is refused as out of order, not delivered twice.
    const std::uint64_t oldTag = epoch + static_cast<std::uint64_t>(0.5 * 4294967296.0);
    feed(m, encodeOscBundle(oldTag, {encodeOscMessage("/sensors", floats({0, 0, 0, 0, 0, 1, 20, 0, -40, 1000}))}), 101.2);
    CHECK(c.imu.size() == 70);
    CHECK(m.stats().outOfOrder == 1);
}

TEST_CASE("osc merger: bad input is counted by kind and never moves the orientation", "[device][osc][merger]")
{
    OscSampleMerger m;
    Collected c;
    attach(m, c);
    double t = 0.0;
    auto good = [&] {
        t += 0.01;
        feed(m, encodeOscMessage("/armadillo/imu", floats({0, 0, 0, 0, 9.8, 0, 0.3, -0.5, -0.8})), t);
    };
    for (int i = 0; i < 300; ++i) good();
    const std::size_t before = c.imu.size();
    REQUIRE(before == 300);

    // Wrong type tags, NaN/∞, absurd, malformed, nested too deep, another format, another device.
    feed(m, encodeOscMessage("/armadillo/imu", {OscArg::string("x")}), t += 0.01);
    feed(m, encodeOscMessage("/armadillo/imu", floats({0, 0, 0, 0, std::numeric_limits<double>::infinity(), 0})), t += 0.01);
    feed(m, encodeOscMessage("/armadillo/imu", floats({0, 0, 0, 0, 900, 0})), t += 0.01);
    const std::vector<std::uint8_t> junk {'/', 'a', 0};
    feed(m, junk, t += 0.01);
    std::vector<std::uint8_t> deep = encodeOscMessage("/armadillo/imu", floats({0, 0, 0, 0, 9.8, 0}));
    for (int i = 0; i < kOscMaxBundleDepth + 1; ++i) deep = encodeOscBundle(1, {deep});
    feed(m, deep, t += 0.01);
    feed(m, encodeOscMessage("/accxyz", floats({1, 0, 0})), t += 0.01);
    feed(m, encodeOscMessage("/armadillo/imu", floats({5, 5, 5, 9.8, 0, 0})), t += 0.01, /*sender*/ 99);
    const OscInputStats s = m.stats();
    CHECK(s.wrongTypes == 1);
    CHECK(s.nonFinite == 1);
    CHECK(s.absurd == 1);
    CHECK(s.malformed == 1);
    CHECK(s.tooDeep == 1);
    CHECK(s.otherFormat == 1);
    CHECK(s.otherDevice == 1);
    CHECK(s.bad == 5);
    CHECK(c.imu.size() == before);   // none of them reached the filter
    CHECK(std::string(m.lastError()).find("second device") != std::string::npos);

    // A flood at 10× the stream's rate: the surplus is dropped and counted.
    const std::size_t beforeFlood = c.imu.size();
    for (int i = 0; i < 1000; ++i) {
        t += 0.001;
        feed(m, encodeOscMessage("/armadillo/imu", floats({0, 0, 0, 0, 9.8, 0, 0.3, -0.5, -0.8})), t);
    }
    const std::size_t passed = c.imu.size() - beforeFlood;
    CHECK(m.stats().flood > 500);
    CHECK(passed < 450);   // ≈ 3 × 100 Hz over 1 s plus the burst allowance
    CHECK(passed > 250);

    // The chosen device silent for longer than the timeout: another may take over.
    feed(m, encodeOscMessage("/armadillo/imu", floats({0, 0, 0, 0, 9.8, 0})), t + 5.0, 99);
    CHECK(m.stats().deviceSwitches == 1);
}

TEST_CASE("osc merger: /armadillo/orientation takes a rotation's quaternion, not any length", "[device][osc][merger]")
{
    // Length 1 within 10 % is rounding and is normalised; 1e-30, 1e-300, 2 and 1e30 are absurd
    // (Core/Pose.h isRotationLength; 0.4.0 normalised any non-zero length).
    OscSampleMerger m;
    Collected c;
    attach(m, c);
    double t = 0.0;
    feed(m, encodeOscMessage("/armadillo/orientation", floats({1.05, 0, 0, 0})), t += 0.01);
    REQUIRE(c.q.size() == 1);
    CHECK(c.q[0].second.norm() == Approx(1.0).margin(1e-12));
    for (const double w : {1e-30, 1e-300, 0.0, 2.0, 1e30}) {
        INFO(w);
        feed(m, encodeOscMessage("/armadillo/orientation", floats({w, 0, 0, 0})), t += 0.01);
    }
    CHECK(c.q.size() == 1);   // none of them moved the orientation
    CHECK(m.stats().absurd == 5);
}

TEST_CASE("osc merger: an accelerometer alone gives tilt, and a compass gives a heading", "[device][osc][merger]")
{
    {
        OscSampleMerger m;
        Collected c;
        attach(m, c);
        // TouchOSC, phone strapped screen up along the forearm, forearm raised 30°, rolled 20°.
        const Pose truth {30.0, 0.0, 20.0};
        const Eigen::Quaterniond qDev = poseToQuaternion(truth);
        Mount phone;
        REQUIRE(mountPreset("phone-screen-up", phone));
        const Eigen::Vector3d upSensor = phone.rotation.conjugate() * (qDev.conjugate() * Eigen::Vector3d::UnitY());
        for (int k = 0; k < 100; ++k) {
            const Eigen::Vector3d g = -upSensor;   // iOS sign: gravity, in G
            feed(m, encodeOscMessage("/accxyz", floats({g.x(), g.y(), g.z()})), 0.02 * k);
        }
        REQUIRE(c.q.size() > 80);
        CHECK(c.imu.empty());
        const Pose p = quaternionToPose(c.q.back().second);
        CHECK(p.elevationDeg == Approx(30.0).margin(0.5));
        CHECK(p.rollDeg == Approx(20.0).margin(0.5));
        CHECK(m.stats().tiltOnly == c.q.size());
    }
    {
        OscSampleMerger m;
        Collected c;
        attach(m, c);
        // GyrOSC: rate + gravity + compass (heading of the phone's top, i.e. the forearm) = 9 axes.
        const Pose truth {10.0, 250.0, -15.0};
        const Eigen::Quaterniond qDev = poseToQuaternion(truth);
        Mount phone;
        REQUIRE(mountPreset("phone-screen-up", phone));
        const Eigen::Vector3d upSensor = phone.rotation.conjugate() * (qDev.conjugate() * Eigen::Vector3d::UnitY());
        for (int k = 0; k < 50; ++k) {
            const double t = 0.02 * k;
            const Eigen::Vector3d g = -upSensor;
            feed(m, encodeOscMessage("/gyrosc/grav", floats({g.x(), g.y(), g.z()})), t);
            feed(m, encodeOscMessage("/gyrosc/comp", floats({250.0})), t);
            feed(m, encodeOscMessage("/gyrosc/rrate", floats({0, 0, 0})), t + 0.001);
        }
        REQUIRE(c.imu.size() == 35);   // after the 0.3 s warm-up
        // The synthesized field's horizontal part points north in the device frame.
        const Eigen::Vector3d northDev = qDev.conjugate() * -Eigen::Vector3d::UnitZ();
        const Eigen::Vector3d m0 = c.imu.back().mag;
        REQUIRE(m0.allFinite());
        CHECK(radToDeg(std::acos(std::clamp(m0.normalized().dot(northDev), -1.0, 1.0))) < 0.5);
    }
}

TEST_CASE("osc merger: each compass reading makes one field, levelled by the sender's gravity, not its pushed accelerometer", "[device][osc][merger]")
{
    const Pose truth {10.0, 250.0, -15.0};
    const Eigen::Quaterniond qDev = poseToQuaternion(truth);
    Mount phone;
    REQUIRE(mountPreset("phone-screen-up", phone));
    const Eigen::Vector3d upSensor = phone.rotation.conjugate() * (qDev.conjugate() * Eigen::Vector3d::UnitY());
    const Eigen::Vector3d northDev = qDev.conjugate() * -Eigen::Vector3d::UnitZ();
    auto northError = [&](const Eigen::Vector3d& m) { return radToDeg(std::acos(std::clamp(m.normalized().dot(northDev), -1.0, 1.0))); };
    {
        // GyrOSC: rate at 100 Hz, gravity at 50 Hz, compass at 10 Hz for 2 s.
        OscSampleMerger m;
        Collected c;
        attach(m, c);
        int compassReadings = 0;
        for (int k = 0; k < 200; ++k) {
            const double t = 0.01 * k;
            const Eigen::Vector3d g = -upSensor;
            if (k % 2 == 0) feed(m, encodeOscMessage("/gyrosc/grav", floats({g.x(), g.y(), g.z()})), t);
            if (k % 10 == 0) {
                feed(m, encodeOscMessage("/gyrosc/comp", floats({250.0})), t);
                if (t > 0.25) ++compassReadings;   // used from the 0.3 s warm-up's end
            }
            feed(m, encodeOscMessage("/gyrosc/rrate", floats({0, 0, 0})), t + 0.001);
        }
        std::size_t withField = 0;
        for (const auto& s : c.imu)
            if (s.mag.allFinite()) {
                ++withField;
                CHECK(northError(s.mag) < 0.5);
            }
        INFO(c.imu.size() << " samples");
        CHECK(c.imu.size() > 150);
        CHECK(static_cast<int>(withField) == compassReadings);   // held, it would be on every sample
        CHECK(m.stats().synthesizedField == withField);
    }
    {
        // ZIG SIM during a push along the forearm (1.5 g of user acceleration): the field stays
        // level with gravity. Levelled by gravity + user acceleration it would lean with the push.
        OscSampleMerger m;
        Collected c;
        attach(m, c);
        const Eigen::Vector3d forearmSensor = phone.rotation.conjugate() * Eigen::Vector3d::UnitX();
        // Core Location's portrait heading: of the horizontal direction up × (the phone's x).
        const Eigen::Vector3d e = Eigen::Vector3d::UnitY().cross(qDev * (phone.rotation * Eigen::Vector3d::UnitX()));
        const double headingDeg = wrapDeg360(radToDeg(std::atan2(e.x(), -e.z())));
        for (int k = 0; k < 60; ++k) {
            const double t = k / 60.0;
            const Eigen::Vector3d grav = -upSensor;                  // G, Core Motion sign
            const Eigen::Vector3d user = -1.5 * forearmSensor;       // G: the arm pushed along +x
            const std::string p = "/ZIGSIM/f00d/";
            feed(m, encodeOscBundle(1, {encodeOscMessage(p + "accel", floats({user.x(), user.y(), user.z()})),
                                        encodeOscMessage(p + "gravity", floats({grav.x(), grav.y(), grav.z()})),
                                        encodeOscMessage(p + "gyro", floats({0, 0, 0})),
                                        encodeOscMessage(p + "compass", {OscArg::float32(float(headingDeg)), OscArg::int32(0)})}),
                 t);
        }
        REQUIRE(!c.imu.empty());
        const Eigen::Vector3d m0 = c.imu.back().mag;
        REQUIRE(m0.allFinite());
        CHECK(std::abs(m0.normalized().dot(qDev.conjugate() * Eigen::Vector3d::UnitY())) < 1e-6);   // horizontal
        CHECK(northError(m0) < 0.5);
    }
}

TEST_CASE("mount: presets, files, and the pose calibration recovers any strap rotation", "[device][osc][mount]")
{
    Mount phone;
    REQUIRE(mountPreset("phone-screen-up", phone));
    CHECK((phone.rotation * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitX()));   // top → hand
    CHECK((phone.rotation * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY()));   // screen → back of forearm
    Mount ng;
    REQUIRE(mountPreset("ngimu", ng));
    CHECK((ng.rotation * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY()));
    CHECK_FALSE(mountPreset("sideways", ng));

    std::mt19937 rng(11);
    std::normal_distribution<double> n01(0.0, 1.0);
    for (int trial = 0; trial < 20; ++trial) {
        // An arbitrary strap rotation, and the poses as a person holds them (a few degrees off).
        const Eigen::Quaterniond strap = Eigen::Quaterniond(n01(rng), n01(rng), n01(rng), n01(rng)).normalized();
        auto posed = [&](const Pose& p) { return poseToQuaternion(p); };
        const double wob = 1.0;   // degrees a careful person is off in each pose
        const Eigen::Quaterniond poses[3] = {posed({n01(rng) * wob, 40.0, n01(rng) * wob}), posed({-90.0 + std::abs(n01(rng)) * wob, 0.0, 0.0}),
                                             posed({n01(rng) * wob, 40.0, 90.0 + n01(rng) * wob})};
        MountCalibration cal;
        const int steps = trial % 2 == 0 ? 3 : 2;
        for (int p = 0; p < steps; ++p) {
            const Eigen::Vector3d upDevice = poses[p].conjugate() * Eigen::Vector3d::UnitY();
            const Eigen::Vector3d upSensor = strap.conjugate() * upDevice;
            for (int k = 0; k < 100; ++k) {
                const Eigen::Vector3d noise(n01(rng), n01(rng), n01(rng));
                cal.feed(kStandardGravity * upSensor + 0.05 * noise, 0.01 * noise);
            }
            REQUIRE(cal.ready());
            cal.finishStep();
        }
        cal.skipRoll();
        Mount solved;
        std::string why;
        REQUIRE(cal.solve(solved, why));
        INFO("trial " << trial << " poses " << steps);
        CHECK(angleDeg(solved.rotation, strap) < 3.0);
    }

    // Still in the first pose when the second is asked for: those samples are not the second
    // pose, so it never fills, and no mount comes out of one direction.
    MountCalibration same;
    for (int k = 0; k < 100; ++k) same.feed(Eigen::Vector3d(0, kStandardGravity, 0), Eigen::Vector3d::Zero());
    REQUIRE(same.ready());
    same.finishStep();
    for (int k = 0; k < 100; ++k) same.feed(Eigen::Vector3d(0, kStandardGravity, 0.5), Eigen::Vector3d::Zero());
    CHECK_FALSE(same.ready());
    same.finishStep();
    Mount none;
    std::string why;
    CHECK_FALSE(same.solve(none, why));
    CHECK(why.find("first two poses") != std::string::npos);
    // Moving samples are not counted.
    MountCalibration moving;
    for (int k = 0; k < 100; ++k) moving.feed(Eigen::Vector3d(0, kStandardGravity, 0), Eigen::Vector3d(1, 0, 0));
    CHECK_FALSE(moving.ready());
}

TEST_CASE("osc merger: decoding, merging and refusing allocate nothing and take no lock; fuzzed input never crashes", "[device][osc][merger]")
{
    ARMADILLO_REQUIRE_GUARD();
    // Every dialect's messages, good and bad, encoded before the guard.
    std::vector<std::vector<std::uint8_t>> datagrams;
    for (int k = 0; k < 50; ++k) {
        const double a = 0.01 * k;
        datagrams.push_back(encodeOscMessage("/gyroscope", floats({a, 0, 0})));
        datagrams.push_back(encodeOscMessage("/accelerometer", floats({0, 0, 9.81})));
        datagrams.push_back(encodeOscMessage("/magneticfield", floats({0, 20, -40})));
        datagrams.push_back(encodeOscMessage("/rotationvector", floats({0, 0, 0.1, 0.99})));
        datagrams.push_back(encodeOscMessage("/gyroscope", floats({std::nan(""), 0, 0})));
        datagrams.push_back(encodeOscMessage("/gyroscope", {OscArg::string("x")}));
        datagrams.push_back(encodeOscMessage("/accxyz", floats({0, 0, -1})));
        datagrams.push_back(encodeOscBundle(1, {encodeOscMessage("/ZIGSIM/u/gyro", floats({0, 0, 0}))}));
    }
    std::vector<std::uint8_t> deep = encodeOscMessage("/gyroscope", floats({0, 0, 0}));
    for (int i = 0; i < kOscMaxBundleDepth + 1; ++i) deep = encodeOscBundle(1, {deep});
    datagrams.push_back(deep);
    datagrams.push_back({'#', 'b', 'u', 'n'});

    OscSampleMerger m;
    struct Count {
        std::size_t imu = 0, q = 0;
    } count;
    m.setSinks([](void* c, const ImuSample&) { ++static_cast<Count*>(c)->imu; },
               [](void* c, double, const Eigen::Quaterniond&) { ++static_cast<Count*>(c)->q; }, &count);
    m.enableSensorTap(true);
    double t = 0.0;
    test::RealtimeGuard guard;
    for (int round = 0; round < 4; ++round)
        for (const auto& d : datagrams) m.handleDatagram(d.data(), d.size(), t += 0.002, 5, "x");
    const bool clean = guard.clean();
    INFO(guard.report());
    CHECK(clean);
    CHECK(count.imu > 100);
    CHECK(m.stats().nonFinite > 0);
    CHECK(m.stats().tooDeep == 4);

    // Fuzz: random bytes and bit flips of valid messages of every dialect.
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> byte(0, 255);
    OscSampleMerger fuzz;
    Count c2;
    fuzz.setSinks([](void* c, const ImuSample& s) {
        CHECK(s.accel.allFinite());
        CHECK(s.gyro.allFinite());
        ++static_cast<Count*>(c)->imu;
    }, [](void* c, double, const Eigen::Quaterniond& q) {
        CHECK(std::abs(q.norm() - 1.0) < 1e-6);
        ++static_cast<Count*>(c)->q;
    }, &c2);
    for (int i = 0; i < 20000; ++i) {
        std::vector<std::uint8_t> d = datagrams[static_cast<std::size_t>(i) % datagrams.size()];
        if (i % 3 == 0) d.resize(static_cast<std::size_t>(byte(rng)) & ~std::size_t(3));
        for (int f = 0; f < 1 + i % 4; ++f)
            if (!d.empty()) d[static_cast<std::size_t>(byte(rng)) % d.size()] ^= static_cast<std::uint8_t>(1 << (byte(rng) % 8));
        fuzz.handleDatagram(d.data(), d.size(), 0.001 * i, 1 + static_cast<std::uint64_t>(i % 2), "f");
    }
    CHECK(fuzz.stats().datagrams == 20000);
}

TEST_CASE("zig sim json: one object per datagram, on the OSC port, told apart by its first byte", "[device][osc][zigsim][json]")
{
    // 2024-01-01T00:00:00Z is 1704067200 s after 1970 (19723 days); March 1st is 60 days later (leap year).
    CHECK(parseIsoTimestamp("2024-01-01T00:00:00Z") == Approx(1704067200.0));
    CHECK(parseIsoTimestamp("2024-03-01T00:00:00.250Z") == Approx(1709251200.25));
    CHECK(parseIsoTimestamp("2024-03-01T02:00:00.000+02:00") == Approx(1709251200.0));
    CHECK(std::isnan(parseIsoTimestamp("2024/03/01 00:00:00")));
    CHECK(std::isnan(parseIsoTimestamp("2024-13-01T00:00:00Z")));

    // ServiceManager.getJSON: device, timestamp, sensordata (Core Motion units: G, rad/s).
    const std::string text = R"({"device":{"name":"iPhone","uuid":"C0FFEE","os":"ios","osversion":"17.0","displaywidth":390,"displayheight":844},)"
                             R"("timestamp":"2024-03-01T00:00:00.250Z","sensordata":{"accel":{"x":0,"y":0,"z":0.5},"gravity":{"x":0,"y":0,"z":-1},)"
                             R"("gyro":{"x":0,"y":0,"z":0.25},"quaternion":{"x":0,"y":0,"z":0,"w":1},"compass":{"compass":30,"faceup":1}}})";
    SensorReading r[6];
    double stamp = 0.0;
    const char* why = nullptr;
    REQUIRE(decodeZigSimJson(text, r, 6, stamp, &why) == 5);
    CHECK(stamp == Approx(1709251200.25));
    CHECK(r[0].kind == SensorReading::Kind::UserAccel);
    CHECK(r[0].accel.z() == Approx(-0.5 * kStandardGravity));
    CHECK(r[1].kind == SensorReading::Kind::Gravity);
    CHECK(r[1].accel.z() == Approx(kStandardGravity));   // screen up: specific force +g on z
    CHECK(r[2].kind == SensorReading::Kind::Gyro);
    CHECK(r[2].gyro.z() == Approx(0.25));
    CHECK(r[3].kind == SensorReading::Kind::Orientation);
    CHECK_FALSE(r[3].qHasHeading);
    CHECK(r[4].kind == SensorReading::Kind::Heading);
    CHECK(r[4].headingDeg == Approx(30.0));
    CHECK(std::string(r[0].device) == "C0FFEE");
    CHECK(r[0].deviceKey == r[4].deviceKey);
    // Older versions send the compass as a bare number.
    REQUIRE(decodeZigSimJson(R"({"sensordata":{"compass":12.5}})", r, 6, stamp, &why) == 1);
    CHECK(r[0].headingDeg == Approx(12.5));
    CHECK(std::isnan(stamp));
    CHECK(decodeZigSimJson("{\"sensordata\":", r, 6, stamp, &why) == -1);
    CHECK(std::string(why).find("not valid JSON") != std::string::npos);
    CHECK(decodeZigSimJson(R"({"other":1})", r, 6, stamp, &why) == -1);
    CHECK(std::string(why).find("sensordata") != std::string::npos);
    CHECK(decodeZigSimJson(R"({"sensordata":{"gyro":{"x":"a"}}})", r, 6, stamp, &why) == -1);

    // Through the merger on the same "port" as OSC: detected as ZIG SIM, samples made.
    OscSampleMerger m;
    Collected c;
    attach(m, c);
    for (int k = 0; k < 60; ++k) {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      R"({"device":{"uuid":"C0FFEE"},"timestamp":"2024-03-01T00:00:%02d.%03dZ","sensordata":{"gravity":{"x":0,"y":0,"z":-1},"gyro":{"x":0,"y":0,"z":0}}})",
                      k / 60, (k % 60) * 1000 / 60);
        const std::string j = buf;
        m.handleDatagram(reinterpret_cast<const std::uint8_t*>(j.data()), j.size(), 5.0 + k / 60.0 + 0.002 * (k % 3), 9, "10.0.0.9:5000");
    }
    CHECK(m.format() == OscFormat::ZigSim);
    CHECK(m.stats().json == 60);
    REQUIRE(c.imu.size() > 30);
    // The timestamps' own spacing (1/60 s to the millisecond), not the jittered arrivals.
    CHECK(c.imu[5].t - c.imu[4].t == Approx(1.0 / 60.0).margin(0.0011));
    CHECK(m.rates().gyro == Approx(60.0).epsilon(0.05));
    CHECK(lowRateAdvice(OscFormat::ZigSim, m.rates().fusion()).empty());
    CHECK(lowRateAdvice(OscFormat::ZigSim, 10.0).find("MESSAGE RATE") != std::string::npos);
    // A datagram that is neither: counted as malformed and listed by its first bytes.
    const std::uint8_t junk[] = {'H', 'e', 'l', 'l', 'o'};
    m.handleDatagram(junk, sizeof junk, 7.0, 9, "10.0.0.9:5000");
    const std::string heard = describeHeard(m.heard());
    CHECK(heard.find("48 65 6c 6c 6f") != std::string::npos);
    CHECK(heard.find("10.0.0.9:5000 (61 datagrams)") != std::string::npos);
}

TEST_CASE("sensors2osc: a reading not resent is unchanged; a phone lying still has its orientation from its first readings",
          "[device][osc][sensors2osc]")
{
    // SensorConfiguration.sendingNotNeeded (Sensors2OSC): a sensor's reading is sent only when it
    // differs from the last one (starting from zeros). Lying perfectly still: the gyroscope (all
    // zeros) never sends; the accelerometer and magnetometer send once.
    OscSampleMerger m;
    Collected c;
    attach(m, c);
    feed(m, encodeOscMessage("/accelerometer", floats({0, 0, 9.81})), 0.0);
    feed(m, encodeOscMessage("/magneticfield", floats({0, 20, -40})), 0.001);
    for (int k = 1; k <= 200; ++k) m.tick(0.02 * k);   // the receiver's idle calls: 4 s of nothing
    // After the warm-up, samples of the held readings at the rest period (50 Hz), gyro zero.
    REQUIRE(c.imu.size() > 180);
    CHECK(c.imu.front().t < 0.4);
    CHECK(c.imu.back().t == Approx(4.0));
    CHECK(c.imu.back().gyro.norm() == 0.0);
    CHECK(c.imu.back().accel.isApprox(Eigen::Vector3d(0, 9.81, 0), 1e-6));
    CHECK(c.imu.back().mag.isApprox(Eigen::Vector3d(20, -40, 0), 1e-6));
    CHECK(m.stats().unchanged == c.imu.size());
    // It starts to turn: gyro messages drive the samples; then it stops turning and goes silent
    // while its last gyroscope reading was not zero: that silence is a gap, nothing is made.
    const std::size_t before = c.imu.size();
    for (int k = 0; k < 50; ++k) feed(m, encodeOscMessage("/gyroscope", floats({0, 0, 0.3 + 0.001 * k})), 4.01 + 0.01 * k);
    CHECK(c.imu.size() == before + 50);
    for (int k = 1; k <= 100; ++k) m.tick(4.5 + 0.02 * k);
    CHECK(c.imu.size() == before + 50);   // the gap stays a gap
    // A gyroscope that said exactly zero last is at rest: held samples again.
    feed(m, encodeOscMessage("/gyroscope", floats({0, 0, 0})), 6.6);
    for (int k = 1; k <= 50; ++k) m.tick(6.6 + 0.02 * k);
    CHECK(c.imu.size() > before + 50 + 40);
    // Another format never holds: a silent ZIG SIM is a gap.
    OscSampleMerger z;
    Collected cz;
    attach(z, cz);
    feed(z, encodeOscMessage("/ZIGSIM/ab/gravity", floats({0, 0, -1})), 0.0);
    for (int k = 1; k <= 100; ++k) z.tick(0.02 * k);
    CHECK(cz.imu.empty());
}
