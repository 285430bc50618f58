// The block clock's 200 Hz step grid belongs to the host's samples (docs/PLUGIN.md "Timing"): a
// mapped CC sits at the sample of the control step that produced it, on a grid counted from the
// first block after prepare(). A block that finds the idle clock finishing its update (the token
// taken, as when audio resumes after a pause or a slow host calls late) is rendered silent and
// takes no step, but the grid keeps counting its samples: the blocks after it stay on the grid.
#include "Engine/Engine.h"
#include "Live/Session/BlockControl.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/ControlToken.h"
#include "Link/LevelSchedule.h"
#include "Mapping/Mapper.h"
#include "Mapping/MappingSpec.h"
#include <catch2/catch.hpp>
#include "Core/Clock.h"
#include <cmath>
#include <thread>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;

namespace {
constexpr double kFs = 48000.0;
constexpr int kBlock = 256;   // not a multiple of the 240-sample step: a lost block would shift the grid
constexpr int kStep = 240;

/// The host's MIDI for one block: no input; the output collected.
struct Midi final : live::BlockMidi {
    struct Out { int offset; std::uint8_t status, number, value; };
    std::vector<Out> out;
    bool nextInput(Event&) noexcept override { return false; }
    void beginOutput() noexcept override { out.clear(); }
    bool add(const std::uint8_t* data, int size, int offset) noexcept override
    {
        if (size != 3) return true;
        out.push_back(Out {offset, data[0], data[1], data[2]});
        return true;
    }
};

struct Rig {
    live::Instrument instrument;   // the core every clock shares (its loop, stage, step)
    live::ControlLoop& loop = instrument.loop();
    live::ControlToken token;
    link::LevelSchedule motors;
    std::atomic<float> elevation {0.0f}, azimuth {0.0f}, roll {0.0f}, source {static_cast<float>(live::SourceKind::HostAutomation)};
    std::unique_ptr<live::BlockControl> control;
    std::vector<float> left = std::vector<float>(kBlock), right = std::vector<float>(kBlock);
    std::int64_t clock = 0;   ///< host samples since prepare()
    Rig()
    {
        EngineConfig config;
        config.scene = "monitor";
        auto slot = std::make_unique<live::EngineSlot>();
        slot->engine = std::make_unique<Engine>(config);
        slot->sceneName = config.scene;
        loop.replace(std::move(slot));
        control = std::make_unique<live::BlockControl>(instrument, token, live::BlockControl::Cells {&elevation, &azimuth, &roll, &source}, motors);
        token.take();
        control->prepare(kFs);
        token.release();
        control->mapper().replace(mapping::MappingSet::build(mapping::parseMappingDocument(
            R"({"version": 1, "mappings": [{"source": "elevation", "in": [-90, 90], "to": {"midi": "cc", "channel": 2, "cc": 20}}]})", "grid.json")));
    }
    /// One block; its MIDI out at absolute host samples.
    std::vector<Midi::Out> block()
    {
        float* channels[2] {left.data(), right.data()};
        Midi midi;
        control->processBlock(live::AudioBlock {channels, 2, kBlock}, midi, Transport {}, false);
        for (auto& e : midi.out) e.offset += static_cast<int>(clock);
        clock += kBlock;
        return midi.out;
    }
};
} // namespace

TEST_CASE("block clock: a block the idle clock holds the token for keeps the step grid on the host's samples", "[live][block-grid]")
{
    Rig rig;
    for (int b = 0; b < 10; ++b) rig.block();   // the mapping set reaches the control side
    int checked = 0;
    for (int i = 0; i < 30; ++i) {
        if (i == 5 || i == 17) {
            // The idle clock is mid-update when the host's block comes: that block is silent and
            // takes no step (its sound is lost, never rendered twice).
            REQUIRE(rig.token.tryTake());
            const auto during = rig.block();
            CHECK(during.empty());
            for (float x : rig.left) CHECK(x == 0.0f);
            rig.token.release();
        }
        rig.elevation.store(static_cast<float>(-60.0 + 4.0 * i));
        const std::int64_t blockStart = rig.clock;
        const auto events = rig.block();
        const std::int64_t firstStep = (blockStart + kStep - 1) / kStep * kStep;
        INFO("block " << i << " at sample " << blockStart << ": " << events.size() << " events");
        REQUIRE(events.size() == 1);   // the block's first step saw the change
        CHECK(events[0].offset == firstStep);
        CHECK(events[0].status == 0xB1);
        CHECK(int(events[0].value) == int(std::lround((-60.0 + 4.0 * i + 90.0) / 180.0 * 127.0)));
        ++checked;
    }
    CHECK(checked == 30);
}

namespace {
/// Waits until the idle clock may take over (no block for more than kIdleAfterMs). A wait for a
/// condition, not a timed assertion: what follows holds however long it took.
void waitPastIdleThreshold()
{
    const double from = monotonicSeconds();
    while ((monotonicSeconds() - from) * 1e3 <= live::BlockControl::kIdleAfterMs + 5.0) std::this_thread::yield();
}
} // namespace

TEST_CASE("block clock: the idle clock steps after real-time blocks stop, never into a slow offline render", "[live][block-grid]")
{
    Rig rig;
    for (int b = 0; b < 4; ++b) rig.block();
    // The probe: after real-time blocks stop, the idle clock runs the control step.
    waitPastIdleThreshold();
    const std::uint64_t before = rig.control->ticks();
    rig.control->idleTick(0.005);
    CHECK(rig.control->ticks() > before);

    // A host's offline render slower than the threshold between blocks: no idle step between them.
    float* channels[2] {rig.left.data(), rig.right.data()};
    Midi midi;
    rig.control->processBlock(live::AudioBlock {channels, 2, kBlock}, midi, Transport {}, true);
    waitPastIdleThreshold();
    const std::uint64_t offline = rig.control->ticks();
    rig.control->idleTick(0.005);
    CHECK(rig.control->ticks() == offline);
    // A real-time block ends the render: the idle clock may take over again after it.
    rig.block();
    waitPastIdleThreshold();
    const std::uint64_t after = rig.control->ticks();
    rig.control->idleTick(0.005);
    CHECK(rig.control->ticks() > after);
}
