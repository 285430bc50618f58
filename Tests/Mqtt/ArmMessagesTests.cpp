// Messages shown by the braille scene through the presenter (no broker here: the broker tests are
// ClientTests/InboxTests and the command line's e2e tests): read by roll or timed, framed by the
// cues of Braille/Sensations.h, urgent first, the interrupted one shown again; control() stays
// allocation- and lock-free while it shows them; the sign shorthand.
#include "Braille/BrailleScene.h"
#include "Braille/Sensations.h"
#include "Braille/Training.h"
#include "Braille/TestArm.h"
#include "Common/RealtimeGuard.h"
#include "Mqtt/ArmMessages.h"
#include "Mqtt/MqttClient.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::braille;
using namespace armadillo::braille::test;
using armadillo::test::RealtimeGuard;

namespace {

class Canvas final : public MotorCanvas {
public:
    std::array<float, kGridMotors> level {};
    void setLevel(int i, float l) override { level[static_cast<std::size_t>(i)] = l; }
    void clearLevels() override { level.fill(0.0f); }
    void trigger(const PatternRequest&) override {}
    void stopVoice(int) override {}
    MotorSet on() const
    {
        MotorSet s = 0;
        for (int i = 0; i < kGridMotors; ++i)
            if (level[static_cast<std::size_t>(i)] > 0.0f) s |= static_cast<MotorSet>(1u << i);
        return s;
    }
};

class Events final : public EventSink {
public:
    std::array<std::pair<const char*, float>, 4096> list {};
    std::size_t count = 0;
    void emit(const char* g, float v) override
    {
        if (count < list.size()) list[count++] = {g, v};
    }
    int n(const std::string& name) const
    {
        int k = 0;
        for (std::size_t i = 0; i < count; ++i) k += name == list[i].first;
        return k;
    }
};

struct Rig {
    std::unique_ptr<Scene> scene = makeBrailleScene();
    BrailleSceneControls& controls = dynamic_cast<BrailleSceneControls&>(*scene);
    Canvas canvas;
    Events events;
    std::vector<MotorSet> frames;   // distinct non-empty motor sets, in order

    explicit Rig(bool messagesOnly = false)
    {
        SceneConfig c;
        c.text = "exit";
        c.messagesOnly = messagesOnly;
        c.resourceDir = std::string(ARMADILLO_SOURCE_DIR) + "/Resources";
        scene->prepare(c);
    }
    void run(const Motion& m, std::size_t from = 0)
    {
        SceneOutput out {canvas, events};
        MotorSet last = 0;
        for (std::size_t i = from; i < m.states.size(); ++i) {
            ControlInput in;
            in.arm = m.states[i];
            in.dt = kDt;
            scene->control(in, out);
            const MotorSet s = canvas.on();
            if (s != last && s != 0) frames.push_back(s);
            last = s;
        }
    }
    void idle(double seconds)
    {
        Motion m;
        m.hold(hanging(0), seconds);
        run(m);
    }
};

/// The row sets of a word's cells by the rows method, wrist row first, pauses left out.
std::vector<MotorSet> rowsOf(const std::string& word)
{
    std::vector<MotorSet> out;
    for (const auto& u : layoutDocument(translateText(word, {}), DisplayMethod::Rows))
        for (MotorSet s : u.steps)
            if (s) out.push_back(s);
    return out;
}

std::vector<MotorSet> cueSets()
{
    return {0x1FF, 0x1FF, motorBit(0, 1), motorBit(1, 1), motorBit(2, 1)};
}

} // namespace

TEST_CASE("a timed message: waiting cue, sweep, its rows, the double tap; then the scene's text again", "[mqtt][braille]")
{
    Rig rig;
    mqtt::MqttConfig config;
    mqtt::MessageInbox inbox(config);
    mqtt::PresenterOptions options;
    options.timed = true;
    mqtt::MessagePresenter presenter(inbox, options);
    REQUIRE(inbox.offerText("hi", "osc", 0));
    const auto said = presenter.poll(rig.controls);
    REQUIRE(said.size() == 1);
    CHECK(said[0] == "message 1 from 'osc' on the arm: hi");
    CHECK(rig.controls.messageBusy());
    rig.idle(10.0);
    std::vector<MotorSet> expected = cueSets();
    for (MotorSet s : rowsOf("hi")) expected.push_back(s);
    expected.push_back(kUndersideLine);
    expected.push_back(kUndersideLine);
    CHECK(rig.frames == expected);
    CHECK(rig.events.n("message-start") == 1);
    CHECK(rig.events.n("message-end") == 1);
    CHECK_FALSE(rig.controls.messageBusy());
    const auto after = presenter.poll(rig.controls);
    REQUIRE(after.size() == 1);
    CHECK(after[0] == "message 1 shown");
    CHECK(presenter.shown() == 1);
    CHECK(presenter.onArm() == 0);
}

TEST_CASE("a message read by roll: the reader rolls through it, then the scene's own text comes back", "[mqtt][braille]")
{
    Rig rig;
    mqtt::MqttConfig config;
    mqtt::MessageInbox inbox(config);
    mqtt::MessagePresenter presenter(inbox, {});
    REQUIRE(inbox.offerText("ok", "osc", 0));
    presenter.poll(rig.controls);
    rig.idle(2.0);   // the announcement; nothing of the message until the reader rolls
    CHECK(rig.frames == cueSets());
    rig.frames.clear();
    Motion m;
    double roll = 0.0;
    m.hold(hanging(roll), 0.3);
    for (int step = 0; step < 7; ++step) {   // 2 letters × 3 rows, then past the end
        m.move(hanging(roll), hanging(roll + 16), 0.1);
        roll += 16;
        m.hold(hanging(roll), 0.3);
    }
    m.hold(hanging(roll), 1.5);
    rig.run(m);
    std::vector<MotorSet> expected = rowsOf("ok");
    expected.push_back(kUndersideLine);
    expected.push_back(kUndersideLine);
    CHECK(rig.frames == expected);
    CHECK_FALSE(rig.controls.messageBusy());
    // The scene's own text ("exit") is read again from where it was: its first row.
    rig.frames.clear();
    Motion next;
    next.hold(hanging(roll), 0.3);
    next.move(hanging(roll), hanging(roll + 16), 0.1);
    next.hold(hanging(roll + 16), 0.4);
    rig.run(next);
    REQUIRE(rig.frames.size() == 1);
    CHECK(rig.frames[0] == rowsOf("e").front());
}

TEST_CASE("messages only (armadillo read): rolling reads nothing of the scene's own; a message is read by roll, then stillness", "[mqtt][braille]")
{
    Rig rig(true);
    // The same rolls that read the scene's own text's first rows in the test above.
    const auto rolls = [](double from, int steps) {
        Motion m;
        double roll = from;
        m.hold(hanging(roll), 0.3);
        for (int step = 0; step < steps; ++step) {
            m.move(hanging(roll), hanging(roll + 16), 0.1);
            roll += 16;
            m.hold(hanging(roll), 0.3);
        }
        m.hold(hanging(roll), 1.5);
        return m;
    };
    rig.run(rolls(0.0, 4));
    CHECK(rig.frames.empty());   // "exit" is not the reader's: not a motor moved
    mqtt::MqttConfig config;
    mqtt::MessageInbox inbox(config);
    mqtt::MessagePresenter presenter(inbox, {});
    REQUIRE(inbox.offerText("ok", "osc", 0));
    presenter.poll(rig.controls);
    rig.idle(2.0);
    CHECK(rig.frames == cueSets());
    rig.frames.clear();
    rig.run(rolls(64.0, 7));   // 2 letters × 3 rows, then past the end
    std::vector<MotorSet> expected = rowsOf("ok");
    expected.push_back(kUndersideLine);
    expected.push_back(kUndersideLine);
    CHECK(rig.frames == expected);
    CHECK_FALSE(rig.controls.messageBusy());
    CHECK(presenter.poll(rig.controls) == std::vector<std::string> {"message 1 shown"});
    rig.frames.clear();
    rig.run(rolls(176.0, 4));
    CHECK(rig.frames.empty());   // after the message: still again
    CHECK(rig.events.n("advance") == 7);   // only the message's steps were read
}

TEST_CASE("an urgent message interrupts; the interrupted one is shown again whole", "[mqtt][braille]")
{
    Rig rig;
    mqtt::MqttConfig config;
    mqtt::MessageInbox inbox(config);
    mqtt::PresenterOptions options;
    options.timed = true;
    mqtt::MessagePresenter presenter(inbox, options);
    REQUIRE(inbox.offerText("abcdef", "arm/inbox", 0));
    presenter.poll(rig.controls);
    rig.idle(3.0);   // into its first cells
    REQUIRE(inbox.offerText("ex", "door/front", 1));
    const auto said = presenter.poll(rig.controls);
    REQUIRE(said.size() == 1);
    CHECK(said[0] == "message 2 from 'door/front' (urgent) on the arm: ex");
    rig.idle(12.0);
    const auto back = presenter.poll(rig.controls);
    CHECK(std::find(back.begin(), back.end(), "message 1 interrupted: shown again next") != back.end());
    CHECK(std::find(back.begin(), back.end(), "message 2 shown") != back.end());
    CHECK(std::find(back.begin(), back.end(), "message 1 from 'arm/inbox' on the arm: abcdef") != back.end());
    rig.frames.clear();
    rig.idle(30.0);
    CHECK(rig.events.n("message-start") == 3);
    CHECK(rig.events.n("message-end") == 2);
    std::vector<MotorSet> expected = cueSets();   // message 1 again, whole
    for (MotorSet s : rowsOf("abcdef")) expected.push_back(s);
    expected.push_back(kUndersideLine);
    expected.push_back(kUndersideLine);
    CHECK(rig.frames == expected);
}

TEST_CASE("the braille scene's control() neither allocates nor locks while it shows a message", "[mqtt][braille]")
{
    Rig rig;
    auto message = prepareArmMessage("do not enter", "test", 1, DisplayMethod::Rows, true, false, 7);
    auto urgent = prepareArmMessage("ex", "test", 1, DisplayMethod::Rows, false, true, 8);
    REQUIRE(rig.controls.showMessage(message.get()));
    Motion m;
    m.hold(hanging(0), 20.0);
    SceneOutput out {rig.canvas, rig.events};
    ARMADILLO_REQUIRE_GUARD();
    RealtimeGuard guard;
    for (std::size_t i = 0; i < m.states.size(); ++i) {
        if (i == 2000) (void)rig.controls.showMessage(urgent.get());
        ControlInput in;
        in.arm = m.states[i];
        in.dt = kDt;
        rig.scene->control(in, out);
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.locks() == 0);
    std::uint64_t id = 0;
    bool interrupted = false;
    REQUIRE(rig.controls.takeFinishedMessage(id, interrupted));
    CHECK(id == 7);
    CHECK(interrupted);
    CHECK_FALSE(rig.controls.takeFinishedMessage(id, interrupted));   // the roll message waits for the reader
    CHECK(rig.controls.messageBusy());
    {
        RealtimeGuard probe;   // the probe sees an allocation
        auto p = std::make_unique<int>(3);
        CHECK(probe.allocations() > 0);
    }
}

TEST_CASE("messages that braille cannot show are said and counted; the sign shorthand", "[mqtt][braille]")
{
    Rig rig;
    mqtt::MqttConfig config;
    mqtt::MessageInbox inbox(config);
    mqtt::PresenterOptions options;
    options.shorthand = signShorthand(defaultSignWords(std::string(ARMADILLO_SOURCE_DIR) + "/Resources"));
    mqtt::MessagePresenter presenter(inbox, options);
    CHECK(mqtt::applyShorthand("EXIT", options.shorthand) == "ex");        // docs/BRAILLE.md: with the shipped words
    CHECK(mqtt::applyShorthand("entrance", options.shorthand) == "en");
    CHECK(mqtt::applyShorthand("EXIT now", {{"ex", "exit"}, {"en", "entrance"}}) == "ex now");
    CHECK(mqtt::applyShorthand("no exits", {{"ex", "exit"}}) == "no exits");
    CHECK(mqtt::applyShorthand("Entrance", {{"ex", "exit"}, {"en", "entrance"}}) == "en");
    REQUIRE(inbox.offerText("\xE2\x98\x83", "osc", 0));   // a snowman: no braille in the table
    const auto said = presenter.poll(rig.controls);
    REQUIRE(said.size() == 1);
    CHECK_THAT(said[0], Catch::Contains("not shown: message 1 from 'osc'"));
    CHECK(presenter.unshowable() == 1);
    CHECK_FALSE(rig.controls.messageBusy());
}

TEST_CASE("during a braille training only urgent messages are shown; the others wait for its end", "[mqtt][braille]")
{
    Rig rig;
    rig.scene->setParameter(kParamMode, static_cast<float>(BrailleMode::Training));
    auto normal = prepareArmMessage("hi", "test", 1, DisplayMethod::Rows, true, false, 1);
    auto urgent = prepareArmMessage("ex", "test", 1, DisplayMethod::Rows, true, true, 2);
    REQUIRE(rig.controls.showMessage(normal.get()));
    rig.idle(5.0);
    CHECK(rig.events.n("message-start") == 0);   // the trial goes on
    CHECK(rig.controls.messageBusy());            // the message waits in the scene
    REQUIRE(rig.controls.showMessage(urgent.get()));
    rig.idle(10.0);
    CHECK(rig.events.n("message-start") == 1);   // the urgent one only
    CHECK(rig.events.n("message-end") == 1);
    std::uint64_t id = 0;
    bool interrupted = true;
    REQUIRE(rig.controls.takeFinishedMessage(id, interrupted));
    CHECK(id == 2);
    CHECK_FALSE(interrupted);
    // Out of training, the waiting one starts.
    rig.scene->setParameter(kParamMode, static_cast<float>(BrailleMode::Active));
    rig.idle(10.0);
    CHECK(rig.events.n("message-start") == 2);
    REQUIRE(rig.controls.takeFinishedMessage(id, interrupted));
    CHECK(id == 1);
}
