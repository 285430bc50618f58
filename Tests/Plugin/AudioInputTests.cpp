// The plugin's audio input (issue 16), through its own control path (BlockControl, as
// processBlock runs it in a host): the listened-to channels — the main input, or the sidechain
// when it is enabled — reach the engine's audio input before the scene's sound for the same
// samples is rendered; the main input plays through to the output (an effect that listens must
// not mute its track); extra input channels are cleared; nothing allocates or locks.
#include "Common/RealtimeGuard.h"
#include "Engine/Engine.h"
#include "Live/Session/BlockControl.h"
#include "Plugin/HostBlock.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::plugin;
using armadillo::test::RealtimeGuard;

namespace {
/// Records what it hears: per channel the sum of the samples and of sample × index (a
/// checksum that catches wrong channels, order and offsets), and how many samples came.
class EarScene final : public Scene {
public:
    std::string_view name() const override { return "ear"; }
    void prepare(const SceneConfig&) override {}
    bool listensToAudio() const override { return true; }
    void processInput(const float* const* in, int channels, int n) noexcept override
    {
        for (int c = 0; c < std::min(channels, 4); ++c)
            for (int i = 0; i < n; ++i) {
                sum[static_cast<std::size_t>(c)] += in[c][i];
                weighted[static_cast<std::size_t>(c)] += static_cast<double>(in[c][i]) * static_cast<double>(heard + i);
            }
        heard += n;
        lastChannels = channels;
    }
    void control(const ControlInput&, SceneOutput&) override {}
    std::array<double, 4> sum {}, weighted {};
    long heard = 0;
    int lastChannels = 0;
};

struct Rig {
    live::Instrument instrument;   // the core every clock shares (its loop, stage, step)
    live::ControlLoop& loop = instrument.loop();
    live::ControlToken token;
    link::LevelSchedule motors;
    std::atomic<float> elevation {0.0f}, azimuth {0.0f}, roll {0.0f}, source {static_cast<float>(live::SourceKind::HostAutomation)};
    EarScene* ear = nullptr;
    std::unique_ptr<live::BlockControl> control;
    HostBlock host;   // the host's buffers as the block clock takes them
    /// `stems`: the engine's SceneConfig::stems (audio-touch's, built from the VST3's sidechains).
    explicit Rig(std::vector<std::string> stems = {})
    {
        EngineConfig config;
        config.scene = "ear";
        config.sceneConfig.stems = std::move(stems);
        auto scene = std::make_unique<EarScene>();
        ear = scene.get();
        auto slot = std::make_unique<live::EngineSlot>();
        slot->engine = std::make_unique<Engine>(config, std::move(scene));
        slot->sceneName = "ear";
        loop.replace(std::move(slot));
        control = std::make_unique<live::BlockControl>(instrument, token, live::BlockControl::Cells {&elevation, &azimuth, &roll, &source}, motors);
        control->prepare(48000.0);
        host.prepare();
    }
};

float signal(int channel, long i) { return 0.25f * std::sin(0.01f * static_cast<float>(i) * static_cast<float>(channel + 1)) + 0.01f * static_cast<float>(channel); }
} // namespace

TEST_CASE("plugin audio input: the main input is heard and played through; a sidechain is heard instead", "[plugin][audio-in]")
{
    ARMADILLO_REQUIRE_GUARD();
    for (const bool sidechain : {false, true}) {
        for (const int block : {1, 64, 480, 4096}) {
            CAPTURE(sidechain, block);
            Rig rig;
            const int channels = sidechain ? 4 : 2;
            juce::AudioBuffer<float> buffer(channels, block);
            juce::MidiBuffer midi;
            live::BlockControl::Listen listen;
            listen.first = sidechain ? 2 : 0;
            listen.count = 2;
            listen.through = 2;
            std::array<double, 2> expectSum {}, expectWeighted {};
            long at = 0;
            double worstThrough = 0.0, worstExtra = 0.0;
            const long total = 48000;
            RealtimeGuard guard;
            while (at < total) {
                for (int c = 0; c < channels; ++c)
                    for (int i = 0; i < block; ++i) buffer.setSample(c, i, signal(c, at + i));
                for (int c = 0; c < 2; ++c)
                    for (int i = 0; i < block; ++i) {
                        const float x = signal(listen.first + c, at + i);
                        expectSum[static_cast<std::size_t>(c)] += x;
                        expectWeighted[static_cast<std::size_t>(c)] += static_cast<double>(x) * static_cast<double>(at + i);
                    }
                rig.host.process(*rig.control, buffer, midi, nullptr, false, listen);
                for (int c = 0; c < 2; ++c)   // the scene is silent: the output is the main input
                    for (int i = 0; i < block; ++i) worstThrough = std::max(worstThrough, std::fabs(double(buffer.getSample(c, i)) - signal(c, at + i)));
                for (int c = 2; c < channels; ++c)
                    for (int i = 0; i < block; ++i) worstExtra = std::max(worstExtra, std::fabs(double(buffer.getSample(c, i))));
                at += block;
            }
            CHECK(guard.allocations() == 0);
            CHECK(guard.locks() == 0);
            CHECK(guard.throws() == 0);
            CHECK(rig.ear->heard == at);
            CHECK(rig.ear->lastChannels == 2);
            for (std::size_t c = 0; c < 2; ++c) {
                CHECK(rig.ear->sum[c] == Approx(expectSum[c]).epsilon(1e-9));
                CHECK(rig.ear->weighted[c] == Approx(expectWeighted[c]).epsilon(1e-9));
            }
            CHECK(worstThrough < 1e-6);
            CHECK(worstExtra == 0.0);
        }
    }
}

TEST_CASE("plugin audio input: without an input nothing is heard and the output is the scene's alone", "[plugin][audio-in]")
{
    Rig rig;
    juce::AudioBuffer<float> buffer(2, 256);
    juce::MidiBuffer midi;
    for (int c = 0; c < 2; ++c)
        for (int i = 0; i < 256; ++i) buffer.setSample(c, i, 0.5f);   // garbage a host may leave
    rig.host.process(*rig.control, buffer, midi, nullptr, false);
    CHECK(rig.ear->heard == 0);
    CHECK(buffer.getMagnitude(0, 256) == 0.0f);
}

TEST_CASE("plugin audio input: stems (sidechain buses) are heard one mono channel each, then the main input, by an engine built for them", "[plugin][audio-in]")
{
    ARMADILLO_REQUIRE_GUARD();
    // Main input 0–1, a stereo stem bus at 2–3, a mono one at 4 (a host's buffer with the
    // main input and two sidechains enabled).
    live::BlockControl::Listen listen;
    listen.first = 0;
    listen.count = 2;
    listen.through = 2;
    listen.stems[0] = {2, 2};
    listen.stems[1] = {4, 1};
    listen.stemCount = 2;
    const auto stem = [](int k, long i) { return k == 0 ? 0.5f * (signal(2, i) + signal(3, i)) : signal(4, i); };
    for (const int engineStems : {2, 0, 1}) {
        for (const int block : {1, 480, 4096}) {
            CAPTURE(engineStems, block);
            std::vector<std::string> names {"bass", "vocals"};
            names.resize(static_cast<std::size_t>(engineStems));
            Rig rig(names);
            juce::AudioBuffer<float> buffer(5, block);
            juce::MidiBuffer midi;
            std::array<double, 4> expectSum {}, expectWeighted {};
            double worstThrough = 0.0;
            long at = 0;
            RealtimeGuard guard;
            while (at < 24000) {
                for (int c = 0; c < 5; ++c)
                    for (int i = 0; i < block; ++i) buffer.setSample(c, i, signal(c, at + i));
                for (int c = 0; c < 2; ++c)
                    for (int i = 0; i < block; ++i) {
                        // An engine with the stems hears them; one without hears the main input.
                        const double x = engineStems == 2 ? double(stem(c, at + i)) : double(signal(c, at + i));
                        expectSum[static_cast<std::size_t>(c)] += x;
                        expectWeighted[static_cast<std::size_t>(c)] += x * static_cast<double>(at + i);
                        if (engineStems == 2) {   // then the main input
                            const double m = signal(c, at + i);
                            expectSum[static_cast<std::size_t>(c + 2)] += m;
                            expectWeighted[static_cast<std::size_t>(c + 2)] += m * static_cast<double>(at + i);
                        }
                    }
                rig.host.process(*rig.control, buffer, midi, nullptr, false, listen);
                for (int c = 0; c < 2; ++c)
                    for (int i = 0; i < block; ++i) worstThrough = std::max(worstThrough, std::fabs(double(buffer.getSample(c, i)) - signal(c, at + i)));
                at += block;
            }
            CHECK(guard.allocations() == 0);
            CHECK(guard.locks() == 0);
            CHECK(guard.throws() == 0);
            CHECK(worstThrough < 1e-6);   // the main input plays through whatever is heard
            if (engineStems == 1) {
                CHECK(rig.ear->heard == 0);   // built for another layout: nothing until it matches
                continue;
            }
            CHECK(rig.ear->heard == at);
            CHECK(rig.ear->lastChannels == (engineStems == 2 ? 4 : 2));   // the stems, then the main input
            for (std::size_t c = 0; c < (engineStems == 2 ? 4u : 2u); ++c) {
                CAPTURE(c);
                CHECK(rig.ear->sum[c] == Approx(expectSum[c]).epsilon(1e-6));
                CHECK(rig.ear->weighted[c] == Approx(expectWeighted[c]).epsilon(1e-6));
            }
        }
    }
}
