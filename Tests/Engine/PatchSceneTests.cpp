// The "patch" scene (issue 46): a front end's patch writes the grid's targets into a lock-free
// cell (Core/MotorTargets.h) and the engine's tactile engine and safety stage decide what the
// motors get. The levels below come out of Engine::control, never out of the cell directly.
#include "Core/MotorTargets.h"
#include "Core/Pose.h"
#include "Engine/Engine.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <memory>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;

namespace {
struct PatchRig {
    std::shared_ptr<MotorTargets> cell = std::make_shared<MotorTargets>();
    std::unique_ptr<Engine> engine;
    ArmState arm {};
    double t = 0.0;
    PatchRig()
    {
        EngineConfig config;
        config.scene = "patch";
        config.sceneConfig.motorTargets = cell;
        engine = std::make_unique<Engine>(config);
        arm.valid = true;
        arm.q = poseToQuaternion({10.0, 0.0, 0.0});
    }
    MotorLevels step()
    {
        t += 0.005;
        arm.t = t;
        return engine->control(arm, Transport {}, 0.005);
    }
};
} // namespace

TEST_CASE("patch scene: made by name, not in the plugin's choice list", "[engine][patch]")
{
    CHECK(createScene("patch")->name() == "patch");
    CHECK(std::find(hostedSceneNames().begin(), hostedSceneNames().end(), "patch") != hostedSceneNames().end());
    CHECK(std::find(sceneNames().begin(), sceneNames().end(), "patch") == sceneNames().end());
}

TEST_CASE("patch scene: the cell's targets reach the motors through the safety stage", "[engine][patch]")
{
    PatchRig rig;
    MotorLevels levels {};
    for (int i = 0; i < 4; ++i) levels = rig.step();
    for (int m = 0; m < kGridMotors; ++m) CHECK(levels[static_cast<std::size_t>(m)] == 0);   // nothing asked yet

    rig.cell->set({15, 0, 0, 0, 8, 0, 0, 0, 3});
    int firstOn = -1;
    bool sawAbove = false;
    for (int i = 0; i < 200; ++i) {   // one second at 200 Hz
        levels = rig.step();
        if (firstOn < 0 && levels[0] > 0) firstOn = i;
        if (levels[0] > 5) sawAbove = true;
        for (int m : {1, 2, 3, 5, 6, 7}) REQUIRE(levels[static_cast<std::size_t>(m)] == 0);
    }
    CHECK(firstOn >= 0);
    CHECK(firstOn < 10);   // within 50 ms
    CHECK(sawAbove);       // 15 asked: above the rating for a while…
    INFO("after 1 s: m1 " << int(levels[0]) << " m5 " << int(levels[4]) << " m9 " << int(levels[8]));
    CHECK(levels[0] > 0);
    CHECK(levels[4] > 0);
    CHECK(levels[8] > 0);
    CHECK(levels[0] >= levels[4]);
    CHECK(levels[4] >= levels[8]);
    CHECK(levels[0] <= 5);   // …and held at the rating after 300 ms by the safety stage

    rig.cell->set({});
    for (int i = 0; i < 40; ++i) levels = rig.step();
    for (int m = 0; m < kGridMotors; ++m) CHECK(levels[static_cast<std::size_t>(m)] == 0);
}

TEST_CASE("patch scene: out-of-range targets are clamped; panic silences them", "[engine][patch]")
{
    PatchRig rig;
    rig.cell->set({-3, 99, 0, 0, 0, 0, 0, 0, 0});
    MotorLevels levels {};
    for (int i = 0; i < 20; ++i) levels = rig.step();
    CHECK(levels[0] == 0);
    CHECK(levels[1] > 0);
    CHECK(levels[1] <= 15);
    rig.engine->panic();
    for (int i = 0; i < 5; ++i) levels = rig.step();
    for (int m = 0; m < kGridMotors; ++m) CHECK(levels[static_cast<std::size_t>(m)] == 0);
}
