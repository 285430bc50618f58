// The scene API's MIDI input (Core/Scene.h, Scene::processMidi): every scene but the layered
// keyboard ignores it — the same audio and motors with and without it, sample by sample — and
// handing it over allocates, locks and throws nothing in any scene.
#include "Common/RealtimeGuard.h"
#include "Core/Pose.h"
#include "Engine/Engine.h"
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <string>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;

TEST_CASE("MIDI input: every scene but layered-keyboard ignores it; handing it over allocates nothing", "[engine][midi][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    constexpr int kBlock = 64;
    std::array<MidiNoteEvent, 4> events {};
    for (std::size_t i = 0; i < events.size(); ++i) {
        events[i].offset = static_cast<int>(i) * 16;
        events[i].note = static_cast<std::uint8_t>(60 + 4 * i);
        events[i].velocity = static_cast<std::uint8_t>(i % 2 == 0 ? 100 : 0);
    }
    int listening = 0;
    for (const std::string& name : sceneNames()) {
        EngineConfig config;
        config.scene = name;
        config.sceneConfig.score = "rite-of-spring";
        config.sceneConfig.text = "abc";
        Engine with(config), without(config);
        INFO(name);
        REQUIRE(with.listensToMidi() == (name == "layered-keyboard"));
        listening += with.listensToMidi();
        if (name == "layered-keyboard") continue;   // it does listen (Tests/Follow/LayeredKeyboardTests.cpp)
        std::vector<float> in(kBlock), la(kBlock), ra(kBlock), lb(kBlock), rb(kBlock);
        ArmState arm;
        arm.valid = true;
        long allocations = 0, locks = 0, throws = 0;
        bool same = true;
        for (int b = 0; b < 400; ++b) {
            for (int i = 0; i < kBlock; ++i) in[static_cast<std::size_t>(i)] = static_cast<float>(0.3 * std::sin(0.05 * (b * kBlock + i)));
            const float* chans[1] = {in.data()};
            {
                test::RealtimeGuard guard;
                with.processMidi(events.data(), static_cast<int>(events.size()));
                allocations += guard.allocations() + guard.deallocations();
                locks += guard.locks();
                throws += guard.throws();
            }
            if (with.listensToAudio()) {
                with.processInput(chans, 1, kBlock);
                without.processInput(chans, 1, kBlock);
            }
            std::fill(la.begin(), la.end(), 0.0f);
            std::fill(ra.begin(), ra.end(), 0.0f);
            std::fill(lb.begin(), lb.end(), 0.0f);
            std::fill(rb.begin(), rb.end(), 0.0f);
            with.renderAudio(la.data(), ra.data(), kBlock);
            without.renderAudio(lb.data(), rb.data(), kBlock);
            const double t = b * kBlock / 48000.0;
            arm.t = t;
            arm.features.pose = Pose {40.0 * std::sin(3.0 * t), 30.0 * std::sin(t), 60.0 * std::cos(2.0 * t)};
            arm.q = poseToQuaternion(arm.features.pose);
            const MotorLevels ma = with.control(arm, Transport {}, kBlock / 48000.0);
            const MotorLevels mb = without.control(arm, Transport {}, kBlock / 48000.0);
            same = same && la == lb && ra == rb && ma == mb;
        }
        CHECK(same);
        CHECK(allocations == 0);
        CHECK(locks == 0);
        CHECK(throws == 0);
        CHECK_FALSE(with.failed());
    }
    CHECK(listening == 1);
}
