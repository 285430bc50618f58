// The plugin's MIDI input notes reach the scene (thesis §5.2: the layered keyboard listens to the
// MIDI input when the instrument has it), through BlockControl::processBlock as a host runs it:
// the layered keyboard captures the exact pitches sent as MIDI (A2, which the audio analysis
// cannot name, included), alone or as a set list's cue; the cue-step notes are not passed on;
// other scenes play the same with and without the notes; nothing allocates, locks or throws.
#include "Common/RealtimeGuard.h"
#include "Engine/Engine.h"
#include "Live/Session/BlockControl.h"
#include "Plugin/HostBlock.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::plugin;
using armadillo::test::RealtimeGuard;

namespace {
constexpr double kFs = 48000.0;
const int kPhrase[4] = {45, 64, 67, 72};   // A2 E4 G4 C5, one every 0.5 s from 0.2 s, 0.45 s long

/// The piano under the keys: each note a decaying sine at its equal-tempered pitch (A4 = 440 Hz).
float piano(long i)
{
    const double t = static_cast<double>(i) / kFs;
    double x = 0.0;
    for (int k = 0; k < 4; ++k) {
        const double u = t - (0.2 + 0.5 * k);
        if (u < 0.0 || u > 0.45) continue;
        const double f = 440.0 * std::pow(2.0, (kPhrase[k] - 69) / 12.0);
        x += 0.25 * std::exp(-3.0 * u) * std::sin(2.0 * M_PI * f * u);
    }
    return static_cast<float>(x);
}

struct Rig {
    live::Instrument instrument;   // the core every clock shares (its loop, stage, step)
    live::ControlLoop& loop = instrument.loop();
    live::ControlToken token;
    link::LevelSchedule motors;
    live::Stage& stage = instrument.stage();
    std::atomic<float> elevation {30.0f}, azimuth {10.0f}, roll {0.0f}, source {static_cast<float>(live::SourceKind::HostAutomation)};
    std::unique_ptr<live::BlockControl> control;
    HostBlock host;   // the host's buffers as the block clock takes them
    Rig(const std::string& scene, bool setList)
    {
        EngineConfig config;
        config.scene = setList ? "monitor" : scene;
        auto slot = std::make_unique<live::EngineSlot>();
        slot->engine = std::make_unique<Engine>(config);
        slot->sceneName = config.scene;
        loop.replace(std::move(slot));
        if (setList) {
            live::SetList list;
            list.source = "show.json";
            list.cues.push_back(live::Cue {"Keys", scene, {}, {}, {}, {}, {}, 1});
            SceneConfig base;
            base.sampleRate = kFs;
            stage.replace(std::make_unique<live::CuePlayer>(list, base));
        }
        control = std::make_unique<live::BlockControl>(instrument, token, live::BlockControl::Cells {&elevation, &azimuth, &roll, &source}, motors);
        control->prepare(kFs);
        host.prepare();
    }
};

struct Played {
    std::vector<int> captured;         ///< the layered keyboard's "captured-note" gestures, in order
    std::vector<float> out;            ///< left output
    std::uint64_t allocations = 0, locks = 0, throws = 0;
};

/// 4 s of blocks: the piano on the input, and (with `notes`) its MIDI notes at their samples,
/// plus a cue-step note (Stage::kNextNote) on and off at 0.1 s, as a foot switch would send it.
Played play(const std::string& scene, bool setList, bool notes, int block)
{
    Rig rig(scene, setList);
    struct Ev { long at; int note; int velocity; };
    std::vector<Ev> events;
    if (notes) {
        events.push_back({static_cast<long>(0.1 * kFs), live::Stage::kNextNote, 100});
        events.push_back({static_cast<long>(0.15 * kFs), live::Stage::kNextNote, 0});
        for (int k = 0; k < 4; ++k) {
            events.push_back({static_cast<long>((0.2 + 0.5 * k) * kFs), kPhrase[k], 90});
            events.push_back({static_cast<long>((0.65 + 0.5 * k) * kFs), kPhrase[k], 0});
        }
    }
    juce::AudioBuffer<float> buffer(2, block);
    juce::MidiBuffer midi;
    midi.ensureSize(4096);
    live::BlockControl::Listen listen;
    listen.count = 2;
    Played p;
    std::size_t next = 0;
    for (long at = 0; at < static_cast<long>(4.0 * kFs); at += block) {
        midi.clear();
        for (; next < events.size() && events[next].at < at + block; ++next) {
            const auto m = events[next].velocity > 0 ? juce::MidiMessage::noteOn(1, events[next].note, static_cast<juce::uint8>(events[next].velocity))
                                                     : juce::MidiMessage::noteOff(1, events[next].note);
            midi.addEvent(m, static_cast<int>(events[next].at - at));
        }
        for (int c = 0; c < 2; ++c)
            for (int i = 0; i < block; ++i) buffer.setSample(c, i, piano(at + i));
        {
            RealtimeGuard guard;
            rig.host.process(*rig.control, buffer, midi, nullptr, false, listen);
            p.allocations += guard.allocations() + guard.deallocations();
            p.locks += guard.locks();
            p.throws += guard.throws();
        }
        p.out.insert(p.out.end(), buffer.getReadPointer(0), buffer.getReadPointer(0) + block);
        GestureEvent g;
        while (rig.control->popGesture(g))
            if (std::string_view(g.name) == "captured-note") p.captured.push_back(static_cast<int>(g.value));
    }
    CHECK(rig.control->notesInDropped() == 0u);
    if (setList) CHECK(rig.stage.newest()->current() == 0);   // the cue note stepped nothing past the only cue
    return p;
}
} // namespace

TEST_CASE("plugin MIDI input: the layered keyboard captures the notes sent as MIDI, alone or as a cue; nothing allocates", "[plugin][midi-in]")
{
    ARMADILLO_REQUIRE_GUARD();
    {   // the probe: an allocation on this thread is seen
        RealtimeGuard guard;
        auto probe = std::make_unique<std::vector<double>>(16);
        CHECK(guard.allocations() >= 1);
    }
    const std::vector<int> exact(std::begin(kPhrase), std::end(kPhrase));
    // The audio alone cannot name A2 (the analysis covers C3..C7): without MIDI the capture differs.
    CHECK(play("layered-keyboard", false, false, 480).captured != exact);
    for (const bool setList : {false, true})
        for (const int block : {64, 480, 4096}) {
            CAPTURE(setList, block);
            const Played p = play("layered-keyboard", setList, true, block);
            CHECK(p.captured == exact);   // exact pitches; the cue note 0 is not among them
            CHECK(p.allocations == 0u);
            CHECK(p.locks == 0u);
            CHECK(p.throws == 0u);
        }
}

TEST_CASE("plugin MIDI input: scenes without MIDI input play the same with and without the notes", "[plugin][midi-in]")
{
    for (const char* scene : {"theremin", "audio-touch"}) {
        CAPTURE(scene);
        const Played with = play(scene, false, true, 480), without = play(scene, false, false, 480);
        CHECK(with.out == without.out);
        CHECK(with.captured.empty());
    }
}
