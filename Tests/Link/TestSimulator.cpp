// The simulated forearm's physics and device-side protocol (no threads): realistic counts and
// the thesis's sync rules on the device side.
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Link/Simulator.h"
#include "Link/SteerableArm.h"
#include "Core/Types.h"
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <memory>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;

TEST_CASE("device side: answers good motor packets, waits for 0x8 after a bad one", "[device][simulator]")
{
    DeviceProtocol d;
    // Power-up: waiting for the host.
    CHECK(d.waitingForResync());
    CHECK(d.onByte(0x00) == DeviceProtocol::Event::None);
    CHECK(d.onByte(0x18) == DeviceProtocol::Event::Resynced);
    const auto p = encodeMotorPacket(ProtocolLevels {1, 2, 3, 4, 5, 6, 7, 8, 9});
    for (int i = 0; i < 4; ++i) CHECK(d.onByte(p[static_cast<std::size_t>(i)]) == DeviceProtocol::Event::None);
    CHECK(d.onByte(p[4]) == DeviceProtocol::Event::MotorPacket);
    CHECK(d.levels() == ProtocolLevels {1, 2, 3, 4, 5, 6, 7, 8, 9});
    // A bad end nibble: levels kept, then wait for any byte whose low nibble is 0x8.
    const std::uint8_t bad[5] {0xFF, 0xFF, 0xFF, 0xFF, 0xF1};
    for (int i = 0; i < 4; ++i) d.onByte(bad[i]);
    CHECK(d.onByte(bad[4]) == DeviceProtocol::Event::BadPacket);
    CHECK(d.levels()[0] == 1);
    CHECK(d.onByte(0x07) == DeviceProtocol::Event::None);
    CHECK(d.onByte(0x88) == DeviceProtocol::Event::Resynced);
    CHECK(d.badPackets() == 1);
}

TEST_CASE("sensor model: gravity, dipping field, drifting gyro bias, motor vibration", "[device][simulator]")
{
    SensorModelParams p;
    SensorModel model(p);
    const Calibration cal = defaultCalibration();
    MotionState rest;
    rest.q = restOrientation();
    // Average 2 s at rest: gravity +g along the board normal, field dipping, gyro = bias.
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero(), g = Eigen::Vector3d::Zero();
    Eigen::Vector3d a2 = Eigen::Vector3d::Zero();
    const int n = 400;
    for (int i = 0; i < n; ++i) {
        const ImuSample s = cal.apply(0, model.sample(rest, i * 0.005, {}));
        a += s.accel;
        a2 += s.accel.cwiseProduct(s.accel);
        m += s.mag;
        g += s.gyro;
    }
    a /= n;
    m /= n;
    g /= n;
    CHECK(a.norm() == Approx(kStandardGravity).epsilon(0.01));
    CHECK(a.y() > 0.99 * kStandardGravity);
    CHECK(std::acos(std::clamp(a.normalized().dot(-m.normalized()), -1.0, 1.0)) == Approx(degToRad(90.0 - 65.0)).margin(0.02));
    CHECK((g - p.gyroBiasStart).norm() < 0.01);
    const double quietNoise = std::sqrt(a2.x() / n - a.x() * a.x());
    CHECK(quietNoise == Approx(p.accelNoise).epsilon(0.35));

    // Bias drifts toward its settled value over the first minute.
    CHECK((model.gyroBias(300.0) - p.gyroBiasSettled).norm() < (model.gyroBias(0.0) - p.gyroBiasSettled).norm());

    // All motors at level 10: the accelerometer gets much noisier (thesis §2.3.1).
    ProtocolLevels on;
    on.fill(10);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        const double x = cal.apply(0, model.sample(rest, 2.0 + i * 0.005, on)).accel.x();
        sum += x;
        sum2 += x * x;
    }
    const double shakenNoise = std::sqrt(sum2 / n - (sum / n) * (sum / n));
    CHECK(shakenNoise > 5.0 * quietNoise);
}

TEST_CASE("sensor model: counts saturate at the 12-bit range instead of wrapping", "[device][simulator]")
{
    SensorModel model;
    MotionState violent;
    violent.q = restOrientation();
    violent.linearAccel = Eigen::Vector3d(1000.0, -1000.0, 0.0);
    violent.omega = Eigen::Vector3d(100.0, -100.0, 0.0);
    const SensorCounts c = model.sample(violent, 0.0, {});
    CHECK(c[kAx] == kMaxCount);
    CHECK(c[kAy] == 0);
    CHECK(c[kGx] == kMaxCount);
    CHECK(c[kGy] == 0);
}

TEST_CASE("wandering motion: unit quaternions, consistent angular velocity, punches", "[device][simulator]")
{
    WanderingMotion w(3);
    int punches = 0;
    for (double t = 0; t < 60.0; t += 0.01) {
        const MotionState m = w.at(t);
        REQUIRE(std::abs(m.q.norm() - 1.0) < 1e-9);
        REQUIRE(m.omega.allFinite());
        REQUIRE(m.omega.norm() < 20.0);
        if (m.linearAccel.x() > 10.0) ++punches;
        // ω integrates to the next orientation.
        const MotionState n = w.at(t + 0.001);
        const Eigen::Quaterniond predicted = m.q * Eigen::Quaterniond(Eigen::AngleAxisd(m.omega.norm() * 0.001, m.omega.normalized()));
        REQUIRE(predicted.angularDistance(n.q) < 1e-3);
    }
    CHECK(punches > 10);
}

TEST_CASE("wandering motion: a punch pushes and stops, so the arm's velocity never drifts away", "[device][simulator]")
{
    // Integrated linear acceleration = velocity change. Each punch must give it back (the push's
    // +1.1 m/s undone by the stop); before, every punch left the arm 1.1 m/s faster for good.
    WanderingMotion w(3);
    const double dt = 1e-4;
    double v = 0.0, vMax = 0.0, vEnd = 0.0;
    int punches = 0;
    bool inPunch = false;
    for (double t = 0; t < 60.0; t += dt) {
        v += w.at(t).linearAccel.x() * dt;
        vMax = std::max(vMax, std::abs(v));
        const bool pushing = w.at(t).linearAccel.x() > 10.0;
        if (pushing && !inPunch) ++punches;
        inPunch = pushing;
        vEnd = v;
    }
    INFO("punches " << punches << ", largest velocity " << vMax << " m/s, after 60 s " << vEnd << " m/s");
    CHECK(punches > 10);
    CHECK(vMax > 0.8);                // the probe sees a punch's velocity (1.5 g · 0.12 s · 2/π ≈ 1.1 m/s)
    CHECK(vMax < 1.3);                // and never more than one punch's worth
    CHECK(std::abs(vEnd) < 0.01);     // all of it given back
}

TEST_CASE("file motion: pose and quaternion files drive the simulator; IMU files are refused", "[device][simulator]")
{
    const std::string dir = ARMADILLO_BINARY_DIR;
    const std::string posePath = dir + "/device-test-pose.csv";
    {
        std::ofstream f(posePath);
        f << "t,elevation,azimuth,roll\n0,0,0,0\n1,30,0,0\n2,30,90,0\n";
    }
    FileMotion m(posePath, false);
    CHECK(m.duration() == 2.0);
    const Pose half = quaternionToPose(m.at(0.5).q);
    CHECK(half.elevationDeg == Approx(15.0).margin(0.01));
    CHECK(m.at(0.5).omega.norm() == Approx(degToRad(30.0)).epsilon(0.01));
    CHECK(quaternionToPose(m.at(10.0).q).azimuthDeg == Approx(90.0).margin(0.01));

    const std::string imuPath = dir + "/device-test-imu.csv";
    {
        std::ofstream f(imuPath);
        f << "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,9.8,0\n";
    }
    CHECK_THROWS_AS(FileMotion(imuPath), InputError);
    CHECK_THROWS_AS(FileMotion(dir + "/does-not-exist.csv"), IoError);
    std::remove(posePath.c_str());
    std::remove(imuPath.c_str());
}

TEST_CASE("forearm device: answers the host and applies its motor levels", "[device][simulator]")
{
    ForearmDevice dev(std::make_shared<WanderingMotion>());
    CHECK(dev.onByte(kResyncByte));
    const SensorPacketBytes p = dev.answer(0.1);
    SensorCounts c {};
    CHECK(decodeSensorPacket(p.data(), c));
    CHECK(c == dev.lastCounts());
    const auto m = encodeMotorPacket(ProtocolLevels {0, 0, 0, 0, 15, 0, 0, 0, 0});
    bool answer = false;
    for (const auto b : m) answer = dev.onByte(b);
    CHECK(answer);
    CHECK(dev.protocol().levels()[4] == 15);
}

TEST_CASE("steerable arm: wanders on the simulator's path with roll flicks, eases to a steered pose and holds it",
          "[device][simulator][steer]")
{
    SteerableArm arm;
    // Wandering: the device simulator's own path, plus a quick roll flick at the start of every 7 s.
    WanderingMotion path;
    double maxFlick = 0.0;
    for (int i = 0; i < 100; ++i) {   // 0.5 s, in 5 ms steps
        const Eigen::Quaterniond q = arm.advance(0.005);
        const Eigen::Quaterniond onPath = path.at(arm.time()).q;
        maxFlick = std::max(maxFlick, q.angularDistance(onPath));
    }
    CHECK(maxFlick == Approx(kPi / 4.0).margin(0.02));   // the flick's peak: 45° about the forearm
    const Eigen::Quaterniond later = arm.advance(0.005);
    CHECK(later.angularDistance(path.at(arm.time()).q) < 1e-9);   // between flicks: exactly the path

    // Steered: eases (80 ms time constant), then holds the pose while time goes on.
    const Pose target {10.0, 120.0, -30.0};
    arm.steerTo(target);
    CHECK_FALSE(arm.wandering());
    arm.advance(0.08);
    const double afterOneTau = std::abs(wrapDeg180(arm.pose().azimuthDeg - target.azimuthDeg));
    CHECK(afterOneTau > 1.0);     // not a step
    for (int i = 0; i < 200; ++i) arm.advance(0.005);
    CHECK(arm.pose().elevationDeg == Approx(target.elevationDeg).margin(0.01));
    CHECK(std::abs(wrapDeg180(arm.pose().azimuthDeg - target.azimuthDeg)) < 0.01);
    CHECK(arm.pose().rollDeg == Approx(target.rollDeg).margin(0.01));
    const Eigen::Quaterniond held = arm.advance(0.5);
    CHECK(held.angularDistance(poseToQuaternion(target)) < 1e-3);
    arm.setWandering(true);
    CHECK(arm.advance(0.005).angularDistance(path.at(arm.time()).q) < 1e-9);
}

TEST_CASE("steerable arm: follows a motion from the moment it is given, on its own time; steering or wandering leaves it",
          "[device][simulator][steer]")
{
    SteerableArm arm;
    for (int i = 0; i < 50; ++i) arm.advance(0.005);   // 0.25 s of wandering first: the motion starts at its own 0
    const auto motion = std::make_shared<FunctionMotion>([](double t) { return poseToQuaternion({10.0 * t, 30.0, 0.0}); });
    arm.follow(motion);
    CHECK(arm.following());
    const double t0 = arm.time();
    for (int i = 1; i <= 200; ++i) {   // 1 s
        const Eigen::Quaterniond q = arm.advance(0.005);
        REQUIRE(q.angularDistance(motion->at(arm.time() - t0).q) < 1e-12);
    }
    CHECK(arm.pose().elevationDeg == Approx(10.0).margin(1e-6));   // 1 s into the motion
    CHECK(arm.time() > t0);                                         // the arm's own time never went back

    arm.steerTo({-20.0, 90.0, 0.0});
    CHECK_FALSE(arm.following());
    arm.follow(motion);
    arm.setWandering(true);
    CHECK_FALSE(arm.following());
    arm.follow(nullptr);
    CHECK_FALSE(arm.following());
    CHECK(arm.wandering());
}
