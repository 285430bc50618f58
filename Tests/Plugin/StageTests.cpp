// On stage in the plugin (issue 28, docs/STAGE.md): a set list of four cues stepped by MIDI
// program change through processBlock — no discontinuity above −60 dBFS at the switches beyond
// the signal's own, no allocation, lock or throw on the audio thread; panic by CC 120 silences
// the audio and every motor within the block and sends CC 120 / CC 123 on all 16 channels and
// the note-off of the mapping's sounding note (none sent again until resume); the notes that step
// cues; the set list kept in the state, a damaged one refused with a message and nothing else lost.
// Part of tests_plugin_ui (it links the processor); no window is opened here.
#include <catch2/catch.hpp>
#include "Common/RealtimeGuard.h"
#include "Mapping/MappingSpec.h"
#include "Osc/OscIo.h"
#include "Plugin/PluginProcessor.h"
#include <cmath>
#include <cstdio>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;
using namespace armadillo::plugin;

namespace {
constexpr double kFs = 48000.0;
constexpr int kBlock = 480;   // 10 ms

const char* kFourCues = R"({"armadillo_setlist": 1,
 "cues": [
  {"name": "Intro", "scene": "theremin"},
  {"name": "Gestures", "scene": "sound-design"},
  {"name": "Wide", "scene": "theremin", "parameters": {"theremin.range": 24, "theremin.scale": "minor pentatonic"}},
  {"name": "Panel", "scene": "panel"}
 ]})";

/// The processor under host automation (deterministic: no simulator, no device), prepared.
struct Rig {
    ArmadilloProcessor processor;
    juce::AudioBuffer<float> buffer {2, kBlock};
    juce::MidiBuffer midi;
    std::atomic<float>* elevation = processor.parameters().getRawParameterValue(ParamIds::elevation);
    std::atomic<float>* azimuth = processor.parameters().getRawParameterValue(ParamIds::azimuth);
    std::atomic<float>* roll = processor.parameters().getRawParameterValue(ParamIds::roll);
    double t = 0.0;
    Rig()
    {
        auto* source = processor.parameters().getParameter(ParamIds::source);
        source->setValueNotifyingHost(source->convertTo0to1(static_cast<float>(SourceKind::HostAutomation)));
        processor.prepareToPlay(kFs, kBlock);
    }
    /// One block; `in` (when given) at sample `offset`. The arm sways as a host's automation
    /// would move it (the parameter cells the control step reads; a store, no allocation).
    void run(const juce::MidiMessage* in = nullptr, int offset = 0)
    {
        elevation->store(static_cast<float>(-20.0 + 30.0 * std::sin(0.7 * t)));
        azimuth->store(static_cast<float>(45.0 + 10.0 * std::sin(0.3 * t)));
        roll->store(static_cast<float>(40.0 * std::sin(2.0 * t)));
        buffer.clear();
        midi.clear();
        if (in != nullptr) midi.addEvent(*in, offset);
        processor.processBlock(buffer, midi);
        t += kBlock / kFs;
    }
    /// One block with the arm held at this pose (as a host's automation would set it).
    void runAt(double el, double rollDeg = 0.0)
    {
        elevation->store(static_cast<float>(el));
        azimuth->store(45.0f);
        roll->store(static_cast<float>(rollDeg));
        buffer.clear();
        midi.clear();
        processor.processBlock(buffer, midi);
        t += kBlock / kFs;
    }
};

double maxStep(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double m = 0.0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < std::min(to, x.size()); ++i)
        m = std::max(m, std::fabs(static_cast<double>(x[i]) - static_cast<double>(x[i - 1])));
    return m;
}

/// As Tests/Live/SetListTests.cpp: the largest step within the switch's fade (plus a block)
/// above the largest step in the 200 ms before it and the 200 ms after the fade.
double switchExcess(const std::vector<float>& x, std::size_t s)
{
    const auto fade = static_cast<std::size_t>(live::CuePlayer::kFadeSeconds * kFs) + kBlock;
    const double around = std::max(maxStep(x, s - 9600, s), maxStep(x, s + fade, s + fade + 9600));
    return std::max(0.0, maxStep(x, s, s + fade) - around);
}

bool hasEvent(const juce::MidiBuffer& midi, int status, int data1, int* offset = nullptr)
{
    for (const auto e : midi)
        if (e.numBytes >= 2 && e.data[0] == status && e.data[1] == data1) {
            if (offset != nullptr) *offset = e.samplePosition;
            return true;
        }
    return false;
}

bool anyMotorOn(const live::ArmFrame& f)
{
    for (int i = 0; i < f.motorCount; ++i)
        if (f.motors[static_cast<std::size_t>(i)] > 0) return true;
    return false;
}
} // namespace

TEST_CASE("stage: four cues stepped by MIDI program change switch click-free, allocation-free", "[plugin][stage]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the guard sees an allocation before its zero is trusted
        auto p = std::make_unique<double>(1.0);
        CHECK(probe.allocations() >= 1);
    }
    Rig rig;
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    for (int i = 0; i < 20; ++i) rig.run();   // the set list takes over at the first block
    REQUIRE(rig.processor.stageInfo().setList);
    CHECK(rig.processor.stageInfo().cueCount == 4);
    CHECK(rig.processor.stageInfo().cue == 0);

    // 5 s; program change 1, 2, 3, 0 at 1, 2, 3, 4 s (sample 100 of the block: it acts at the
    // block's start, documented).
    const int blocks = static_cast<int>(5.0 * kFs) / kBlock;
    std::vector<float> out;
    out.reserve(static_cast<std::size_t>(blocks * kBlock));
    const int programs[4] {1, 2, 3, 0};
    std::vector<juce::MidiMessage> changes;
    for (int p : programs) changes.push_back(juce::MidiMessage::programChange(1, p));
    std::vector<int> cueAt(static_cast<std::size_t>(blocks), -1);
    RealtimeGuard guard;
    for (int b = 0; b < blocks; ++b) {
        const int second = b * kBlock / static_cast<int>(kFs);
        const bool change = b > 0 && b * kBlock % static_cast<int>(kFs) == 0 && second >= 1 && second <= 4;
        rig.run(change ? &changes[static_cast<std::size_t>(second - 1)] : nullptr, 100);
        const float* l = rig.buffer.getReadPointer(0);
        out.insert(out.end(), l, l + kBlock);   // reserved: no allocation
    }
    const auto allocations = guard.allocations(), locks = guard.locks(), throws = guard.throws();
    CHECK(allocations == 0);
    CHECK(locks == 0);
    CHECK(throws == 0);
    CHECK(rig.processor.stageInfo().cue == 0);   // the last change went back to cue 0

    const double minus60 = std::pow(10.0, -60.0 / 20.0);
    for (int s = 1; s <= 4; ++s) {
        const double excess = switchExcess(out, static_cast<std::size_t>(s * kFs));
        std::printf("plugin set list: program change %d at %d s: largest step above its neighbourhood %.2e (%.1f dBFS)\n",
                    programs[s - 1], s, excess, 20.0 * std::log10(std::max(excess, 1e-12)));
        CHECK(excess <= minus60);
    }
    // The cues sound (a silent output would pass the step test vacuously).
    CHECK(maxStep(out, 24000, 48000) > 1e-3);
    CHECK(maxStep(out, static_cast<std::size_t>(2.2 * kFs), static_cast<std::size_t>(2.9 * kFs)) > 1e-3);
    // A hard cut between two points of this very output, 0.5 s apart, would have been caught.
    std::vector<float> cut(out.begin(), out.begin() + 96000);
    cut.insert(cut.end(), out.begin() + 96000 + 24000 + 137, out.end());
    CHECK(switchExcess(cut, 96000) > minus60);
}

TEST_CASE("stage: CC 120 panics within the block: audio, motors, notes; CC 119 resumes", "[plugin][stage][panic]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    Rig rig;
    // A mapping that holds a note: azimuth 0–90° plays note 60 on channel 4 (the arm sways 35–55°).
    const char* json = R"({"version": 1, "name": "held note", "mappings": [
        {"source": "azimuth", "to": {"midi": "notes", "channel": 4, "velocity": 100, "zones": [[0, 90, 60], [90, 360, 62]]}}]})";
    REQUIRE(rig.processor.mapping()->setDocument(mapping::parseMappingDocument(json, "held.json"), "held") == "");
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    bool noteOn = false, motorsOn = false;
    float sound = 0.0f;
    for (int i = 0; i < 100; ++i) {
        rig.run();
        noteOn = noteOn || hasEvent(rig.midi, 0x93, 60);
        motorsOn = motorsOn || anyMotorOn(rig.processor.latestFrame());
        sound = std::max(sound, rig.buffer.getMagnitude(0, 0, kBlock));
    }
    REQUIRE(noteOn);
    REQUIRE(motorsOn);      // the theremin's cue drives the motors …
    REQUIRE(sound > 0.01f); // … and sounds

    const auto panic = juce::MidiMessage::allSoundOff(1);   // CC 120 on channel 1
    RealtimeGuard guard;
    rig.run(&panic, 200);
    const auto allocations = guard.allocations();
    CHECK(allocations == 0);
    // The audio: faded in 1 ms (48 samples) from the block's start, then exactly 0.
    const float* l = rig.buffer.getReadPointer(0);
    const float* r = rig.buffer.getReadPointer(1);
    float tail = 0.0f;
    for (int i = 48; i < kBlock; ++i) tail = std::max({tail, std::fabs(l[i]), std::fabs(r[i])});
    CHECK(tail == 0.0f);
    // Every motor off from the block's first control step: what went to the link's schedule.
    CHECK_FALSE(anyMotorOn(rig.processor.latestFrame()));
    // The MIDI out: the held note ended, CC 120 and CC 123 on all 16 channels.
    CHECK((hasEvent(rig.midi, 0x83, 60) || hasEvent(rig.midi, 0x93, 60)));
    for (int ch = 0; ch < 16; ++ch) {
        INFO("channel " << ch + 1);
        CHECK(hasEvent(rig.midi, 0xB0 | ch, 120));
        CHECK(hasEvent(rig.midi, 0xB0 | ch, 123));
    }
    CHECK(rig.processor.panicked());
    CHECK(rig.processor.panics() == 1);
    // Still silent, still off, no note sent again while in panic (a cue change does not resume).
    const auto next = juce::MidiMessage::programChange(1, 2);
    bool resent = false, on = false;
    float after = 0.0f;
    for (int i = 0; i < 100; ++i) {
        rig.run(i == 10 ? &next : nullptr);
        resent = resent || hasEvent(rig.midi, 0x93, 60);
        on = on || anyMotorOn(rig.processor.latestFrame());
        after = std::max(after, rig.buffer.getMagnitude(0, 0, kBlock));
    }
    CHECK_FALSE(resent);
    CHECK_FALSE(on);
    CHECK(after == 0.0f);
    CHECK(rig.processor.stageInfo().cue == 2);

    // CC 119 ≥ 64 resumes: the current cue sounds again, the note is sent again.
    const auto resume = juce::MidiMessage::controllerEvent(1, 119, 127);
    rig.run(&resume);
    bool again = hasEvent(rig.midi, 0x93, 60);
    float back = 0.0f;
    for (int i = 0; i < 50; ++i) {
        rig.run();
        again = again || hasEvent(rig.midi, 0x93, 60);
        back = std::max(back, rig.buffer.getMagnitude(0, 0, kBlock));
    }
    CHECK_FALSE(rig.processor.panicked());
    CHECK(again);
    CHECK(back > 0.01f);
}

TEST_CASE("stage: a mapping's \"stage\" destinations step the set list and panic as the arm crosses them", "[plugin][stage][mapping]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the guard sees an allocation before its zero is trusted
        auto p = std::make_unique<double>(1.0);
        CHECK(probe.allocations() >= 1);
    }
    Rig rig;
    // Raising the forearm past 30° = next cue; hanging it below −60° = panic; rolling past 60° = resume.
    const char* json = R"({"version": 1, "name": "stage by arm", "mappings": [
        {"source": "elevation", "threshold": 30, "to": {"stage": "next"}},
        {"source": "elevation", "zones": [[-90, -60, 1]], "to": {"stage": "panic"}},
        {"source": "roll", "zones": [[60, 180, 1]], "to": {"stage": "resume"}}]})";
    REQUIRE(rig.processor.mapping()->setDocument(mapping::parseMappingDocument(json, "stage.json"), "stage") == "");
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    for (int i = 0; i < 30; ++i) rig.runAt(0.0);
    REQUIRE(rig.processor.stageInfo().setList);
    REQUIRE(rig.processor.stageInfo().cue == 0);

    // Only the blocks are guarded (stageInfo() is the message thread's and builds strings).
    std::uint64_t allocations = 0, locks = 0, throws = 0;
    const auto block = [&](double el, double rollDeg) {
        RealtimeGuard guard;
        rig.runAt(el, rollDeg);
        allocations += guard.allocations();
        locks += guard.locks();
        throws += guard.throws();
    };
    int cueRaised = -1, cueHeld = -1, cueTwice = -1;
    for (int i = 0; i < 30; ++i) block(45.0, 0.0);   // across the threshold: one step
    cueRaised = rig.processor.stageInfo().cue;
    for (int i = 0; i < 100; ++i) block(50.0 + 5.0 * std::sin(i * 0.3), 0.0);   // held (1 s): no further step
    cueHeld = rig.processor.stageInfo().cue;
    for (int i = 0; i < 30; ++i) block(0.0, 0.0);
    for (int i = 0; i < 30; ++i) block(45.0, 0.0);   // a second crossing: one more
    cueTwice = rig.processor.stageInfo().cue;
    float before = 0.0f;
    for (int i = 0; i < 30; ++i) {   // cue 2 (the theremin) sounds
        block(0.0, 0.0);
        before = std::max(before, rig.buffer.getMagnitude(0, 0, kBlock));
    }
    bool panicked = false;
    float tail = 0.0f;
    for (int i = 0; i < 60; ++i) {   // the forearm hangs: panic from the next block on
        block(-80.0, 0.0);
        panicked = panicked || rig.processor.panicked();
        if (i >= 20) tail = std::max(tail, rig.buffer.getMagnitude(0, 0, kBlock));   // (the fusion reaches −60° well within 20 blocks)
    }
    float silentMax = 0.0f;
    for (int i = 0; i < 30; ++i) {
        block(0.0, 0.0);   // raised again: still silent until resume
        silentMax = std::max(silentMax, rig.buffer.getMagnitude(0, 0, kBlock));
    }
    const bool stillPanicked = rig.processor.panicked();
    float back = 0.0f;
    for (int i = 0; i < 60; ++i) {   // rolled past 60°: resume
        block(0.0, 90.0);
        back = std::max(back, rig.buffer.getMagnitude(0, 0, kBlock));
    }
    std::printf("plugin stage mapping: cue after raising %d, after holding 1 s %d, after a second raise %d; "
                "panicked %d, in panic peak %.3g, after resume peak %.3g; %llu stage commands; %llu allocations, %llu locks, %llu throws\n",
                cueRaised, cueHeld, cueTwice, panicked ? 1 : 0, static_cast<double>(silentMax), static_cast<double>(back),
                static_cast<unsigned long long>(rig.processor.mappedStageCommands()),
                static_cast<unsigned long long>(allocations), static_cast<unsigned long long>(locks), static_cast<unsigned long long>(throws));
    CHECK(cueRaised == 1);
    CHECK(cueHeld == 1);
    CHECK(cueTwice == 2);
    CHECK(before > 0.01f);
    CHECK(panicked);
    CHECK(tail == 0.0f);
    CHECK(stillPanicked);
    CHECK(silentMax == 0.0f);
    CHECK_FALSE(rig.processor.panicked());
    CHECK(back > 0.01f);
    CHECK(rig.processor.panics() == 1);
    CHECK(rig.processor.mappedStageCommands() == 4);   // next, next, panic, resume
    CHECK(allocations == 0);
    CHECK(locks == 0);
    CHECK(throws == 0);
}

TEST_CASE("stage: without a set list CC 120 still panics the scene; notes step cues; settable notes", "[plugin][stage]")
{
    Rig rig;
    for (int i = 0; i < 30; ++i) rig.run();
    const auto panic = juce::MidiMessage::allSoundOff(9);
    rig.run(&panic);
    CHECK(rig.processor.panicked());
    for (int i = 0; i < 5; ++i) rig.run();
    CHECK(rig.buffer.getMagnitude(0, 0, kBlock) == 0.0f);
    CHECK_FALSE(anyMotorOn(rig.processor.latestFrame()));
    rig.processor.resume();

    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    const auto nextNote = juce::MidiMessage::noteOn(16, live::Stage::kNextNote, 1.0f);
    const auto prevNote = juce::MidiMessage::noteOn(16, live::Stage::kPrevNote, 1.0f);
    const auto release = juce::MidiMessage::noteOff(16, live::Stage::kNextNote);
    rig.run(&nextNote);
    rig.run(&release);   // a note-off steps nothing
    rig.run(&nextNote);
    CHECK(rig.processor.stageInfo().cue == 2);
    rig.run(&prevNote);
    CHECK(rig.processor.stageInfo().cue == 1);
    const auto far = juce::MidiMessage::programChange(1, 99);   // past the end: the last cue
    rig.run(&far);
    CHECK(rig.processor.stageInfo().cue == 3);
    // The notes are a setting (−1: off).
    rig.processor.settings().setProperty(SettingIds::cueNextNote, 36, nullptr);
    rig.processor.settings().setProperty(SettingIds::cuePrevNote, -1, nullptr);
    rig.run(&prevNote);
    CHECK(rig.processor.stageInfo().cue == 3);
    const auto c1 = juce::MidiMessage::noteOn(1, 36, 0.5f);
    rig.run(&c1);
    CHECK(rig.processor.stageInfo().cue == 3);   // already the last
    const auto first = juce::MidiMessage::programChange(1, 0);
    rig.run(&first);
    rig.run(&c1);
    CHECK(rig.processor.stageInfo().cue == 1);
}

TEST_CASE("stage: the set list is kept in the state; a damaged one is refused with a message, nothing else lost", "[plugin][stage][state]")
{
    juce::MemoryBlock state;
    {
        Rig rig;
        REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
        rig.processor.settings().setProperty(SettingIds::midiChannel, 7, nullptr);
        rig.processor.getStateInformation(state);
    }
    {
        Rig rig;
        rig.processor.setStateInformation(state.getData(), static_cast<int>(state.getSize()));
        const auto info = rig.processor.stageInfo();
        CHECK(info.setList);
        CHECK(info.cueCount == 4);
        CHECK(info.listName == "show.json");
        CHECK(info.cueName == "Intro");
        CHECK(static_cast<int>(rig.processor.settings()[SettingIds::midiChannel]) == 7);
    }
    // The same state with the set list's text damaged (an unknown scene in cue 2).
    auto xml = juce::AudioProcessor::getXmlFromBinary(state.getData(), static_cast<int>(state.getSize()));
    REQUIRE(xml != nullptr);
    auto* settings = xml->getChildByName("SETTINGS");
    REQUIRE(settings != nullptr);
    settings->setAttribute("setList", juce::String(kFourCues).replace("sound-design", "kazoo"));
    juce::MemoryBlock damaged;
    juce::AudioProcessor::copyXmlToBinary(*xml, damaged);
    Rig rig;
    REQUIRE(rig.processor.useSetList(kFourCues, "before.json") == "");   // one in use before: it goes too
    rig.processor.setStateInformation(damaged.getData(), static_cast<int>(damaged.getSize()));
    const auto message = rig.processor.statusMessage();
    INFO(message);
    CHECK(message.contains("The saved set list is not used"));
    CHECK(message.contains("show.json"));
    CHECK(message.contains("kazoo"));
    CHECK_FALSE(rig.processor.stageInfo().setList);
    CHECK(rig.processor.settings()[SettingIds::setList].toString().isEmpty());
    CHECK(static_cast<int>(rig.processor.settings()[SettingIds::midiChannel]) == 7);   // the rest is taken
    for (int i = 0; i < 5; ++i) rig.run();
    CHECK(rig.processor.latestFrame().valid);   // the single scene plays
    // A file that is not a set list names itself, and the set list in use stays.
    const auto bad = juce::File::createTempFile(".json");
    bad.replaceWithText("{\"armadillo_setlist\": 1, \"cues\": []}");
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    const auto why = rig.processor.loadSetList(bad);
    bad.deleteFile();
    INFO(why);
    CHECK(why.contains(bad.getFileName()));
    CHECK(rig.processor.stageInfo().setList);
    CHECK(rig.processor.loadSetList(juce::File("/nonexistent/show.json")).contains("no such file"));
}

TEST_CASE("stage: the OSC stage commands reach the plugin's set list over loopback UDP", "[plugin][stage][osc]")
{
    Rig rig;
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    CHECK(rig.processor.stageOscPort() == 0);   // off by default
    rig.processor.settings().setProperty(SettingIds::stageOscPort, 0, nullptr);   // any free port
    rig.processor.settings().setProperty(SettingIds::stageOscEnabled, true, nullptr);
    const int port = rig.processor.stageOscPort();
    REQUIRE(port > 0);
    osc::OscSender sender(osc::HostPort {"127.0.0.1", port});
    const auto until = [&](auto done) {
        // Polls with a deadline (UDP and the receiver's thread): each try runs one block.
        const double end = juce::Time::getMillisecondCounterHiRes() + 3000.0;
        while (! done() && juce::Time::getMillisecondCounterHiRes() < end) {
            rig.run();
            juce::Thread::sleep(2);
        }
        return done();
    };
    const osc::OscArg two = osc::OscArg::int32(2);
    REQUIRE(sender.send("/armadillo/cue", &two, 1));
    CHECK(until([&] { return rig.processor.stageInfo().cue == 2; }));
    REQUIRE(sender.send("/armadillo/cue/next", nullptr, 0));
    CHECK(until([&] { return rig.processor.stageInfo().cue == 3; }));
    REQUIRE(sender.send("/armadillo/cue/prev", nullptr, 0));
    CHECK(until([&] { return rig.processor.stageInfo().cue == 2; }));
    REQUIRE(sender.send("/armadillo/panic", nullptr, 0));
    CHECK(until([&] { return rig.processor.panicked(); }));
    rig.run();   // the block that applies it (fading in its first 48 samples) …
    rig.run();   // … and the next one: silent
    CHECK(rig.buffer.getMagnitude(0, 0, kBlock) == 0.0f);
    REQUIRE(sender.send("/armadillo/resume", nullptr, 0));
    CHECK(until([&] { return ! rig.processor.panicked(); }));
    rig.processor.settings().setProperty(SettingIds::stageOscEnabled, false, nullptr);
    CHECK(rig.processor.stageOscPort() == 0);
}

TEST_CASE("stage: every cue of a set list takes the reader's touch profile setting", "[plugin][stage][profile]")
{
    Rig rig;
    // Thresholds 8, 4, 2 on the wrist row, 4 elsewhere: the gains are threshold / median
    // (Link/TouchProfile.h): m1 ×2, m2 ×1, m3 ×0.5, the rest ×1.
    const std::string profile = R"({"threshold": [8, 4, 2, 4, 4, 4, 4, 4, 4]})";
    rig.processor.settings().setProperty(SettingIds::touchProfile, juce::String(profile), nullptr);
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    const live::CuePlayer* cues = rig.processor.cuePlayer();
    REQUIRE(cues != nullptr);
    for (int c = 0; c < cues->cueCount(); ++c) {
        CAPTURE(c);
        const auto& g = cues->engine(c).config().motorGain;
        CHECK(g[0] == Approx(2.0f));
        CHECK(g[1] == Approx(1.0f));
        CHECK(g[2] == Approx(0.5f));
        for (std::size_t m = 3; m < kGridMotors; ++m) CHECK(g[m] == Approx(1.0f));
    }
    // Without a profile the cues are as they were.
    rig.processor.settings().setProperty(SettingIds::touchProfile, "", nullptr);
    for (int i = 0; i < 5; ++i) rig.run();   // the first set list takes over; the next may be offered
    REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");
    for (int i = 0; i < 5; ++i) rig.run();
    const live::CuePlayer* plain = rig.processor.cuePlayer();
    REQUIRE(plain != nullptr);
    CHECK(plain->engine(0).config().motorGain == TactileConfig::unitMotorGains());
}

TEST_CASE("stage: the panic gesture setting — the right forearm hanging down 2 s panics, once per hang", "[plugin][stage][panic][gesture]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the guard sees an allocation before its zero is trusted
        auto p = std::make_unique<double>(1.0);
        CHECK(probe.allocations() >= 1);
    }
    const bool withSetList = GENERATE(true, false);
    INFO((withSetList ? "with a set list" : "the single scene"));
    Rig rig;
    if (withSetList) REQUIRE(rig.processor.useSetList(kFourCues, "show.json") == "");   // cue 1: the theremin
    REQUIRE_FALSE(static_cast<bool>(rig.processor.settings()[SettingIds::panicGesture]));   // off by default

    std::uint64_t allocations = 0, locks = 0, throws = 0;
    float peak = 0.0f;
    bool motorsOn = false;
    const auto hold = [&](double el, int blocks) {   // the arm held at `el` for blocks × 10 ms
        peak = 0.0f;
        motorsOn = false;
        for (int i = 0; i < blocks; ++i) {
            RealtimeGuard guard;
            rig.runAt(el);
            allocations += guard.allocations();
            locks += guard.locks();
            throws += guard.throws();
            peak = std::max(peak, rig.buffer.getMagnitude(0, 0, kBlock));
            motorsOn = motorsOn || anyMotorOn(rig.processor.latestFrame());
        }
    };
    // Just above the gesture's −75° (the fusion settles there), then hanging at −85°.
    hold(-70.0, 100);
    REQUIRE(peak > 0.01f);   // it sounds (the set list's theremin, the Scene box's default scene)
    if (withSetList) REQUIRE(motorsOn);   // the theremin's cue drives the motors
    hold(-85.0, 300);        // off: 3 s hanging does nothing
    const bool offPanicked = rig.processor.panicked();
    const float offPeak = peak;

    rig.processor.settings().setProperty(SettingIds::panicGesture, true, nullptr);
    hold(-70.0, 50);
    hold(-85.0, 190);        // 1.9 s: not yet
    const bool shortPanicked = rig.processor.panicked();
    hold(-70.0, 50);         // risen: the hang is over
    const bool shortAfter = rig.processor.panicked();
    hold(-85.0, 210);        // 2.1 s: panic
    const bool longPanicked = rig.processor.panicked();
    hold(-85.0, 10);         // from the next block on: audio exactly 0, motors all-off
    const float panicPeak = peak;
    const bool panicMotors = motorsOn;

    rig.processor.resume();  // resumed while still hanging: no panic again …
    hold(-85.0, 300);
    const bool resumedPanicked = rig.processor.panicked();
    const float resumedPeak = peak;
    hold(-70.0, 50);         // … until the arm rose and hangs 2 s again
    hold(-85.0, 210);
    const bool againPanicked = rig.processor.panicked();
    std::printf("plugin panic gesture (%s): off 3 s -> %d; on 1.9 s -> %d; 2.1 s -> %d, then peak %.3g motors %d; "
                "resumed hanging 3 s -> %d (peak %.3g); risen and 2.1 s -> %d; %u panics; %llu allocations, %llu locks, %llu throws\n",
                withSetList ? "set list" : "single scene", offPanicked ? 1 : 0, shortPanicked ? 1 : 0, longPanicked ? 1 : 0,
                static_cast<double>(panicPeak), panicMotors ? 1 : 0, resumedPanicked ? 1 : 0, static_cast<double>(resumedPeak),
                againPanicked ? 1 : 0, rig.processor.panics(), static_cast<unsigned long long>(allocations),
                static_cast<unsigned long long>(locks), static_cast<unsigned long long>(throws));
    CHECK_FALSE(offPanicked);
    CHECK(offPeak > 0.0f);
    CHECK_FALSE(shortPanicked);
    CHECK_FALSE(shortAfter);
    CHECK(longPanicked);
    CHECK(panicPeak == 0.0f);
    CHECK_FALSE(panicMotors);
    CHECK_FALSE(resumedPanicked);
    CHECK(resumedPeak > 0.0f);
    CHECK(againPanicked);
    CHECK(rig.processor.panics() == 2);
    CHECK(allocations == 0);
    CHECK(locks == 0);
    CHECK(throws == 0);

    // The setting is saved in the state and acts again after loading it.
    juce::MemoryBlock state;
    rig.processor.getStateInformation(state);
    Rig loaded;
    loaded.processor.setStateInformation(state.getData(), static_cast<int>(state.getSize()));
    CHECK(static_cast<bool>(loaded.processor.settings()[SettingIds::panicGesture]));
    for (int i = 0; i < 50; ++i) loaded.runAt(-70.0);
    for (int i = 0; i < 210; ++i) loaded.runAt(-85.0);
    CHECK(loaded.processor.panicked());
}
