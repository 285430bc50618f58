// Cue changes are allocation-free: CuePlayer::request / next / control / processInput /
// renderAudio inside the real-time guard (RealtimeLoopTests.cpp is this executable's guard TU
// and proves first that the guard sees what it counts).
#include "Common/RealtimeGuard.h"
#include "Core/Pose.h"
#include "Live/Stage/SetList.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::live;
using namespace armadillo::test;

TEST_CASE("set list: stepping through cues allocates, frees, locks and throws nothing", "[realtime][setlist]")
{
    ARMADILLO_REQUIRE_GUARD();
    const SetList list = parseSetList(R"({"armadillo_setlist": 1, "cues": [
        {"scene": "theremin"}, {"scene": "cymbal"}, {"scene": "layered-keyboard"}, {"scene": "sound-design"},
        {"scene": "audio-touch"}, {"scene": "panel"}]})", "rt.json");
    CuePlayer player(list, SceneConfig {});
    std::vector<float> l(512), r(512), in(512);
    const float* input[1] = {in.data()};
    ArmState arm;
    arm.valid = true;
    RealtimeGuard guard;
    double t = 0.0;
    for (int i = 0; i < 3000; ++i) {
        if (i % 97 == 0) player.next();
        if (i % 389 == 0) player.previous();
        if (i % 733 == 0) player.request(i % 6);
        const int n = 64 + (i % 7) * 64;
        for (int k = 0; k < n; ++k) in[static_cast<std::size_t>(k)] = static_cast<float>(0.2 * std::sin(2.0 * 3.14159265358979 * 440.0 * (t + k / 48000.0)));
        arm.t = t;
        arm.features.pose = Pose {40.0 * std::sin(t), 20.0 * std::sin(0.7 * t), 30.0 * std::sin(1.3 * t)};
        arm.q = poseToQuaternion(arm.features.pose);
        (void) player.control(arm, Transport {}, n / 48000.0);
        player.processInput(input, 1, n);
        player.renderAudio(l.data(), r.data(), n);
        t += n / 48000.0;
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(player.changes() > 20u);
}

TEST_CASE("set list with two arms: cue changes and both arms' control steps allocate, free, lock and throw nothing", "[realtime][setlist][twoarms]")
{
    ARMADILLO_REQUIRE_GUARD();
    const SetList list = parseSetList(R"({"armadillo_setlist": 1, "cues": [
        {"scene": "theremin-duo"}, {"scene": "theremin"}, {"scene": "cymbal"}, {"scene": "theremin-duo", "parameters": {"theremin-duo.base": 330}}]})",
                                      "rt-two.json");
    CuePlayer player(list, SceneConfig {}, kGridMotors, true);
    REQUIRE(player.twoArms());
    std::vector<float> l(512), r(512);
    ArmState arm, left;
    arm.valid = left.valid = true;
    double leftMotors = 0.0;
    RealtimeGuard guard;
    double t = 0.0;
    for (int i = 0; i < 2000; ++i) {
        if (i % 97 == 0) player.next();
        if (i % 389 == 0) player.request(0);
        const int n = 64 + (i % 5) * 64;
        arm.t = left.t = t;
        arm.features.pose = Pose {40.0 * std::sin(t), 20.0 * std::sin(0.7 * t), 30.0 * std::sin(1.3 * t)};
        arm.q = poseToQuaternion(arm.features.pose);
        left.features.pose = Pose {30.0 * std::sin(0.9 * t), 200.0, 80.0 * std::sin(0.5 * t)};
        left.q = poseToQuaternion(left.features.pose);
        (void) player.control(arm, left, Transport {}, n / 48000.0);
        for (const auto v : player.leftLevels()) leftMotors += v;
        player.renderAudio(l.data(), r.data(), n);
        t += n / 48000.0;
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(player.changes() > 10u);
    CHECK(leftMotors > 0.0);   // the left arm's motors ran (the duo shows its brightness on them)
}
