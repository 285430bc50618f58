// The tactile output of a full reading, through the real TactileEngine (shaping + safety stage),
// checked against the overheating rules of ARMADILLO.md §6 / thesis §3.2.3.
#include "Braille/BrailleScene.h"
#include "Braille/Sensations.h"
#include "Tactile/TactileEngine.h"
#include "TestArm.h"
#include <catch2/catch.hpp>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;
using namespace armadillo::braille;
using namespace armadillo::braille::test;

namespace {
class CountingEvents final : public EventSink {
public:
    int advances = 0;
    void emit(const char* g, float) override { advances += std::string(g) == "advance"; }
};

struct Outcome {
    std::vector<MotorLevels> packets;   ///< one per control update, each on for kDt
    int advances = 0;
};

Outcome drive(const Motion& m, const std::vector<std::pair<int, float>>& params, const std::string& text,
              ArmSide side = ArmSide::Right)
{
    auto scene = makeBrailleScene();
    SceneConfig c;
    c.text = text;
    c.resourceDir = std::string(ARMADILLO_SOURCE_DIR) + "/Resources";
    scene->prepare(c);
    for (const auto& [i, v] : params) scene->setParameter(i, v);
    TactileEngine te;
    TactileConfig tc;
    tc.side = side;
    te.prepare(tc);
    CountingEvents events;
    SceneOutput out {te, events};
    Outcome o;
    for (const ArmState& s : m.states) {
        ControlInput in;
        in.arm = s;
        in.dt = kDt;
        scene->control(in, out);
        o.packets.push_back(te.tick(kDt));
    }
    o.advances = events.advances;
    return o;
}

/// The three bounds, checked on every motor over every window of the output.
void checkSafety(const std::vector<MotorLevels>& packets)
{
    const std::size_t n = packets.size();
    const std::size_t w2 = static_cast<std::size_t>(2.0 * kRate), w10 = static_cast<std::size_t>(10.0 * kRate);
    bool anyOn = false;
    for (int m = 0; m < kGridMotors; ++m) {
        std::vector<double> above(n + 1, 0.0), power(n + 1, 0.0);
        double run = 0.0, longest = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const int level = packets[i][static_cast<std::size_t>(m)];
            anyOn = anyOn || level > 0;
            const bool hot = level > kRatedLevel;
            run = hot ? run + kDt : 0.0;
            longest = std::max(longest, run);
            above[i + 1] = above[i] + (hot ? kDt : 0.0);
            power[i + 1] = power[i] + (level / 15.0) * (level / 15.0) * kDt;
        }
        INFO("motor " << m + 1);
        CHECK(longest <= 0.300 + 1e-9);
        double worstDuty = 0.0, worstPower = 0.0;
        for (std::size_t i = 0; i + w2 <= n; ++i) worstDuty = std::max(worstDuty, (above[i + w2] - above[i]) / 2.0);
        for (std::size_t i = 0; i + w10 <= n; ++i) worstPower = std::max(worstPower, (power[i + w10] - power[i]) / 10.0);
        CHECK(worstDuty <= 0.30 + 1e-9);
        CHECK(worstPower <= (5.0 / 15.0) * (5.0 / 15.0) + 1e-9);
    }
    CHECK(anyOn);
}

/// Reads `rows` rows forward (hanging arm) then `rows` backward (level arm), one step every
/// `period` s: a brisk reader scrubbing the word.
Motion scrub(int rows, double period)
{
    Motion m;
    m.hold(hanging(0), 0.5);
    double r = 0.0;
    for (int i = 0; i < rows; ++i) {
        m.move(hanging(r), hanging(r + 16), 0.05);
        r += 16;
        m.hold(hanging(r), period - 0.05);
    }
    m.move(hanging(r), level(r), 1.0);   // raising the arm: the roll stays where it was
    for (int i = 0; i < rows; ++i) {
        m.move(level(r), level(r - 16), 0.05);
        r -= 16;
        m.hold(level(r), period - 0.05);
    }
    m.hold(level(r), 2.0);
    return m;
}
} // namespace

TEST_CASE("A full reading of a sign word never breaks the safety bounds", "[braille][safety]")
{
    const int rows = 8 * 3 + 1;   // ENTRANCE and the end cue
    SECTION("at the default level, reading at a deliberate pace")
    {
        const Outcome o = drive(scrub(rows, 0.5), {}, "entrance");
        CHECK(o.advances == 2 * rows);
        checkSafety(o.packets);
    }
    SECTION("at full level, scrubbing fast, with held steps repeating")
    {
        const Outcome o = drive(scrub(rows, 0.2), {{kParamLevel, 15.0f}, {kParamPulse, 2.0f}, {kParamHoldRepeat, 0.3f}}, "entrance");
        CHECK(o.advances == 2 * rows);
        checkSafety(o.packets);
    }
    SECTION("passive drawing repeated for a minute at full level")
    {
        Motion m;
        m.hold(hanging(0), 60.0);
        const Outcome o = drive(m, {{kParamMode, 1.0f}, {kParamLevel, 15.0f}, {kParamPassiveOn, 2.0f}, {kParamPassiveRepeat, 0.5f}}, "entrance");
        checkSafety(o.packets);
    }
}

TEST_CASE("Through the real tactile engine every row of a word reaches its motors", "[braille][safety]")
{
    // The row sensations must survive shaping and the safety stage: at the default level a
    // deliberate reader feels exactly the motors of each row, the serif included.
    Motion m;
    m.hold(hanging(0), 0.5);
    double r = 0.0;
    for (int i = 0; i < 12; ++i) {
        m.move(hanging(r), hanging(r + 16), 0.05);
        r += 16;
        m.hold(hanging(r), 0.6);
    }
    const Outcome o = drive(m, {}, "exit");
    REQUIRE(o.advances == 12);
    std::vector<std::string> felt;
    MotorSet prev = 0;
    for (const MotorLevels& p : o.packets) {
        MotorSet on = 0;
        for (int k = 0; k < kGridMotors; ++k)
            if (p[static_cast<std::size_t>(k)] > 0) on |= static_cast<MotorSet>(1u << k);
        if (on != 0 && on != prev) felt.push_back(motorList(on));
        prev = on;
    }
    // e: 1 / 6 / -   x: 1,2,3 / - / 7,8,9   i: 3 / 4 / -   t: 3 / 4,5,6 / 7
    CHECK(felt == std::vector<std::string> {"1", "6", "1,2,3", "7,8,9", "3", "4", "3", "4,5,6", "7"});

    // Worn on the left arm the engine mirrors the columns: the scene itself does not change.
    const Outcome left = drive(m, {}, "exit", ArmSide::Left);
    std::vector<std::string> feltLeft;
    prev = 0;
    for (const MotorLevels& p : left.packets) {
        MotorSet on = 0;
        for (int k = 0; k < kGridMotors; ++k)
            if (p[static_cast<std::size_t>(k)] > 0) on |= static_cast<MotorSet>(1u << k);
        if (on != 0 && on != prev) feltLeft.push_back(motorList(on));
        prev = on;
    }
    CHECK(feltLeft == std::vector<std::string> {"3", "4", "1,2,3", "7,8,9", "1", "6", "1", "4,5,6", "9"});
}
