// procedures::DeviceCalibration through a scripted presenter: the raw packets of a simulated board
// (Link/Simulator.h's SensorModel) moved by procedures::CalibrationRehearsal — the motion
// `armadillo calibrate --simulate` uses — are offered as the link thread offers them; the script
// presses Next when the rehearsed movement is through and the step is ready (and once at once,
// which must be refused with a reason), or skips. The board's ADC differs from the starting calibration, so the measured steps must find it.
#include "Common/ScratchDir.h"
#include "Common/SimulatedBoards.h"
#include "Link/Simulator.h"
#include "Procedures/DeviceCalibration.h"
#include <catch2/catch.hpp>
#include <filesystem>

using namespace armadillo;
using armadillo::procedures::CalibrationRehearsal;
using armadillo::procedures::DeviceCalibration;
using Step = DeviceCalibration::Step;

namespace {

/// The link side: 200 packets a second from the board moved by the rehearsal, offered one by
/// one, drained every 20 (the app's UI timer, the CLI's answer loop).
struct Board {
    link::SensorModel model;
    CalibrationRehearsal motion;
    double t = 0.0;
    /// Runs until `done()` or `maxSeconds`; true when done.
    bool runUntil(DeviceCalibration& calibration, const std::function<bool()>& done, double maxSeconds = 60.0)
    {
        for (int n = 0; n * 0.005 < maxSeconds; ++n) {
            if (n % 20 == 0) {
                calibration.drain();
                if (done()) return true;
            }
            calibration.offer(t, model.sample(motion.at(t), t, {}));
            t += 0.005;
        }
        calibration.drain();
        return done();
    }
};

} // namespace

TEST_CASE("DeviceCalibration: the rehearsal satisfies every step and the steps recover the board's calibration", "[procedures][calibration]")
{
    const link::SensorModelParams p = armadillo::testing::boardWithItsOwnAdc();
    Board board {link::SensorModel(p), {}};
    DeviceCalibration calibration;
    const link::Calibration start = link::defaultCalibration();
    calibration.begin(start);
    std::vector<std::string> prompts;
    for (int k = 0; k < DeviceCalibration::kStepCount; ++k) {
        REQUIRE(calibration.running());
        const Step step = calibration.step();
        CHECK(static_cast<int>(step) == k);
        board.motion.setStep(step);
        prompts.push_back(calibration.stepTitle() + ": " + calibration.instruction());
        CHECK(calibration.stepTitle() == "Step " + std::to_string(k + 1) + " of 7: " + DeviceCalibration::stepLabel(step));
        std::string why;
        CHECK_FALSE(calibration.next(why));   // pressed at once: not enough data, and why
        CHECK(why.find("Not enough data") != std::string::npos);
        INFO(prompts.back());
        // The simulated user says "done" once the movement is through (a step is ready() with
        // enough data for a rough number, e.g. half a turn).
        REQUIRE(board.runUntil(calibration, [&] { return calibration.ready() && board.motion.performed(); }));
        REQUIRE(calibration.next(why));
        CHECK(calibration.measured(step));
    }
    REQUIRE(calibration.finished());
    CHECK(calibration.stepTitle() == "Calibration complete");
    const link::Calibration c = calibration.result();
    CHECK(c.gyro.bias.isApprox(p.adc.gyro.bias, 2e-3));
    CHECK(c.accel.bias.isApprox(p.adc.accel.bias, 5e-3));
    CHECK(c.accel.scale.isApprox(p.adc.accel.scale, 1e-2));
    CHECK(c.mag.bias.isApprox(p.adc.mag.bias, 1e-2));
    for (int axis = 0; axis < 3; ++axis) CHECK(c.gyro.scale[axis] == Approx(p.adc.gyro.scale[axis]).epsilon(0.02));
    CHECK(calibration.measuredList(false).empty());
    CHECK(calibration.packetsDropped() == 0);

    // The file both presenters write.
    const std::string path = (armadillo::test::scratchDir("procedures-calibration") / "cal.json").string();
    calibration.save(path);
    const link::Calibration back = link::loadCalibration(path);
    CHECK(back.gyro.bias.isApprox(c.gyro.bias, 1e-6));
    CHECK(! back.date.empty());
}

TEST_CASE("DeviceCalibration: skipped steps keep the starting numbers; cancel and a stalled drain", "[procedures][calibration]")
{
    Board board {link::SensorModel {}, {}};
    DeviceCalibration calibration;
    link::Calibration start = link::defaultCalibration();
    start.gyro.scale *= 1.1;   // something a skip must keep
    calibration.begin(start);
    board.motion.setStep(Step::GyroStill);
    REQUIRE(board.runUntil(calibration, [&] { return calibration.ready(); }));
    std::string why;
    REQUIRE(calibration.next(why));
    while (calibration.running()) calibration.skip();
    CHECK(calibration.finished());
    CHECK(calibration.result().gyro.scale.isApprox(start.gyro.scale));
    CHECK(calibration.measuredList(true) == "gyro bias");
    CHECK(calibration.measuredList(false) == "accelerometer, magnetometer, gyro roll, gyro turn, gyro tip");
    // A finished run takes no packets; cancel forgets it.
    calibration.offer(1e3, link::SensorCounts {});
    CHECK(calibration.drain() == 0);
    calibration.cancel("the device was disconnected");
    CHECK_FALSE(calibration.running());
    CHECK(calibration.stopReason() == "the device was disconnected");
    // A front end that stops draining loses packets, never blocks the link thread.
    calibration.begin(start);
    for (std::size_t i = 0; i < DeviceCalibration::kQueueCapacity + 10; ++i) calibration.offer(static_cast<double>(i), link::SensorCounts {});
    CHECK(calibration.packetsDropped() == 10);
    CHECK(calibration.drain() == DeviceCalibration::kQueueCapacity);
}
