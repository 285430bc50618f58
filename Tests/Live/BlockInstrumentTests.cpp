// The instrument on the block clock, assembled once (Live/Session/BlockInstrument.h, issue 45): built with
// nothing but the host's cells and an engine, it runs the control step on its own idle clock with
// the simulated arm as source, steers to a pose, applies a panic through its stage, and stops —
// the clock and every part — once, however often it is asked.
#include "Engine/Engine.h"
#include "Live/Session/BlockInstrument.h"
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <thread>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;

namespace {
struct Cells {
    std::atomic<float> elevation {0.0f}, azimuth {0.0f}, roll {0.0f}, source {static_cast<float>(live::SourceKind::Simulator)};
    live::BlockControl::Cells cells() { return {&elevation, &azimuth, &roll, &source}; }
};

void installEngine(live::BlockInstrument& instrument, const std::string& scene)
{
    EngineConfig config;
    config.scene = scene;
    config.sceneConfig.sampleRate = 48000.0;
    auto slot = std::make_unique<live::EngineSlot>();
    slot->engine = std::make_unique<Engine>(config);
    slot->sceneName = config.scene;
    instrument.token().take();
    instrument.loop().replace(std::move(slot));
    instrument.control().prepare(config.sceneConfig.sampleRate);
    instrument.token().release();
}

/// Polls `done` until it holds or `seconds` of wall time pass (no fixed sleep decides a result).
template <typename F>
bool within(double seconds, F done)
{
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return done();
}
} // namespace

TEST_CASE("block instrument: its idle clock runs the step from the simulated arm, its stage panics, stop() ends it once",
          "[live][instrument]")
{
    Cells cells;
    live::SceneParameterTable table;
    live::BlockInstrument instrument(live::BlockInstrument::Host {cells.cells(), &table, [] { return 1; }});
    installEngine(instrument, "theremin");
    instrument.rig().setSimulatorWandering(false);
    Pose target;
    target.elevationDeg = 40.0;
    target.azimuthDeg = 20.0;
    instrument.rig().steerSimulator(target);
    REQUIRE(instrument.control().latestFrame().serial == 0);   // nothing runs before start()
    instrument.start();

    // The step runs (frames count up) and follows the steered arm.
    REQUIRE(within(5.0, [&] {
        const auto f = instrument.control().latestFrame();
        return f.valid && std::abs(f.pose[0] - target.elevationDeg) < 3.0;
    }));
    CHECK(instrument.sourceSamples(live::SourceKind::Simulator) > 0);
    CHECK(instrument.control().source() == live::SourceKind::Simulator);

    // A panic through the stage (the one switch) silences every motor at a following step.
    instrument.stage().apply(StageCommand {StageCommand::Kind::Panic});
    REQUIRE(within(2.0, [&] { return instrument.stage().panicked(); }));
    const auto afterPanic = instrument.control().latestFrame().serial;
    REQUIRE(within(2.0, [&] { return instrument.control().latestFrame().serial > afterPanic + 5; }));
    const auto frame = instrument.control().latestFrame();
    for (int m = 0; m < frame.motorCount; ++m) CHECK(frame.motors[static_cast<std::size_t>(m)] == 0);

    // stop(): no step after it, and a second stop (the destructor's) is harmless.
    instrument.stop();
    const auto last = instrument.control().latestFrame().serial;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));   // 10 idle periods: none may step
    CHECK(instrument.control().latestFrame().serial == last);
    instrument.stop();
    instrument.start();   // not after stop(): the instrument stays stopped
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(instrument.control().latestFrame().serial == last);
}
