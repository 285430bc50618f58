// procedures::MountCalibration through a scripted presenter: a person holding a strapped sensor
// goes through the poses; the app's way (Next, a full pose frozen until then) and the text
// presenter's way (each pose taken when ready, announced in one line, the roll pose skipped when
// the session ends in it), to the same mount and the same file.
#include "Common/ScratchDir.h"
#include "Core/Types.h"
#include "Procedures/MountCalibration.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using armadillo::procedures::MountCalibration;
using Pose = MountCalibration::Pose;
using Q = Eigen::Quaterniond;
using V = Eigen::Vector3d;

namespace {

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

/// The sensor's samples of a held pose, noisy, in the sensor's axes (strap: sensor → device).
struct Arm {
    Q strap;
    std::mt19937 rng {5};
    double t = 0.0;
    osc::SensorFrameSample sample(const V& up, double noise = 0.08)
    {
        std::normal_distribution<double> n(0.0, noise);
        const V a = strap.conjugate() * (up * kStandardGravity + V(n(rng), n(rng), n(rng)));
        osc::SensorFrameSample s;
        s.t = (t += 0.01);
        for (int i = 0; i < 3; ++i) {
            s.accel[i] = a[i];
            s.gyro[i] = n(rng) * 0.02;
        }
        return s;
    }
    /// A tap of `count` samples of pose `p` (the OSC input's sensor-frame tap).
    std::function<bool(osc::SensorFrameSample&)> tap(Pose p, int count)
    {
        auto left = std::make_shared<int>(count);
        return [this, p, left](osc::SensorFrameSample& s) {
            if (*left <= 0) return false;
            --*left;
            s = sample(upInDevice(p));
            return true;
        };
    }
};

} // namespace

TEST_CASE("MountCalibration: a text presenter's walk — each pose taken when ready, announced, the roll skipped at the end", "[procedures][mount]")
{
    const Q strap = Q(Eigen::AngleAxisd(0.7, V(1, 2, 3).normalized()));
    Arm arm {strap};
    MountCalibration calibration;
    std::vector<std::string> said;
    calibration.setAnnouncer([&](const std::string& line) { said.push_back(line); });
    calibration.begin({}, MountCalibration::Advance::WhenReady);
    REQUIRE(said.size() == 1);
    CHECK(said[0] == std::string("mount calibration pose 1 (") + link::MountCalibration::poseName(Pose::LevelForward) +
                         "): " + link::MountCalibration::instruction(Pose::LevelForward));
    calibration.drain(arm.tap(Pose::LevelForward, 100));
    CHECK(calibration.pose() == Pose::HangingDown);   // taken without a Next
    REQUIRE(said.size() == 2);
    CHECK(said[1].rfind("mount calibration pose 2 (", 0) == 0);
    calibration.drain(arm.tap(Pose::HangingDown, 100));
    CHECK(calibration.pose() == Pose::RolledRight);
    CHECK(said.size() == 3);
    // The session ends in the optional roll pose: skipped, solved, named, written.
    calibration.setDevice("phone-7");
    std::string why;
    REQUIRE(calibration.conclude(why));
    CHECK(calibration.finished());
    CHECK(radToDeg(calibration.result().rotation.angularDistance(strap)) < 3.0);
    CHECK(calibration.result().device == "phone-7");
    const std::string path = (armadillo::test::scratchDir("procedures-mount") / MountCalibration::fileNameForDevice("phone-7")).string();
    calibration.save(path);
    const link::Mount back = link::loadMount(path);
    CHECK(back.rotation.angularDistance(calibration.result().rotation) < 1e-6);

    // With the roll pose held too, the walk completes by itself and says so.
    MountCalibration full;
    said.clear();
    full.setAnnouncer([&](const std::string& line) { said.push_back(line); });
    full.begin("phone-8", MountCalibration::Advance::WhenReady);
    Arm arm2 {strap};
    for (const Pose p : {Pose::LevelForward, Pose::HangingDown, Pose::RolledRight}) full.drain(arm2.tap(p, 100));
    CHECK(full.finished());
    CHECK(said.back() == "mount calibration complete");
    CHECK(radToDeg(full.result().rotation.angularDistance(strap)) < 3.0);

    // A session that ends before two poses: no mount, and why; the pose it stopped at.
    MountCalibration early;
    early.begin({}, MountCalibration::Advance::WhenReady);
    early.drain(arm.tap(Pose::LevelForward, 30));
    CHECK_FALSE(early.conclude(why));
    CHECK_FALSE(why.empty());
    CHECK(early.pose() == Pose::LevelForward);
}

TEST_CASE("MountCalibration: the app's walk — a full pose waits for Next, the same mount", "[procedures][mount]")
{
    const Q strap = Q(Eigen::AngleAxisd(-1.1, V(0, 1, 1).normalized()));
    Arm arm {strap};
    MountCalibration calibration;
    calibration.begin("phone-1");
    std::string why;
    CHECK_FALSE(calibration.next(why));
    CHECK(why.find("No sensor samples yet") != std::string::npos);
    calibration.drain(arm.tap(Pose::LevelForward, 100));
    CHECK(calibration.ready());
    calibration.drain(arm.tap(Pose::HangingDown, 100));   // moving on before Next cannot overwrite it
    CHECK(calibration.pose() == Pose::LevelForward);
    REQUIRE(calibration.next(why));
    CHECK(calibration.stepTitle() == std::string("Pose 2 of 3: ") + link::MountCalibration::poseName(Pose::HangingDown));
    calibration.drain(arm.tap(Pose::HangingDown, 100));
    REQUIRE(calibration.next(why));
    REQUIRE(calibration.canSkip());
    REQUIRE(calibration.skip(why));
    CHECK(calibration.finished());
    CHECK(radToDeg(calibration.result().rotation.angularDistance(strap)) < 3.0);
}
