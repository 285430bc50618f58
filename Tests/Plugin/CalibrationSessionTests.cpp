// The guided calibration behind the device panel's "Calibrate..." (no JUCE): raw packets offered
// as the link thread offers them, drained by the message thread into the thesis's procedure
// (§2.4), step by step to a calibration close to the simulated board's true one; and the live
// link (simulated forearm, real link code) feeding it and taking up a new calibration without a
// reconnect.
#include "Core/Pose.h"
#include "Common/SimulatedBoards.h"
#include "Link/Simulator.h"
#include "Procedures/DeviceCalibration.h"
#include "Live/Sources/DeviceConnection.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;
using CalibrationSession = armadillo::procedures::DeviceCalibration;   // the app's session is the procedure (issue 32)
using armadillo::live::DeviceConnection;
using armadillo::live::LiveImu;
using armadillo::live::LiveInput;
using Step = CalibrationSession::Step;

namespace {
using Q = Eigen::Quaterniond;
using A = Eigen::AngleAxisd;

/// Feeds `session` like the link thread does (offer per packet), draining like the UI timer
/// (every 0.1 s of packets, well inside the queue).
struct Feeder {
    CalibrationSession& session;
    SensorModel& model;
    double t = 0.0;
    void run(const std::function<Q(double)>& q, double seconds)
    {
        FunctionMotion m(q);
        const double t0 = t, dt = 1.0 / 200.0;
        int n = 0;
        for (; t < t0 + seconds; t += dt) {
            session.offer(t, model.sample(m.at(t - t0), t, {}));
            if (++n % 20 == 0) session.drain();
        }
        session.drain();
    }
};

auto still(const Q& q)
{
    return [q](double) { return q; };
}

/// Polls `done` (it drains queues itself) until true or 10 s pass: waits on the condition, never on time.
bool waitUntil(const std::function<bool()>& done)
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (! done()) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

double medianAccel(LiveInput& input, int count)
{
    std::vector<double> norms;
    LiveImu imu;
    waitUntil([&] {
        while (static_cast<int>(norms.size()) < count && input.popImu(imu))
            norms.push_back(std::sqrt(double(imu.a[0]) * imu.a[0] + double(imu.a[1]) * imu.a[1] + double(imu.a[2]) * imu.a[2]));
        return static_cast<int>(norms.size()) >= count;
    });
    REQUIRE(static_cast<int>(norms.size()) == count);
    std::nth_element(norms.begin(), norms.begin() + count / 2, norms.end());
    return norms[static_cast<std::size_t>(count / 2)];
}
} // namespace

TEST_CASE("CalibrationSession: the guided steps recover a board's true calibration from offered raw packets")
{
    // A board whose ADC is not the default one: the session must find its numbers.
    const SensorModelParams p = armadillo::testing::boardWithItsOwnAdc();
    SensorModel model(p);
    CalibrationSession session;
    Feeder feed {session, model};

    // Nothing runs yet: packets are not taken, Next says why.
    session.offer(0.0, model.sample(MotionState {}, 0.0, {}));
    CHECK(session.drain() == 0);
    CHECK_FALSE(session.running());
    std::string why;
    CHECK_FALSE(session.next(why));
    CHECK_FALSE(why.empty());

    const Calibration start = defaultCalibration();
    session.begin(start);
    REQUIRE(session.running());
    CHECK(session.stepTitle() == "Step 1 of 7: gyroscope bias (keep still)");
    CHECK(session.instruction() == CalibrationProcedure(start).instruction());
    CHECK_FALSE(session.ready());
    CHECK_FALSE(session.next(why));   // no data yet: refused with a reason, the step stays
    CHECK(why.find("Not enough data") != std::string::npos);
    CHECK(session.step() == Step::GyroStill);

    feed.run(still(restOrientation()), 1.5);
    CHECK(session.progress() > 0.3);
    CHECK(session.progress() < 0.7);
    feed.run(still(restOrientation()), 2.0);
    REQUIRE(session.ready());
    REQUIRE(session.next(why));
    CHECK(session.result().gyro.bias.isApprox(p.adc.gyro.bias, 1e-3));

    REQUIRE(session.step() == Step::AccelExtremes);
    CHECK(session.stepNumber() == 2);
    const Q poses[] = {Q(A(kPi / 2, Eigen::Vector3d::UnitZ())), Q(A(-kPi / 2, Eigen::Vector3d::UnitZ())), Q::Identity(),
                       Q(A(kPi, Eigen::Vector3d::UnitX())), Q(A(-kPi / 2, Eigen::Vector3d::UnitX())), Q(A(kPi / 2, Eigen::Vector3d::UnitX()))};
    for (const Q& q : poses) feed.run(still(q), 1.0);
    REQUIRE(session.ready());
    REQUIRE(session.next(why));
    CHECK(session.result().accel.bias.isApprox(p.adc.accel.bias, 2e-3));
    CHECK(session.result().accel.scale.isApprox(p.adc.accel.scale, 5e-3));

    REQUIRE(session.step() == Step::MagHorizontal);
    feed.run([](double s) { return Q(A(2 * kPi * s / 8.0, Eigen::Vector3d::UnitY())); }, 8.0);
    REQUIRE(session.next(why));
    REQUIRE(session.step() == Step::MagVertical);
    feed.run([](double s) { return Q(A(2 * kPi * s / 8.0, Eigen::Vector3d::UnitX())); }, 8.0);
    feed.run([](double s) { return Q(A(2 * kPi * s / 8.0, Eigen::Vector3d::UnitZ())); }, 8.0);
    feed.run([](double s) { return Q(A(kPi / 2, Eigen::Vector3d::UnitY())) * Q(A(2 * kPi * s / 8.0, Eigen::Vector3d::UnitZ())); }, 8.0);
    feed.run([](double s) { return Q(A(kPi / 2, Eigen::Vector3d::UnitZ())) * Q(A(2 * kPi * s / 8.0, Eigen::Vector3d::UnitX())); }, 8.0);
    REQUIRE(session.ready());
    REQUIRE(session.next(why));
    CHECK(session.result().mag.bias.isApprox(p.adc.mag.bias, 5e-3));
    CHECK(session.result().mag.scale.isApprox(p.adc.mag.scale, 2e-2));

    // Roll (x) and the level turn (y) are measured; the tip (z) is skipped and keeps its start.
    for (int axis = 0; axis < 2; ++axis) {
        const Eigen::Vector3d a = Eigen::Vector3d::Unit(axis);
        feed.run([&](double s) { return restOrientation() * Q(A(2 * kPi * std::clamp(s / 4.0, 0.0, 1.0), a)); }, 5.0);
        REQUIRE(session.ready());
        REQUIRE(session.next(why));
        CHECK(session.result().gyro.scale[axis] == Approx(p.adc.gyro.scale[axis]).epsilon(0.01));
    }
    REQUIRE(session.step() == Step::GyroTurnZ);
    session.skip();
    REQUIRE(session.finished());
    CHECK_FALSE(session.running());
    CHECK(session.stepTitle() == "Calibration complete");
    CHECK(session.result().gyro.scale.z() == start.gyro.scale.z());
    CHECK(session.measured(Step::GyroTurnY));
    CHECK_FALSE(session.measured(Step::GyroTurnZ));
    CHECK(session.packetsDropped() == 0);
    CHECK(session.packetsFed() > 10000);

    // A finished run takes no more packets; the result stays until the next begin/cancel.
    session.offer(100.0, model.sample(MotionState {}, 100.0, {}));
    CHECK(session.drain() == 0);
    session.cancel();
    CHECK_FALSE(session.finished());
    CHECK_FALSE(session.running());
}

TEST_CASE("CalibrationSession: a UI that stops draining loses packets, never blocks the producer")
{
    SensorModel model;
    CalibrationSession session;
    session.begin(defaultCalibration());
    const int offered = static_cast<int>(CalibrationSession::kQueueCapacity) + 100;
    for (int i = 0; i < offered; ++i) session.offer(i / 200.0, model.sample(MotionState {}, i / 200.0, {}));
    CHECK(session.packetsDropped() == 100);
    CHECK(session.drain() == CalibrationSession::kQueueCapacity);
    // A new run starts empty: nothing of the old one counts.
    for (int i = 0; i < 50; ++i) session.offer(i / 200.0, model.sample(MotionState {}, i / 200.0, {}));
    session.begin(defaultCalibration());
    CHECK(session.drain() == 0);
    CHECK(session.packetsDropped() == 0);
    CHECK(session.progress() == 0.0);
}

TEST_CASE("DeviceConnection: the simulated forearm feeds the calibration; a new calibration applies without reconnecting")
{
    LiveInput input;
    link::LevelSchedule motors;
    live::ArmSourceSlot slot;   // where an instrument keeps the source
    DeviceConnection connection(input, motors, slot);
    std::string message;
    REQUIRE(connection.connect(DeviceConnection::kSimulatedPort, 57600, "", message));
    INFO(message);

    // Raw packets reach the session through its queue while it runs (drained here as the UI timer does).
    auto& session = connection.calibrationSession();
    session.begin(connection.calibration());
    CHECK(waitUntil([&] { session.drain(); return session.packetsFed() >= 40; }));
    CHECK(session.running());

    // The default calibration reads gravity as 1 g; a calibration with twice the accelerometer
    // scale, applied live, reads it as 2 g from the packet the link thread takes it up at.
    auto waitForUptake = [&] { return waitUntil([&] { return connection.calibrationInUse() == connection.calibrationPublished(); }); };
    REQUIRE(waitForUptake());
    LiveImu drop;
    while (input.popImu(drop)) {
    }
    CHECK(medianAccel(input, 41) == Approx(kStandardGravity).epsilon(0.2));
    Calibration doubled = connection.calibration();
    doubled.accel.scale *= 2.0;
    connection.applyCalibration(doubled, "test");
    CHECK(connection.calibrationNote() == "test");
    REQUIRE(waitForUptake());
    while (input.popImu(drop)) {
    }
    CHECK(medianAccel(input, 41) == Approx(2.0 * kStandardGravity).epsilon(0.2));
    CHECK(connection.isOpen());

    // Disconnecting cancels a running calibration and says why.
    connection.disconnect();
    CHECK_FALSE(session.running());
    CHECK(session.stopReason() == "the device was disconnected");
}
