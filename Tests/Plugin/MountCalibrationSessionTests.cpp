// The guided mount calibration behind the device panel's "Calibrate mount..." (no JUCE): a sensor
// strapped on at an arbitrary rotation is held in the poses (with noise, a small tremor and the
// arm moving between poses), and the session recovers the strap rotation; the same through the
// OSC merger's sensor-frame tap, which the app drains.
#include "Core/Types.h"
#include "Osc/Osc.h"
#include "Osc/OscInput.h"
#include "Procedures/MountCalibration.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using MountCalibrationSession = armadillo::procedures::MountCalibration;   // the app's session is the procedure (issue 32)
using Pose = MountCalibrationSession::Pose;

namespace {
using Q = Eigen::Quaterniond;
using V = Eigen::Vector3d;

/// "Up" (the specific force direction at rest) in the DEVICE frame for each pose (Mount.h).
V upInDevice(Pose p)
{
    switch (p) {
    case Pose::LevelForward: return V::UnitY();
    case Pose::HangingDown: return -V::UnitX();
    case Pose::RolledRight: return -V::UnitZ();
    case Pose::Done: break;
    }
    return V::Zero();
}

double angleDeg(const Q& a, const Q& b)
{
    return radToDeg(a.angularDistance(b));
}

/// A person holding a strapped sensor (mount `strap`: sensor → device): samples of one pose,
/// the pose tilted by up to `wobbleDeg` (nobody holds the arm exactly level) and noisy.
struct Arm {
    Q strap;
    std::mt19937 rng {7};
    double t = 0.0;
    osc::SensorFrameSample sample(const V& upDevice, double noise)
    {
        std::normal_distribution<double> n(0.0, noise);
        const V accelDevice = upDevice * kStandardGravity + V(n(rng), n(rng), n(rng));
        const V a = strap.conjugate() * accelDevice;   // device → sensor axes
        osc::SensorFrameSample s;
        t += 0.01;
        s.t = t;
        for (int i = 0; i < 3; ++i) {
            s.accel[i] = a[i];
            s.gyro[i] = n(rng) * 0.02;   // tremor, well under the stillness limit
        }
        return s;
    }
    /// The arm moving from one pose to the next: fast, so none of it counts as a pose.
    void move(MountCalibrationSession& session)
    {
        for (int i = 0; i < 50; ++i) {
            osc::SensorFrameSample s = sample(V(0.5, 0.5, 0.7).normalized(), 3.0);
            s.gyro[0] = 2.0;
            session.feed(s);
        }
    }
    void hold(MountCalibrationSession& session, Pose p, int samples, double noise = 0.08)
    {
        for (int i = 0; i < samples; ++i) session.feed(sample(upInDevice(p), noise));
    }
};

Q randomRotation(std::mt19937& rng)
{
    std::normal_distribution<double> n(0.0, 1.0);
    return Q(n(rng), n(rng), n(rng), n(rng)).normalized();
}
} // namespace

TEST_CASE("mount calibration session: an arbitrary strap rotation comes back within 3 degrees", "[plugin][mount]")
{
    std::mt19937 rng(2026);
    for (int trial = 0; trial < 20; ++trial) {
        const Q strap = randomRotation(rng);
        const bool withRoll = trial % 2 == 0;
        Arm arm {strap};
        MountCalibrationSession session;
        session.begin("phone-1");
        REQUIRE(session.running());
        std::string why;
        for (const Pose p : {Pose::LevelForward, Pose::HangingDown, Pose::RolledRight}) {
            REQUIRE(session.pose() == p);
            if (p == Pose::RolledRight && ! withRoll) {
                REQUIRE(session.canSkip());
                REQUIRE(session.skip(why));
                break;
            }
            CHECK_FALSE(session.ready());
            arm.hold(session, p, 80);
            REQUIRE(session.ready());
            CHECK(session.progress() == Approx(1.0));
            REQUIRE(session.next(why));
            if (p != Pose::RolledRight) arm.move(session);
        }
        REQUIRE(session.finished());
        const double err = angleDeg(session.result().rotation, strap);
        INFO("trial " << trial << " roll " << withRoll << " error " << err << " deg");
        CHECK(err < 3.0);
        CHECK(session.result().device == "phone-1");
        CHECK(session.result().name == "calibrated");
        // The solved mount maps the sensor's gravity in each pose onto the forearm's.
        CHECK((session.result().toDevice(strap.conjugate() * V::UnitY()) - V::UnitY()).norm() < 0.05);
    }
}

TEST_CASE("mount calibration session: a full pose waits for Next; moving on cannot overwrite it", "[plugin][mount]")
{
    std::mt19937 rng(11);
    const Q strap = randomRotation(rng);
    Arm arm {strap};
    MountCalibrationSession session;
    session.begin("dev");
    std::string why;
    // Next with no data says why, and nothing moves on.
    CHECK_FALSE(session.next(why));
    CHECK(why.find("No sensor samples") != std::string::npos);
    CHECK(session.pose() == Pose::LevelForward);
    CHECK_FALSE(session.canSkip());
    CHECK_FALSE(session.skip(why));
    arm.hold(session, Pose::LevelForward, 80);
    REQUIRE(session.ready());
    // The person lets the arm hang before pressing Next: the level pose must stay the level pose.
    arm.move(session);
    arm.hold(session, Pose::HangingDown, 200);
    REQUIRE(session.next(why));
    REQUIRE(session.pose() == Pose::HangingDown);
    CHECK(session.progress() == 0.0);   // the hanging samples before Next did not count twice
    arm.hold(session, Pose::HangingDown, 80);
    REQUIRE(session.next(why));
    REQUIRE(session.skip(why));
    REQUIRE(session.finished());
    CHECK(angleDeg(session.result().rotation, strap) < 3.0);
    // Samples after the end change nothing; cancel clears.
    arm.hold(session, Pose::LevelForward, 10);
    CHECK(session.finished());
    session.cancel();
    CHECK_FALSE(session.running());
    CHECK_FALSE(session.finished());
}

TEST_CASE("mount calibration session: a moving arm never fills a pose", "[plugin][mount]")
{
    Arm arm {Q::Identity()};
    MountCalibrationSession session;
    session.begin({});
    for (int i = 0; i < 20; ++i) arm.move(session);
    CHECK(session.progress() == 0.0);
    std::string why;
    CHECK_FALSE(session.next(why));
    CHECK(why.find("still") != std::string::npos);
    CHECK(session.stepTitle() == "Pose 1 of 3: level forward");
}

TEST_CASE("mount calibration session: fed from the OSC merger's tap, in the sensor's own axes", "[plugin][mount]")
{
    // A sender using ARMadillo's /armadillo/imu, with a mount already set (the app's current one):
    // the tap must give the sensor's own axes back, so the calibration does not depend on the mount in use.
    std::mt19937 rng(5);
    const Q strap = randomRotation(rng);
    osc::OscInputOptions options;
    options.format = osc::OscFormat::Armadillo;
    REQUIRE(link::mountPreset("phone-screen-up", options.mount));
    options.mountGiven = true;
    osc::OscSampleMerger merger(options);
    int delivered = 0;
    merger.setSinks([](void* c, const ImuSample&) { ++*static_cast<int*>(c); }, [](void*, double, const Q&) {}, &delivered);
    merger.enableSensorTap(true);

    MountCalibrationSession session;
    session.begin("udp-sender");
    Arm arm {strap};
    double arrival = 10.0;
    auto send = [&](Pose p, int n) {
        for (int i = 0; i < n; ++i) {
            const osc::SensorFrameSample s = arm.sample(upInDevice(p), 0.05);
            const std::vector<osc::OscArg> args {
                osc::OscArg::float32(static_cast<float>(s.gyro[0])),  osc::OscArg::float32(static_cast<float>(s.gyro[1])),
                osc::OscArg::float32(static_cast<float>(s.gyro[2])),  osc::OscArg::float32(static_cast<float>(s.accel[0])),
                osc::OscArg::float32(static_cast<float>(s.accel[1])), osc::OscArg::float32(static_cast<float>(s.accel[2]))};
            const auto bytes = osc::encodeOscMessage("/armadillo/imu", args);
            arrival += 0.01;
            merger.handleDatagram(bytes.data(), bytes.size(), arrival, 1, "udp-sender");
            if (i % 10 == 9) session.drain([&](osc::SensorFrameSample& out) { return merger.popSensorSample(out); });
        }
        session.drain([&](osc::SensorFrameSample& out) { return merger.popSensorSample(out); });
    };
    std::string why;
    send(Pose::LevelForward, 100);
    REQUIRE(session.ready());
    REQUIRE(session.next(why));
    send(Pose::HangingDown, 100);
    REQUIRE(session.next(why));
    send(Pose::RolledRight, 100);
    REQUIRE(session.next(why));
    REQUIRE(session.finished());
    CHECK(delivered >= 290);
    INFO("error " << angleDeg(session.result().rotation, strap) << " deg");
    CHECK(angleDeg(session.result().rotation, strap) < 3.0);
}

TEST_CASE("mount calibration session: per-device file names are safe", "[plugin][mount]")
{
    CHECK(MountCalibrationSession::fileNameForDevice("") == "mount-sensor.json");
    CHECK(MountCalibrationSession::fileNameForDevice("192.168.1.20:53412") == "mount-192-168-1-20.json");   // no ephemeral port
    CHECK(MountCalibrationSession::fileNameForDevice("fe80::1") == "mount-fe80-1.json");
    CHECK(MountCalibrationSession::fileNameForDevice("../../etc/passwd") == "mount-etc-passwd.json");
    CHECK(MountCalibrationSession::fileNameForDevice("ZIGSIM 3F2A-11") == "mount-ZIGSIM-3F2A-11.json");
}
