// The app's reader functions (issue 26) without a window: self-voicing and the braille display
// (ReaderVoice, captured through the core's capture backends), Perkins chord entry (the
// TrainingKeys listener driven by simulated key presses as the Training panel's answer field gets them),
// the detection that turns self-voicing on by default, and the touch profile kept in the state.
#include "Access/Feedback.h"
#include "Engine/Engine.h"
#include "Live/Session/BlockControl.h"
#include "Plugin/HostBlock.h"
#include "Access/ReaderProfile.h"
#include "Procedures/AdaptiveTraining.h"
#include "Plugin/PerkinsKeys.h"
#include "Plugin/PluginState.h"
#include "Access/ReaderVoice.h"
#include "Procedures/TouchTest.h"
#include "HostedPlugin.h"
#include "Common/Eventually.h"
#include "Common/FakeBrlApi.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

using namespace armadillo;
using namespace armadillo::plugin;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::tactile;
// The app's sessions are the procedures (issue 32: each guided procedure written once, below JUCE).
using TouchTestSession = armadillo::procedures::TouchTest;
using AdaptiveSession = armadillo::procedures::AdaptiveTraining;
using armadillo::procedures::AdaptiveChoices;

namespace {

juce::File freshDir(const char* name)
{
    auto dir = juce::File::getSpecialLocation(juce::File::tempDirectory).getChildFile(name);
    dir.deleteRecursively();
    REQUIRE(dir.createDirectory());
    return dir;
}

juce::StringArray linesOf(const juce::File& f)
{
    juce::StringArray lines;
    lines.addLines(f.loadFileAsString());
    lines.removeEmptyStrings();
    return lines;
}

/// Presses and releases a chord on `keys` the way JUCE delivers it: a keyPressed per key going
/// down, then keyStateChanged(false) as each comes up (`held` is what isKeyCurrentlyDown sees).
void chord(TrainingKeys& keys, juce::Component& field, const std::string& chordKeys, std::set<int>& held)
{
    for (char k : chordKeys) {
        held.insert(k);
        CHECK(keys.keyPressed(juce::KeyPress(k, 0, static_cast<juce::juce_wchar>(k)), &field));
    }
    for (char k : chordKeys) {   // released one at a time: the cell is taken when the last comes up
        held.erase(k);
        keys.keyStateChanged(false, &field);
    }
}

} // namespace

TEST_CASE("Self-voicing: every text reaches the speech and the braille display; repeat, stop, rate", "[plugin][reader]")
{
    const auto dir = freshDir("armadillo-reader-voice");
    const auto speech = dir.getChildFile("speech.txt"), display = dir.getChildFile("display.txt");
    armadillo::access::ReaderVoice voice;
    voice.say("not heard: nothing is open");   // remembered for repeat, but no backend yet
    REQUIRE(voice.open("capture:" + speech.getFullPathName().toStdString(), "capture:" + display.getFullPathName().toStdString()) == "");
    CHECK(voice.speaking());
    CHECK(voice.showing());
    // Each step waited for: a new interrupting text (and stop) drops what is still queued, by design.
    voice.setRate(40);
    voice.say("Trial 1 of 3: which letter?");
    voice.waitIdle();
    voice.say("right. 1 of 1 right.", false);
    voice.waitIdle();
    voice.repeat();
    voice.waitIdle();
    voice.stop();
    voice.setRate(500);   // clamped
    voice.waitIdle();
    CHECK(voice.rate() == 100);
    const auto said = linesOf(speech);
    REQUIRE(said.size() >= 6);
    // open() sets the rate it has (0), then the queue in order.
    CHECK(said.contains("rate: 40"));
    CHECK(said.contains("say: Trial 1 of 3: which letter?"));
    CHECK(said.contains("say+: right. 1 of 1 right."));
    CHECK(said.indexOf("say: right. 1 of 1 right.") > said.indexOf("say+: right. 1 of 1 right."));   // repeated
    CHECK(said.contains("stop"));
    CHECK(said.contains("rate: 100"));
    CHECK(! said.joinIntoString("\n").contains("not heard"));
    const auto shown = linesOf(display);
    CHECK(shown.contains("write: Trial 1 of 3: which letter?"));
    CHECK(shown.contains("write: right. 1 of 1 right."));

    // A backend that cannot be opened is named; the other one still works.
    const auto why = voice.open("capture:" + dir.getChildFile("no-such-dir/x.txt").getFullPathName().toStdString(),
                                "capture:" + display.getFullPathName().toStdString());
    CHECK_THAT(why, Catch::Contains("No speech"));
    CHECK(! voice.speaking());
    CHECK(voice.showing());
    voice.close();
    CHECK(! voice.showing());
}

TEST_CASE("Self-voicing is on by default when a screen reader or brltty runs", "[plugin][reader]")
{
    const auto dir = freshDir("armadillo-reader-detect");
    const auto proc = dir.getChildFile("proc");
    REQUIRE(proc.getChildFile("1").createDirectory());
    REQUIRE(proc.getChildFile("1/comm").replaceWithText("systemd\n", false, false, "\n"));
    CHECK(! armadillo::access::ReaderVoice::readerDetected(proc.getFullPathName().toStdString(), {}));
    CHECK(! armadillo::access::ReaderVoice::readerDetected(proc.getFullPathName().toStdString(), {dir.getChildFile("BrlAPI/0").getFullPathName().toStdString()}));
    for (const char* reader : {"orca", "brltty", "speech-dispatch"}) {   // comm is cut at 15 characters
        REQUIRE(proc.getChildFile("77").createDirectory());
        REQUIRE(proc.getChildFile("77/comm").replaceWithText(juce::String(reader) + "\n", false, false, "\n"));
        CHECK(armadillo::access::ReaderVoice::readerDetected(proc.getFullPathName().toStdString(), {}));
        REQUIRE(proc.getChildFile("77").deleteRecursively());
    }
    // The BrlAPI socket alone (brltty started by the system, not visible in this /proc).
    REQUIRE(dir.getChildFile("BrlAPI/0").create());
    CHECK(armadillo::access::ReaderVoice::readerDetected(proc.getFullPathName().toStdString(), {dir.getChildFile("BrlAPI/0").getFullPathName().toStdString()}));
}

TEST_CASE("Keyboard only: a scripted answer session with chords, letters, repeat and the display's keys", "[plugin][reader]")
{
    juce::ScopedJuceInitialiser_GUI juce;
    const auto dir = freshDir("armadillo-reader-keys");
    const auto speech = dir.getChildFile("speech.txt");
    // The braille display: a fake BrlAPI server (Tests/Common/FakeBrlApi.h) behind the real
    // BrlAPI backend, so its writes and its keys go the whole way.
    armadillo::test::FakeBrlApiServer server;
    REQUIRE(server.ok());
    armadillo::access::ReaderVoice voice;
    const auto why = voice.open("capture:" + speech.getFullPathName().toStdString(), "brlapi:" + server.host());
    if (why.find("not found") != std::string::npos) {
        WARN("libbrlapi is not installed here (Debian: libbrlapi0.8): " + why);
        return;
    }
    REQUIRE(why == "");

    // What the Training panel does with an answer (TrainingPanel::submit, announce): the field's
    // text is the answer, the feedback is announced, which the app speaks and brailles.
    juce::TextEditor field;
    TrainingKeys keys;
    std::set<int> held;
    keys.isDown = [&held](int code) { return held.count(code) > 0; };
    const std::vector<std::string> expected {"b", "e", "x", "k", "z"};
    std::vector<std::string> answers;
    auto announce = [&voice](const juce::String& t) {
        voice.say(t.toStdString());
        voice.waitIdle();   // each text whole on the display before the next (the test reads them all)
    };
    auto prompt = [&] { announce("Trial " + juce::String(answers.size() + 1) + " of 5: which letter?"); };
    keys.attach(field, [&] {
        const auto given = field.getText().toStdString();
        const auto& want = expected[answers.size()];
        answers.push_back(given);
        field.clear();
        announce(given == want ? juce::String("right") : "wrong: it was '" + juce::String(want) + "'");
        if (answers.size() < expected.size()) prompt();
    }, announce, &voice);

    prompt();
    keys.keyPressed(juce::KeyPress(juce::KeyPress::F2Key), &field);   // chord entry on
    CHECK(keys.chordMode());
    chord(keys, field, "fd", held);                 // dots 1 2 = b
    CHECK(field.getText() == "b");
    CHECK(keys.keyPressed(juce::KeyPress(juce::KeyPress::spaceKey, 0, ' '), &field));   // Space answers
    chord(keys, field, "s", held);                  // dot 3 alone: not a letter, said, nothing typed
    CHECK(field.getText().isEmpty());
    chord(keys, field, "kf", held);                 // dots 1 5 = e
    CHECK(keys.keyPressed(juce::KeyPress(juce::KeyPress::F3Key), &field));   // repeat: "e" again
    voice.waitIdle();   // (a new text interrupts: the repeat is said before the answer's feedback)
    keys.keyPressed(juce::KeyPress(juce::KeyPress::spaceKey, 0, ' '), &field);
    chord(keys, field, "fd", held);                 // b, taken back with Backspace, then x = 1 3 4 6
    keys.keyPressed(juce::KeyPress(juce::KeyPress::backspaceKey), &field);
    chord(keys, field, "fsjl", held);
    CHECK(! keys.keyPressed(juce::KeyPress('x', juce::ModifierKeys::ctrlModifier, 0), &field));   // shortcuts pass
    keys.keyPressed(juce::KeyPress(juce::KeyPress::spaceKey, 0, ' '), &field);
    // Chords off: typed letters are the field's own (the listener lets them through to it) and
    // Return is the field's onReturnKey, which the panel points at submit as Space is here.
    keys.keyPressed(juce::KeyPress(juce::KeyPress::F2Key), &field);
    CHECK(! keys.chordMode());
    CHECK(! keys.keyPressed(juce::KeyPress('k', 0, 'k'), &field));
    field.insertTextAtCaret("k");
    keys.onSubmit();
    // The braille display's own keys answer the last trial: "z" then Enter, polled as the
    // panel's timer does.
    server.type("z\n");
    CHECK(armadillo::testing::eventually([&] {
        keys.pollDisplay();
        return answers.size() == expected.size();
    }, 20.0));
    voice.waitIdle();
    CHECK(armadillo::testing::eventually([&] { return ! server.writes().empty() && server.writes().back() == "right"; }, 20.0));

    CHECK(answers == expected);
    const auto said = linesOf(speech);
    const auto shownList = server.writes();
    juce::StringArray shown;
    for (const auto& w : shownList) shown.add(juce::String(w));
    // Every prompt and every feedback reached both the speech and the braille display.
    for (const char* line : {"Trial 1 of 5: which letter?", "Trial 2 of 5: which letter?", "Trial 3 of 5: which letter?",
                             "Trial 4 of 5: which letter?", "Trial 5 of 5: which letter?", "right", "dots 3 is not a letter",
                             "b", "e", "x", "erased b"}) {
        INFO(line);
        CHECK(said.contains(juce::String("say: ") + line));
        CHECK(shown.contains(line));
    }
    CHECK(said.joinIntoString("\n").contains("Chord entry on"));
    CHECK(said.joinIntoString("\n").contains("Chord entry off"));
    // F3 said the echo "e" again, and all five answers were right.
    CHECK(said.joinIntoString("\n").contains("say: e\nsay: e"));
    CHECK(said.joinIntoString("\n").contains("right") );
    CHECK(! said.joinIntoString("\n").contains("wrong"));
    field.removeKeyListener(&keys);
}

TEST_CASE("Touch profile in the plugin state: kept when it parses, refused when damaged", "[plugin][reader][state]")
{
    const std::string profile = R"({"format": "armadillo-touch-profile", "version": 1, "threshold": [3, 4, 5, 6, 7, 8, 9, 10, 11]})";
    juce::ValueTree loaded(SettingIds::root);
    loaded.setProperty(SettingIds::touchProfile, juce::String(profile), nullptr);
    loaded.setProperty(SettingIds::readerVoice, "on", nullptr);
    loaded.setProperty(SettingIds::speechRate, 30, nullptr);
    juce::ValueTree settings(SettingIds::root);
    PluginState::installSettings(settings, loaded);
    CHECK(settings[SettingIds::touchProfile].toString().toStdString() == profile);
    CHECK(settings[SettingIds::readerVoice].toString() == "on");
    CHECK(static_cast<int>(settings[SettingIds::speechRate]) == 30);

    // Damaged: a threshold out of 1..15, not JSON, a rate out of range, an unknown voice mode.
    for (const char* bad : {R"({"threshold": [3, 4, 5, 6, 7, 8, 9, 10, 99]})", "{not json", R"({"threshold": [1, 2]})"}) {
        loaded.setProperty(SettingIds::touchProfile, bad, nullptr);
        loaded.setProperty(SettingIds::speechRate, 1000, nullptr);
        loaded.setProperty(SettingIds::readerVoice, "loud", nullptr);
        PluginState::installSettings(settings, loaded);
        INFO(bad);
        CHECK(settings[SettingIds::touchProfile].toString().isEmpty());
        CHECK(static_cast<int>(settings[SettingIds::speechRate]) == 0);
        CHECK(settings[SettingIds::readerVoice].toString() == "auto");
    }
}

TEST_CASE("Sensitivity test in the app: a simulated reader's nine thresholds found within one level", "[plugin][reader][touch]")
{
    // The simulated reader feels a stimulus when the level that reached the motor (after the
    // tactile engine and the safety stage) is at least that motor's threshold.
    const std::array<int, 9> truth {3, 5, 7, 9, 11, 4, 6, 8, 10};
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the probe catches an allocation before a zero is trusted
        int* volatile p = new int(7);
        CHECK(probe.allocations() >= 1);
        delete p;
    }
    TouchTestSession test;
    test.begin(7);
    std::vector<int> comfortAsked;
    double t = 0.0;
    const double dt = 1.0 / 200.0;   // the plugin's control rate: one onPacket per control step
    int guardSteps = 0;
    std::uint64_t allocations = 0;
    while (test.state() != TouchTestSession::State::Done && t < 3600.0) {
        {
            RealtimeGuard guard;   // the control step's side: no allocation
            (void) test.player().onPacket(t);
            allocations += guard.allocations();
        }
        ++guardSteps;
        t += dt;
        if (test.poll()) {
            const int m = test.motor();
            // The comfort step (after every threshold): "comfortable" once the level reaching the
            // motor is three above its threshold.
            if (test.comfortStep()) {
                CHECK_THAT(test.question(), Catch::EndsWith(": comfortable?"));
                CHECK(m == 4);   // the profile's comfort motor, m5
                comfortAsked.push_back(test.level());
                test.answer(test.player().maxLevel(m) >= truth[static_cast<std::size_t>(m)] + 3);
            } else {
                test.answer(test.player().maxLevel(m) >= truth[static_cast<std::size_t>(m)]);
            }
        }
    }
    REQUIRE(test.state() == TouchTestSession::State::Done);
    CHECK(allocations == 0);
    const auto profile = test.profile();
    for (std::size_t m = 0; m < 9; ++m) {
        INFO("motor m" << (m + 1) << ": found " << profile.threshold[m] << ", true " << truth[m]);
        CHECK(std::abs(profile.threshold[m] - truth[m]) <= 1);
    }
    INFO(profile.stimuli << " stimuli over " << t << " s of stimulus clock");
    CHECK(t < 5.0 * 60.0 * 2.0);   // the issue asks for < 5 min of stimuli from the CLI; the app adds the rests
    // The comfortable level, as `armadillo touch-profile` finds it: ascending one level a step
    // from the found threshold + 1 until "comfortable".
    REQUIRE(! comfortAsked.empty());
    CHECK(comfortAsked.front() == profile.threshold[4] + 1);
    for (std::size_t i = 1; i < comfortAsked.size(); ++i) CHECK(comfortAsked[i] == comfortAsked[i - 1] + 1);
    CHECK(profile.comfort == truth[4] + 3);
    CHECK(profile.comfortMotor == 5);
    // The profile round-trips through its JSON (what the state keeps), the comfort included.
    const auto back = armadillo::link::parseTouchProfile(armadillo::link::touchProfileToJson(profile), "test");
    CHECK(back.threshold == profile.threshold);
    CHECK(back.comfort == profile.comfort);
    // Without the comfort step (the CLI's --no-comfort) the test ends with the thresholds.
    TouchTestSession quick;
    quick.begin(7, false);
    for (double q = 0.0; quick.state() != TouchTestSession::State::Done && q < 3600.0; q += dt) {
        (void) quick.player().onPacket(q);
        if (quick.poll()) {
            CHECK_FALSE(quick.comfortStep());
            quick.answer(quick.player().maxLevel(quick.motor()) >= truth[static_cast<std::size_t>(quick.motor())]);
        }
    }
    CHECK(quick.state() == TouchTestSession::State::Done);
    CHECK(quick.profile().comfort == 0);
}

TEST_CASE("VST3: the reader's settings in the plugin's state; the profile applied with no allocation in processBlock",
          "[plugin][reader][state]")
{
    using namespace armadillo::test::host;
    const auto dir = freshDir("armadillo-reader-vst3");
    const auto speech = dir.getChildFile("speech.txt"), display = dir.getChildFile("display.txt");
    // The backends self-voicing opens (PluginProcessor::applyVoiceSettings): captured.
    ::setenv("ARMADILLO_SPEECH", ("capture:" + speech.getFullPathName()).toRawUTF8(), 1);
    ::setenv("ARMADILLO_BRAILLE", ("capture:" + display.getFullPathName()).toRawUTF8(), 1);
    auto h = loadVst3();
    prepare(h);
    auto setSettings = [&h](const juce::String& attributes) {
        const auto xml = juce::parseXML("<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"scene\" value=\"5\"/></PARAMETERS><SETTINGS "
                                        + attributes + "/></ARMADILLO>");
        REQUIRE(xml != nullptr);
        juce::MemoryBlock payload;
        juce::AudioProcessor::copyXmlToBinary(*xml, payload);
        juce::XmlElement state("VST3PluginState");
        state.createNewChildElement("IComponent")->addTextElement(payload.toBase64Encoding());
        juce::MemoryBlock blob;
        juce::AudioProcessor::copyXmlToBinary(state, blob);
        h.plugin->setStateInformation(blob.getData(), static_cast<int>(blob.getSize()));
        for (int i = 0; i < 5; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
    };
    const juce::String profile = R"({"format": "armadillo-touch-profile", "version": 1, "threshold": [2, 4, 6, 8, 10, 12, 14, 3, 5]})";
    setSettings("readerVoice=\"on\" speechRate=\"20\" touchProfile=\""
                + profile.replace("\"", "&quot;") + "\"");
    auto own = ownState(h);
    const auto* settings = own->getChildByName("SETTINGS");
    REQUIRE(settings != nullptr);
    CHECK(settings->getStringAttribute("touchProfile") == profile);   // saved back as it was restored
    CHECK(settings->getStringAttribute("readerVoice") == "on");
    CHECK(settings->getIntAttribute("speechRate") == 20);
    // Self-voicing on in a host too when asked: its first words reach the speech and the display.
    CHECK(armadillo::testing::eventually([&] { return speech.loadFileAsString().contains("say: ARMadillo. Self-voicing on."); }, 20.0));
    CHECK(speech.loadFileAsString().contains("rate: 20"));
    CHECK(display.loadFileAsString().contains("write: ARMadillo. Self-voicing on."));

    // The engine built with the profile's gains plays without allocating on the audio thread.
    render(h, 0.1);
    countDuringProcessing(h, 20, false);
    const auto counts = countDuringProcessing(h, 200, false);
    CHECK(counts.allocations == 0);
    CHECK(counts.throws == 0);

    // A damaged profile is refused: none is kept (every motor alike), and the state says so.
    setSettings("touchProfile=\"{&quot;threshold&quot;: [99]}\"");
    own = ownState(h);
    CHECK(own->getChildByName("SETTINGS")->getStringAttribute("touchProfile").isEmpty());
    h.plugin.reset();
    ::unsetenv("ARMADILLO_SPEECH");
    ::unsetenv("ARMADILLO_BRAILLE");
}

namespace {
/// A scene that holds the underside middle motor (index 4) at level 3: what the stimulus replaces.
class HoldScene final : public armadillo::core::Scene {
public:
    std::string_view name() const override { return "hold"; }
    void prepare(const armadillo::core::SceneConfig&) override {}
    void control(const armadillo::core::ControlInput&, armadillo::core::SceneOutput& out) override { out.motors.setLevel(4, 3.0f); }
};
} // namespace

TEST_CASE("Arm feedback through the plugin's control path: the stimulus takes the motors, then gives them back, allocating nothing",
          "[plugin][reader][realtime]")
{
    using namespace armadillo;
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the probe catches an allocation before a zero is trusted
        int* volatile p = new int(3);
        CHECK(probe.allocations() >= 1);
        delete p;
    }
    constexpr double kRate = 48000.0;
    constexpr int kBlock = 240;   // one 200 Hz control step per block
    live::Instrument instrument;   // the core every clock shares (its loop, stage, step)
    live::ControlLoop& loop = instrument.loop();
    {
        EngineConfig config;
        config.scene = "hold";
        config.sceneConfig.sampleRate = kRate;
        auto slot = std::make_unique<live::EngineSlot>();
        slot->engine = std::make_unique<Engine>(config, std::make_unique<HoldScene>());
        slot->sceneName = "hold";
        loop.replace(std::move(slot));
    }
    live::ControlToken token;
    link::LevelSchedule motors;
    std::atomic<float> elevation {0.0f}, azimuth {0.0f}, roll {0.0f}, source {static_cast<float>(live::SourceKind::HostAutomation)};
    live::BlockControl control(instrument, token, live::BlockControl::Cells {&elevation, &azimuth, &roll, &source}, motors);
    control.prepare(kRate);
    HostBlock host;
    host.prepare();
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    auto run = [&](int blocks, std::array<int, kMaxMotors>& highest, std::uint64_t& allocations) {
        highest.fill(0);
        for (int b = 0; b < blocks; ++b) {
            {
                RealtimeGuard guard;
                host.process(control, buffer, midi, nullptr, false);
                allocations += guard.allocations();
            }
            const auto f = control.latestFrame();
            for (std::size_t m = 0; m < kMaxMotors; ++m) highest[m] = std::max(highest[m], static_cast<int>(f.motors[m]));
        }
    };
    std::array<int, kMaxMotors> highest {};
    std::uint64_t allocations = 0;
    run(40, highest, allocations);   // the scene alone: its motor 4 only
    CHECK(highest[4] > 0);
    CHECK(highest[0] == 0);

    // "wrong" (the outer columns, three buzzes) played in place of the scene.
    access::TactilePlayer player(TactileConfig {}, 0.0);
    const int id = player.play(access::feedbackSensation(false, 10.0f), access::feedbackPause(false));
    control.setStimulus(&player);
    allocations = 0;
    int blocks = 0;
    std::array<int, kMaxMotors> during {};
    during.fill(0);
    while (player.completed() < id && blocks < 2000) {
        run(1, highest, allocations);
        for (std::size_t m = 0; m < kMaxMotors; ++m) during[m] = std::max(during[m], highest[m]);
        ++blocks;
    }
    REQUIRE(player.completed() >= id);
    CHECK(allocations == 0);
    for (int m : {0, 2, 3, 5, 6, 8}) CHECK(during[static_cast<std::size_t>(m)] > 0);   // the outer columns
    for (int m : {1, 4, 7}) CHECK(during[static_cast<std::size_t>(m)] == 0);          // not the underside, not the scene's
    for (int m : {0, 2, 3, 5, 6, 8}) CHECK(during[static_cast<std::size_t>(m)] <= 15);
    INFO("the sensation and its pause took " << blocks << " control steps");
    CHECK(blocks >= static_cast<int>((0.5 + access::feedbackPause(false)) * 200.0) - 2);

    control.setStimulus(nullptr);   // the scene has the motors again
    run(40, highest, allocations);
    CHECK(highest[4] > 0);
    CHECK(highest[0] == 0);
}

TEST_CASE("Adaptive training in the app: trials drawn on the arm, answers kept in the reader profile across sessions",
          "[plugin][reader][adaptive]")
{
    using namespace armadillo;
    const auto dir = freshDir("armadillo-reader-adaptive");
    const auto profile = dir.getChildFile("reader.json").getFullPathName().toStdString();
    access::TactilePlayer player(TactileConfig {}, 0.0);
    double t = 0.0;
    auto runUntil = [&](auto done) {   // the control step's side: one onPacket per 5 ms step (done() is asked once per step)
        for (int i = 0; i < 200 * 120; ++i) {
            if (done()) return true;
            (void) player.onPacket(t);
            t += 0.005;
        }
        return false;
    };
    for (int session = 1; session <= 2; ++session) {
        AdaptiveSession s(player);
        std::string why;
        AdaptiveChoices six;
        six.trials = 6;
        REQUIRE(s.begin(profile, six, why));
        int answered = 0, peak = 0;
        std::vector<std::string> feedback;
        while (s.state() != AdaptiveSession::State::Done) {
            INFO("session " << session << " answered " << answered << " completed " << player.completed() << " clock " << player.clock());
            REQUIRE(runUntil([&] { return s.poll(); }));
            for (int m = 0; m < 9; ++m) peak = std::max(peak, player.maxLevel(m));
            CHECK_THAT(s.prompt(), Catch::StartsWith("Trial " + std::to_string(answered + 1) + " of 6: "));
            feedback.push_back(s.answer("q", 1.5));   // this reader always answers q
            ++answered;
        }
        CHECK(answered == 6);
        CHECK(peak > 0);   // the trials reached the motors (through the player's tactile engine)
        CHECK_THAT(feedback.front(), Catch::StartsWith("wrong: it was '"));
        CHECK_THAT(feedback.back(), Catch::Contains("Training complete: 0 of 6 right"));
        const auto saved = access::loadReaderProfile(profile);
        // One answer per trial, a "pairs" trial (a confused pair side by side) one per letter.
        int thisSession = 0, wrong = 0;
        for (const auto& a : saved.answers) {
            thisSession += a.session == session;
            wrong += a.session == session && ! a.correct;
        }
        CHECK(thisSession >= 6);
        CHECK(wrong == thisSession);
        REQUIRE(static_cast<int>(saved.sessions.size()) == session);
        CHECK(saved.sessions.back().session == session);
        CHECK(saved.answers.front().answer == "q");
    }
    // A profile that cannot be written is refused before the first trial.
    AdaptiveSession s(player);
    std::string why;
    CHECK(! s.begin(dir.getChildFile("no/such/dir/reader.json").getFullPathName().toStdString(), AdaptiveChoices {}, why));
    CHECK(! why.empty());
    CHECK(s.state() == AdaptiveSession::State::Idle);
}

namespace {
/// Reads a CSV log into rows of fields (RFC 4180 quoting: a motor list "2,5,8" is one field).
std::vector<std::vector<std::string>> csvRows(const std::string& text)
{
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> f(1);
        bool quoted = false;
        for (std::size_t i = 0; i < line.size(); ++i) {
            const char c = line[i];
            if (quoted) {
                if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') f.back() += '"', ++i;
                else if (c == '"') quoted = false;
                else f.back() += c;
            } else if (c == '"') {
                quoted = true;
            } else if (c == ',') {
                f.emplace_back();
            } else {
                f.back() += c;
            }
        }
        rows.push_back(f);
    }
    return rows;
}
} // namespace

TEST_CASE("Adaptive training in the app: the CLI's choices, a session log, and the arm's twists", "[plugin][reader][adaptive]")
{
    using namespace armadillo;
    const auto dir = freshDir("armadillo-reader-adaptive-choices");
    const auto profile = dir.getChildFile("reader.json").getFullPathName().toStdString();
    access::TactilePlayer player(TactileConfig {}, 0.0);
    double t = 0.0;
    double rollRate = 0.0;
    auto step = [&] {
        (void) player.onPacket(t, rollRate);
        t += 0.005;
    };
    auto runUntil = [&](auto done) {
        for (int i = 0; i < 200 * 120; ++i) {
            if (done()) return true;
            step();
        }
        return false;
    };
    // A twist of the forearm and back: the roll rate one full sine period, ±6 rad/s in 0.3 s.
    auto twist = [&] {
        for (double u = 0.0; u < 0.3; u += 0.005) {
            rollRate = 6.0 * std::sin(2.0 * 3.14159265358979323846 * u / 0.3);
            step();
        }
        rollRate = 0.0;
    };

    AdaptiveChoices bad;
    std::string why;
    AdaptiveSession refused(player);
    bad.trials = 0;
    CHECK(! refused.begin(profile, bad, why));
    CHECK_THAT(why, Catch::Contains("trials"));
    bad = {};
    bad.stages = "letters,hold";
    CHECK(! refused.begin(profile, bad, why));
    CHECK_THAT(why, Catch::Contains("'hold'"));
    bad = {};
    bad.method = "braille";
    CHECK(! refused.begin(profile, bad, why));
    CHECK_THAT(why, Catch::Contains("method"));
    bad = {};
    bad.level = 16;
    CHECK(! refused.begin(profile, bad, why));
    CHECK_THAT(why, Catch::Contains("level"));

    AdaptiveChoices c;
    c.trials = 4;
    c.stages = "letters";
    c.method = "dots";
    c.level = 5;
    AdaptiveSession s(player);
    REQUIRE(s.begin(profile, c, why));
    CHECK(s.logPath() == dir.getChildFile("reader-session1.csv").getFullPathName().toStdString());

    // Trial 1: one twist shows it again; trial 2: two twists skip it; trials 3 and 4 answered.
    REQUIRE(runUntil([&] { return s.poll(); }));
    CHECK_THAT(s.prompt(), Catch::StartsWith("Trial 1 of 4: "));
    twist();
    REQUIRE(runUntil([&] { return player.repeats() == 1; }));   // reported once the pair window is over
    CHECK(s.takeGesture() == AdaptiveSession::Gesture::Repeat);
    CHECK(s.takeGesture() == AdaptiveSession::Gesture::None);   // taken once
    s.again();
    CHECK(s.state() == AdaptiveSession::State::Drawing);
    REQUIRE(runUntil([&] { return s.poll(); }));
    s.answer("q", 1.0);
    REQUIRE(runUntil([&] { return s.poll(); }));
    CHECK_THAT(s.prompt(), Catch::StartsWith("Trial 2 of 4: "));
    twist();
    twist();
    REQUIRE(runUntil([&] { return player.skips() == 1; }));
    REQUIRE(s.takeGesture() == AdaptiveSession::Gesture::Skip);
    CHECK_THAT(s.skip(2.0), Catch::StartsWith("skipped: it was '"));
    for (int n = 3; n <= 4; ++n) {
        REQUIRE(runUntil([&] { return s.poll(); }));
        s.answer("q", 1.0);
    }
    CHECK(s.state() == AdaptiveSession::State::Done);

    // The log: the CLI's columns; every trial's cue, rows, answer and feedback; the gestures; the end.
    const auto rows = csvRows(juce::File(s.logPath()).loadFileAsString().toStdString());
    REQUIRE(rows.size() > 10);
    CHECK(rows[0] == std::vector<std::string> {"t", "event", "stage", "trial", "expected", "prompt", "posture", "roll_deg", "unit", "step",
                                               "motors", "answer", "correct"});
    int trials = 0, answers = 0, feedbacks = 0, ends = 0;
    std::vector<std::string> gestures;
    double lastFeedbackEnd = -1.0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& r = rows[i];
        REQUIRE(r.size() == 13);
        trials += r[1] == "trial";
        answers += r[1] == "answer";
        ends += r[1] == "end";
        if (r[1] == "gesture") gestures.push_back(r[11]);
        if (r[1] == "feedback") {
            ++feedbacks;
            lastFeedbackEnd = std::stod(r[0]) + 0.5;   // the longer sensation ("wrong") lasts 0.5 s
        }
        // The next trial's "next" cue comes after the feedback (and the right cell again) has played.
        if (r[1] == "cue" && r[5] == "next" && lastFeedbackEnd > 0.0) CHECK(std::stod(r[0]) >= lastFeedbackEnd);
        // The dots method: one motor a step.
        if (r[1] == "row") CHECK(r[10].find(',') == std::string::npos);
    }
    CHECK(trials == 4);
    CHECK(answers == 4);
    CHECK(feedbacks == 4);
    CHECK(ends == 1);
    CHECK(gestures == std::vector<std::string> {"twist", "two twists"});
    // The reader profile: the four answers, the skip logged as "(skipped)", the method "dots".
    const auto saved = access::loadReaderProfile(profile);
    REQUIRE(saved.answers.size() >= 4);
    CHECK(saved.sessions.back().method == "dots");
    int skipped = 0;
    for (const auto& a : saved.answers) skipped += a.answer == "(skipped)";
    CHECK(skipped == 1);
}

TEST_CASE("Adaptive choices in the settings: kept when usable, the defaults otherwise", "[plugin][reader][state]")
{
    juce::ValueTree loaded("SETTINGS");
    loaded.setProperty(SettingIds::adaptiveTrials, 35, nullptr);
    loaded.setProperty(SettingIds::adaptiveStages, "letters,signs", nullptr);
    loaded.setProperty(SettingIds::adaptiveMethod, "dots", nullptr);
    loaded.setProperty(SettingIds::adaptiveLevel, 11, nullptr);
    loaded.setProperty(SettingIds::readerProfile, "/home/reader/reader.json", nullptr);
    juce::ValueTree settings("SETTINGS");
    PluginState::installSettings(settings, loaded);
    CHECK(static_cast<int>(settings[SettingIds::adaptiveTrials]) == 35);
    CHECK(settings[SettingIds::adaptiveStages].toString() == "letters,signs");
    CHECK(settings[SettingIds::adaptiveMethod].toString() == "dots");
    CHECK(static_cast<int>(settings[SettingIds::adaptiveLevel]) == 11);
    CHECK(settings[SettingIds::readerProfile].toString() == "/home/reader/reader.json");
    juce::ValueTree damaged("SETTINGS");
    damaged.setProperty(SettingIds::adaptiveTrials, 0, nullptr);
    damaged.setProperty(SettingIds::adaptiveStages, "letters,hold", nullptr);
    damaged.setProperty(SettingIds::adaptiveMethod, "braille", nullptr);
    damaged.setProperty(SettingIds::adaptiveLevel, 99, nullptr);
    PluginState::installSettings(settings, damaged);
    CHECK(static_cast<int>(settings[SettingIds::adaptiveTrials]) == 20);
    CHECK(settings[SettingIds::adaptiveStages].toString() == "letters,words");
    CHECK(settings[SettingIds::adaptiveMethod].toString() == "rows");
    CHECK(static_cast<int>(settings[SettingIds::adaptiveLevel]) == 8);
}
