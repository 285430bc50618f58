// Calibration: the JSON file of INTERFACES.md (refused with clear errors when invalid), the
// default that matches the simulator, and the thesis's guided procedures (thesis §2.4) recovering
// a board's true calibration from simulated moves.
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Link/Calibration.h"
#include "Common/SimulatedBoards.h"
#include "Link/Simulator.h"
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;

namespace {
std::string refusal(const std::string& json)
{
    try {
        parseCalibration(json, "cal.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
const char* kValid = R"({"device": "board 7", "date": "2026-11-22",
  "accel": {"bias": [2048, 2050, 2046], "scale": [0.0239, 0.0240, 0.0238]},
  "gyro":  {"bias": [2040, 2051.5, 2049], "scale": [0.0051, 0.0051, 0.0052]},
  "mag":   {"bias": [2000, 2100, 2048], "scale": [0.001, 0.001, 0.00098], "cross": [[1,0,0],[0,1,0.01],[0,0,1]]}})";
} // namespace

TEST_CASE("calibration JSON: a valid file loads, applies and round-trips", "[device][calibration]")
{
    const Calibration c = parseCalibration(kValid, "cal.json");
    CHECK(c.device == "board 7");
    CHECK(c.accel.bias.y() == 2050.0);
    CHECK(c.gyro.bias.y() == 2051.5);
    CHECK(c.mag.cross(1, 2) == 0.01);
    SensorCounts counts {2048 + 410, 2050, 2046, 2040, 2051, 2049, 2000, 2100, 2048};
    const ImuSample s = c.apply(1.5, counts);
    CHECK(s.t == 1.5);
    CHECK(s.accel.x() == Approx(410 * 0.0239));
    CHECK(s.accel.y() == Approx(0.0).margin(1e-12));
    CHECK(s.gyro.y() == Approx(-0.5 * 0.0051));
    const Calibration again = parseCalibration(calibrationToJson(c), "again.json");
    CHECK(again.accel.scale.isApprox(c.accel.scale));
    CHECK(again.mag.cross.isApprox(c.mag.cross));
    CHECK(again.device == c.device);
    // physical = (count − bias) × scale, and toCounts is its inverse.
    const Eigen::Vector3d phys(1.0, -2.0, 3.0);
    CHECK(c.mag.apply(c.mag.toCounts(phys).x(), c.mag.toCounts(phys).y(), c.mag.toCounts(phys).z()).isApprox(phys, 1e-12));
}

TEST_CASE("calibration JSON: invalid files are refused naming the key and line", "[device][calibration]")
{
    CHECK(refusal("").find("empty") != std::string::npos);
    CHECK(refusal("[1,2]").find("JSON object") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,3], "scale": [1,1,1]}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}})").find("mag") != std::string::npos);
    const std::string shortVec = refusal(R"({"accel": {"bias": [1,2], "scale": [1,1,1]}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}, "mag": {"bias": [1,2,3], "scale": [1,1,1]}})");
    CHECK(shortVec.find("accel.bias") != std::string::npos);
    CHECK(shortVec.find("3 numbers") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,3], "scale": [1,0,1]}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}, "mag": {"bias": [1,2,3], "scale": [1,1,1]}})")
              .find("zero") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,99999], "scale": [1,1,1]}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}, "mag": {"bias": [1,2,3], "scale": [1,1,1]}})")
              .find("outside") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,"2",3], "scale": [1,1,1]}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}, "mag": {"bias": [1,2,3], "scale": [1,1,1]}})")
              .find("not a number") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,3], "scale": [1,1,1], "offset": 2}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}, "mag": {"bias": [1,2,3], "scale": [1,1,1]}})")
              .find("unknown key") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,3], "scale": [1,1,1]}, "accel": {}})").find("duplicate") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,3], "scale": [1,1,1]}} trailing)").find("after the JSON value") != std::string::npos);
    CHECK(refusal("{\"accel\": \n\n {\"bias\": [1,2,NaN]}}").find("cal.json:3") != std::string::npos);
    CHECK(refusal(R"({"accel": {"bias": [1,2,3], "scale": [1,1,1], "cross": [[0,0,0],[0,1,0],[0,0,1]]}, "gyro": {"bias": [1,2,3], "scale": [1,1,1]}, "mag": {"bias": [1,2,3], "scale": [1,1,1]}})")
              .find("singular") != std::string::npos);
    CHECK_THROWS_AS(loadCalibration("/nonexistent/cal.json"), IoError);
}

TEST_CASE("calibration file save is atomic and loads back", "[device][calibration]")
{
    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/device-test-cal.json";
    Calibration c = defaultCalibration();
    c.gyro.bias = Eigen::Vector3d(2000.25, 2001.5, 2002.75);
    saveCalibration(path, c);
    const Calibration back = loadCalibration(path);
    CHECK(back.gyro.bias.isApprox(c.gyro.bias));
    std::remove(path.c_str());
}

TEST_CASE("default calibration matches the simulator: rest reads +1 g up and the dipping field", "[device][calibration]")
{
    SensorModelParams p;
    p.accelNoise = p.gyroNoise = p.magNoise = 0.0;
    p.gyroBiasStart = p.gyroBiasSettled = Eigen::Vector3d::Zero();
    p.gyroBiasWalk = 0.0;
    SensorModel model(p);
    MotionState rest;
    rest.q = restOrientation();
    const Calibration cal = defaultCalibration();
    const ImuSample s = cal.apply(0.0, model.sample(rest, 0.0, {}));
    const double countA = cal.accel.scale.x(), countM = cal.mag.scale.x();
    CHECK(s.accel.x() == Approx(0.0).margin(countA));
    CHECK(s.accel.y() == Approx(kStandardGravity).margin(countA));
    CHECK(s.accel.z() == Approx(0.0).margin(countA));
    // Forearm toward north (device x = north), field dips 65° down (device −y).
    CHECK(s.mag.x() == Approx(std::cos(degToRad(65.0))).margin(countM));
    CHECK(s.mag.y() == Approx(-std::sin(degToRad(65.0))).margin(countM));
    CHECK(s.gyro.norm() < cal.gyro.scale.x());
}

TEST_CASE("guided calibration recovers a board's true bias and scale from simulated moves", "[device][calibration]")
{
    // A board whose ADC differs from the default: the procedure must find its numbers.
    const SensorModelParams p = armadillo::testing::boardWithItsOwnAdc();
    SensorModel model(p);
    CalibrationProcedure proc;   // starts from the default calibration
    double t = 0.0;
    const double dt = 1.0 / 200.0;
    auto run = [&](const std::function<Eigen::Quaterniond(double)>& q, double seconds) {
        FunctionMotion m(q);
        const double t0 = t;
        for (; t < t0 + seconds; t += dt) proc.feed(t, model.sample(m.at(t - t0), t, {}));
    };
    auto still = [](const Eigen::Quaterniond& q) { return [q](double) { return q; }; };
    using Q = Eigen::Quaterniond;
    using A = Eigen::AngleAxisd;
    const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();

    REQUIRE(proc.step() == CalibrationProcedure::Step::GyroStill);
    CHECK_THROWS_AS(proc.finishStep(), InputError);   // not enough data yet
    run(still(restOrientation()), 3.5);
    REQUIRE(proc.ready());
    proc.finishStep();
    CHECK(proc.result().gyro.bias.isApprox(p.adc.gyro.bias, 1e-3));

    REQUIRE(proc.step() == CalibrationProcedure::Step::AccelExtremes);
    // Each device axis held up and down: rotate so that axis maps to earth ±Y.
    const Q poses[] = {Q(A(kPi / 2, Z)), Q(A(-kPi / 2, Z)), Q::Identity(), Q(A(kPi, X)), Q(A(-kPi / 2, X)), Q(A(kPi / 2, X))};
    for (const Q& q : poses) run(still(q), 1.0);
    REQUIRE(proc.ready());
    proc.finishStep();
    CHECK(proc.result().accel.bias.isApprox(p.adc.accel.bias, 2e-3));
    CHECK(proc.result().accel.scale.isApprox(p.adc.accel.scale, 5e-3));

    REQUIRE(proc.step() == CalibrationProcedure::Step::MagHorizontal);
    run([&](double s) { return Q(A(2 * kPi * s / 8.0, Y)); }, 8.0);   // level, one full turn
    proc.finishStep();
    REQUIRE(proc.step() == CalibrationProcedure::Step::MagVertical);
    // Vertical circles about east (X) and about north-south (Z), and the board face swept too.
    run([&](double s) { return Q(A(2 * kPi * s / 8.0, X)); }, 8.0);
    run([&](double s) { return Q(A(2 * kPi * s / 8.0, Z)); }, 8.0);
    run([&](double s) { return Q(A(kPi / 2, Y)) * Q(A(2 * kPi * s / 8.0, Z)); }, 8.0);   // forearm in the north-south vertical plane
    run([&](double s) { return Q(A(kPi / 2, Z)) * Q(A(2 * kPi * s / 8.0, X)); }, 8.0);
    REQUIRE(proc.ready());
    proc.finishStep();
    CHECK(proc.result().mag.bias.isApprox(p.adc.mag.bias, 5e-3));
    CHECK(proc.result().mag.scale.isApprox(p.adc.mag.scale, 2e-2));

    // One full turn about each device axis in 4 s, then still.
    for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d a = Eigen::Vector3d::Unit(axis);
        run([&](double s) { return restOrientation() * Q(A(2 * kPi * std::clamp(s / 4.0, 0.0, 1.0), a)); }, 5.0);
        REQUIRE(proc.ready());
        proc.finishStep();
        CHECK(proc.result().gyro.scale[axis] == Approx(p.adc.gyro.scale[axis]).epsilon(0.01));
    }
    CHECK(proc.step() == CalibrationProcedure::Step::Done);
}

TEST_CASE("guided calibration: movement restarts the still step", "[device][calibration]")
{
    SensorModel model;
    CalibrationProcedure proc;
    // A restless arm (wobbling ±0.3 rad at 0.5 Hz) never completes the still step ...
    FunctionMotion wobble([](double s) { return Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * std::sin(kPi * s), Eigen::Vector3d::UnitY())); });
    for (double t = 0; t < 5.0; t += 0.005) proc.feed(t, model.sample(wobble.at(t), t, {}));
    CHECK_FALSE(proc.ready());
    CHECK(proc.progress() < 0.5);
    // ... nor does a steady spin (a turntable), which no stillness can look like.
    CalibrationProcedure spinning;
    FunctionMotion spin([](double s) { return Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * s, Eigen::Vector3d::UnitY())); });
    for (double t = 0; t < 5.0; t += 0.005) spinning.feed(t, model.sample(spin.at(t), t, {}));
    CHECK_FALSE(spinning.ready());
    // Then holding still completes it.
    for (double t = 5.0; t < 9.0; t += 0.005) proc.feed(t, model.sample(MotionState {}, t, {}));
    CHECK(proc.ready());
}
