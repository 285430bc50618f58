#include "Braille/BrailleScene.h"
#include "Braille/Cells.h"
#include "Braille/Sensations.h"
#include "TestArm.h"
#include <catch2/catch.hpp>
#include <array>
#include <string>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::braille;
using namespace armadillo::braille::test;

namespace {
/// Records the motor targets the scene states, as the set of motors on at each update.
class RecordingCanvas final : public MotorCanvas {
public:
    std::array<float, kGridMotors> level {};
    int triggers = 0;
    void setLevel(int i, float l) override
    {
        REQUIRE(i >= 0);
        REQUIRE(i < kGridMotors);
        level[static_cast<std::size_t>(i)] = l;
    }
    void clearLevels() override { level.fill(0.0f); }
    void trigger(const PatternRequest&) override { ++triggers; }
    void stopVoice(int) override {}
    MotorSet on() const
    {
        MotorSet s = 0;
        for (int i = 0; i < kGridMotors; ++i)
            if (level[static_cast<std::size_t>(i)] > 0.0f) s |= static_cast<MotorSet>(1u << i);
        return s;
    }
};

class RecordingEvents final : public EventSink {
public:
    std::vector<std::pair<std::string, float>> events;
    void emit(const char* g, float v) override { events.emplace_back(g, v); }
    int count(const std::string& name) const
    {
        int n = 0;
        for (const auto& e : events) n += e.first == name ? 1 : 0;
        return n;
    }
};

struct Harness {
    std::unique_ptr<Scene> scene = makeBrailleScene();
    RecordingCanvas canvas;
    RecordingEvents events;
    std::vector<MotorSet> frames;   ///< motors on after each update

    explicit Harness(const std::string& text, std::uint64_t seed = 1)
    {
        REQUIRE(scene);
        SceneConfig c;
        c.text = text;
        c.seed = seed;
        c.resourceDir = std::string(ARMADILLO_SOURCE_DIR) + "/Resources";
        scene->prepare(c);
    }
    void set(int param, float value) { scene->setParameter(param, value); }
    void run(const Motion& m)
    {
        SceneOutput out {canvas, events};
        for (const ArmState& s : m.states) {
            ControlInput in;
            in.arm = s;
            in.dt = kDt;
            scene->control(in, out);
            frames.push_back(canvas.on());
        }
    }
    void idle(double seconds)
    {
        Motion m;
        m.hold(hanging(0), seconds);
        run(m);
    }
    /// Distinct motor sets in the order they came on (consecutive repeats merged).
    std::vector<MotorSet> shapes() const
    {
        std::vector<MotorSet> s;
        MotorSet prev = 0;
        for (MotorSet f : frames) {
            if (f != 0 && f != prev) s.push_back(f);
            prev = f;
        }
        return s;
    }
};

std::vector<MotorSet> rowsOf(const std::string& word)
{
    std::vector<MotorSet> rows;
    const BrailleDocument doc = translateText(word, {});
    for (const auto& sym : doc.messages.at(0).symbols)
        for (Dots c : sym.cells)
            for (int r = 0; r < 3; ++r)
                if (rowSensation(c, r) != 0) rows.push_back(rowSensation(c, r));
    return rows;
}
} // namespace

TEST_CASE("The braille scene is built and names its parameters", "[braille][scene]")
{
    auto scene = makeBrailleScene();
    REQUIRE(scene);
    CHECK(scene->name() == "braille");
    const auto params = scene->parameters();
    REQUIRE(params.size() == static_cast<std::size_t>(kParamCount));
    CHECK(params[kParamMode].id == "braille.mode");
    CHECK(params[kParamStep].defaultValue == 15.0f);
}

TEST_CASE("Reading a word by roll through the Scene API feels its rows and emits advances", "[braille][scene]")
{
    Harness h("men");
    Motion m;
    m.hold(hanging(0), 0.5);
    double r = 0.0;
    for (int i = 0; i < 9; ++i) {
        m.move(hanging(r), hanging(r + 16), 0.1);
        r += 16;
        m.hold(hanging(r), 0.5);
    }
    h.run(m);
    CHECK(h.events.count("advance") == 9);
    CHECK(h.shapes() == rowsOf("men"));   // M: 1,2,3 / - / 7   E: 1 / 6   N: 1,2,3 / 6 / 7
    // One more step past the end: the message-end cue on the underside line.
    Motion more;
    more.t = m.t;
    more.move(hanging(r), hanging(r + 16), 0.1);
    more.hold(hanging(r + 16), 0.8);
    h.frames.clear();
    h.run(more);
    CHECK(h.events.count("end") == 1);
    const MotorSet centre = motorBit(0, 1) | motorBit(1, 1) | motorBit(2, 1);
    CHECK(h.shapes() == std::vector<MotorSet> {centre, centre});
}

TEST_CASE("Changing reading posture gives the direction cue", "[braille][scene]")
{
    Harness h("a b");
    Motion m;
    m.hold(hanging(0), 0.3);
    m.move(hanging(0), hanging(16), 0.1);
    m.hold(hanging(16), 0.5);
    m.move(hanging(16), level(16), 1.0);
    m.hold(level(16), 1.0);
    h.run(m);
    CHECK(h.events.count("advance") == 1);
    REQUIRE(h.events.count("direction") == 1);
    // The cue sweeps the underside wrist → elbow for backward reading.
    const auto shapes = h.shapes();
    REQUIRE(shapes.size() >= 4);
    CHECK(std::vector<MotorSet>(shapes.end() - 3, shapes.end()) ==
          std::vector<MotorSet> {motorBit(0, 1), motorBit(1, 1), motorBit(2, 1)});
}

TEST_CASE("Passive mode draws the message with no movement, with adjustable timing", "[braille][scene]")
{
    Harness h("it is");
    h.set(kParamMode, 1.0f);
    h.set(kParamPassiveRepeat, 0.0f);
    h.idle(20.0);
    std::vector<MotorSet> expected = rowsOf("it");
    expected.push_back(motorBit(0, 1) | motorBit(1, 1) | motorBit(2, 1));   // word gap
    for (MotorSet s : rowsOf("is")) expected.push_back(s);
    // the end cue: two taps of the underside line
    expected.push_back(motorBit(0, 1) | motorBit(1, 1) | motorBit(2, 1));
    expected.push_back(motorBit(0, 1) | motorBit(1, 1) | motorBit(2, 1));
    CHECK(h.shapes() == expected);
    CHECK(h.events.count("advance") == 0);

    // Slower steps take longer: the last motor goes quiet later.
    auto lastOn = [](const Harness& x) {
        for (std::size_t i = x.frames.size(); i-- > 0;)
            if (x.frames[i] != 0) return i;
        return std::size_t {0};
    };
    Harness slow("it is");
    slow.set(kParamMode, 1.0f);
    slow.set(kParamPassiveRepeat, 0.0f);
    slow.set(kParamPassiveOn, 0.8f);
    slow.idle(20.0);
    CHECK(slow.shapes() == expected);
    CHECK(lastOn(slow) > lastOn(h) + 200);
}

TEST_CASE("Passive dot-by-dot drawing takes about three seconds a letter, as in §4.2.1", "[braille][scene]")
{
    Harness h("n");
    h.set(kParamMode, 1.0f);
    h.set(kParamMethod, 3.0f);   // dots
    h.set(kParamPassiveRepeat, 0.0f);
    h.set(kParamPassiveOn, 0.5f);
    h.set(kParamPassiveGap, 0.25f);
    h.idle(6.0);
    CHECK(h.shapes().size() == 4 + 2);   // four dots of N, then the two end taps
    std::size_t firstOn = 0, fourthOff = 0;
    int seen = 0;
    MotorSet prev = 0;
    for (std::size_t i = 0; i < h.frames.size(); ++i) {
        if (h.frames[i] != 0 && prev == 0 && seen++ == 0) firstOn = i;
        if (h.frames[i] == 0 && prev != 0 && seen == 4) fourthOff = i;
        prev = h.frames[i];
    }
    const double letterSeconds = static_cast<double>(fourthOff - firstOn) * kDt;
    CHECK(letterSeconds == Approx(2.75).margin(0.05));
}

TEST_CASE("Bad text is refused when the scene is prepared", "[braille][scene]")
{
    auto scene = makeBrailleScene();
    SceneConfig c;
    c.text = "snow \xE2\x98\x83";
    CHECK_THROWS_WITH(scene->prepare(c), Catch::Contains("U+2603"));
    c.text = "@/nonexistent/book.brf";
    CHECK_THROWS(scene->prepare(c));
    c.text = "   \t ";
    CHECK_THROWS_WITH(scene->prepare(c), Catch::Contains("nothing to read"));
}

TEST_CASE("Training mode takes answers from the app and logs them", "[braille][scene]")
{
    Harness h("unused", 3);
    h.set(kParamMode, 2.0f);
    auto* controls = dynamic_cast<BrailleSceneControls*>(h.scene.get());
    REQUIRE(controls);
    h.idle(0.5);
    REQUIRE(controls->submitAnswer("left"));
    h.idle(0.1);
    CHECK(h.events.count("answer") == 1);
    const std::string log = controls->trainingLogCsv();
    CHECK(log.find(",answer,") != std::string::npos);
    CHECK(log.find(",left,") != std::string::npos);
}

TEST_CASE("Training progress is published for a UI: trial, score, prompt and expected answer", "[braille][scene]")
{
    Harness h("unused", 3);
    h.set(kParamMode, 2.0f);
    auto* controls = dynamic_cast<BrailleSceneControls*>(h.scene.get());
    REQUIRE(controls);
    const int count = controls->trainingTrialCount();
    REQUIRE(count > 10);
    CHECK(controls->trainingTrial() == 0);
    CHECK(controls->trainingPrompt(0) == "left, right or both?");
    CHECK(controls->trainingPrompt(-1).empty());
    CHECK(controls->trainingPrompt(count).empty());
    CHECK(controls->trainingExpected(count).empty());
    h.idle(0.2);
    // One right answer, then one wrong: the trial moves on each time, the score only once.
    REQUIRE(controls->submitAnswer(controls->trainingExpected(0)));
    h.idle(0.1);
    CHECK(controls->trainingTrial() == 1);
    CHECK(controls->trainingCorrect() == 1);
    REQUIRE(controls->submitAnswer("not-an-answer"));
    h.idle(0.1);
    CHECK(controls->trainingTrial() == 2);
    CHECK(controls->trainingCorrect() == 1);
}

TEST_CASE("Grade and method are scene parameters, switched without re-preparing", "[braille][scene]")
{
    auto stepsToEnd = [](int grade, int method) {
        Harness h("the");
        h.set(kParamGrade, static_cast<float>(grade));
        h.set(kParamMethod, static_cast<float>(method));
        Motion m;
        m.hold(hanging(0), 0.3);
        double r = 0.0;
        for (int i = 0; i < 12 && h.events.count("end") == 0; ++i) {
            Motion s;
            s.t = m.t + i * 0.6;
            s.move(hanging(r), hanging(r + 16), 0.1);
            r += 16;
            s.hold(hanging(r), 0.5);
            h.run(s);
        }
        return h.events.count("advance");
    };
    CHECK(stepsToEnd(0, 0) == 3 * 3 + 1);   // Grade 1: t h e, three rows each, then the end
    CHECK(stepsToEnd(1, 0) == 1 * 3 + 1);   // Grade 2: one cell for "the"
    CHECK(stepsToEnd(0, 1) == 3 + 1);       // whole characters: one step each
    CHECK(stepsToEnd(0, 2) == 3 * 2 + 1);   // column pairs: two steps each
}

TEST_CASE("A held row repeats only when asked to", "[braille][scene]")
{
    auto pulsesWhileHolding = [](float repeat) {
        Harness h("a");
        h.set(kParamHoldRepeat, repeat);
        Motion m;
        m.hold(hanging(0), 0.3);
        m.move(hanging(0), hanging(16), 0.1);
        m.hold(hanging(16), 2.2);
        h.run(m);
        return h.shapes().size();   // consecutive pulses are separated by silence
    };
    CHECK(pulsesWhileHolding(0.0f) == 1);
    CHECK(pulsesWhileHolding(0.5f) == 5);   // at 0, 0.5, 1.0, 1.5, 2.0 s
}

TEST_CASE("In the training's hold stage a held row stays felt (thesis 4.4.1), elsewhere it does not repeat", "[braille][scene]")
{
    Harness h("unused", 3);
    h.set(kParamMode, 2.0f);
    auto* controls = dynamic_cast<BrailleSceneControls*>(h.scene.get());
    REQUIRE(controls);
    // Roll to the next row and hold it 2.4 s; count the separate pulses felt while holding.
    double roll = 0.0;
    auto pulsesWhileHolding = [&] {
        Motion m;
        m.t = h.frames.size() * kDt;
        m.move(hanging(roll), hanging(roll + 16), 0.1);
        roll += 16;
        m.hold(hanging(roll), 0.3);   // the step's own pulse (0.25 s) is over by now
        const std::size_t from = h.frames.size() + m.states.size();
        m.hold(hanging(roll), 2.4);
        h.run(m);
        int pulses = 0;
        for (std::size_t i = from; i < h.frames.size(); ++i)
            if (h.frames[i] != 0 && h.frames[i - 1] == 0) ++pulses;
        return pulses;
    };
    h.idle(0.3);
    // The first stage ("sides"): a held row is one pulse, as in reading.
    REQUIRE(controls->trainingPrompt(controls->trainingTrial()).find("left") != std::string::npos);
    CHECK(pulsesWhileHolding() == 0);
    // Answer the sides trials right until the hold stage begins.
    int guard = 0;
    while (controls->trainingPrompt(controls->trainingTrial()).find("hold") == std::string::npos && guard++ < 100) {
        REQUIRE(controls->submitAnswer(controls->trainingExpected(controls->trainingTrial())));
        h.idle(0.05);
    }
    REQUIRE(controls->trainingPrompt(controls->trainingTrial()).find("hold") != std::string::npos);
    h.idle(0.3);
    CHECK(pulsesWhileHolding() >= 2);   // repeats every 0.8 s while the row is held
}
