// procedures::TouchTest through a scripted presenter: a reader with hidden thresholds answers each
// "felt it?" by the level that reached the stimulated motor (after the tactile engine and safety
// stage), and "comfortable?" two levels above the threshold. The prompts, the stimuli (one motor,
// soft, never the same motor twice in a row), the profile and the file it writes are checked.
#include "Core/AtomicFile.h"
#include "Common/ScratchDir.h"
#include "Link/TouchProfile.h"
#include "Procedures/TouchTest.h"
#include "ScriptedPresenter.h"
#include <catch2/catch.hpp>
#include <filesystem>
#include <regex>

using armadillo::procedures::TouchTest;
using armadillo::test::ScriptedPlayerSide;

namespace {

struct Script {
    std::array<int, 9> hidden {};
    std::vector<std::string> prompts;
    std::vector<int> motors;   // the stimulated motor of each prompt (as the motors felt it)
    int againAt = -1;          // the prompt answered "again" once
};

/// Runs a whole test; returns false when the procedure stopped asking before Done.
bool run(TouchTest& test, ScriptedPlayerSide& side, Script& script)
{
    while (test.state() != TouchTest::State::Done) {
        side.clear();
        if (! side.runUntil([&] { return test.poll(); })) return false;
        REQUIRE(test.state() == TouchTest::State::Asking);
        script.prompts.push_back(test.question());
        // The stimulus reached exactly one motor: the one asked about.
        int felt = -1, level = 0;
        for (int m = 0; m < 9; ++m)
            if (side.highest()[static_cast<std::size_t>(m)] > 0) {
                CHECK(felt == -1);
                felt = m;
                level = side.highest()[static_cast<std::size_t>(m)];
            }
        CHECK(felt == test.motor());
        script.motors.push_back(felt);
        if (static_cast<int>(script.prompts.size()) == script.againAt) {
            const int motor = test.motor(), asked = test.level();
            test.again();
            CHECK(test.state() == TouchTest::State::Presenting);
            side.clear();
            REQUIRE(side.runUntil([&] { return test.poll(); }));
            CHECK(test.motor() == motor);   // the same stimulus again
            CHECK(test.level() == asked);
            CHECK(side.highest()[static_cast<std::size_t>(motor)] > 0);
        }
        const int t = script.hidden[static_cast<std::size_t>(felt < 0 ? 0 : felt)];
        test.answer(test.comfortStep() ? level >= t + 2 : level >= t);
    }
    return true;
}

} // namespace

TEST_CASE("TouchTest: a scripted reader's nine thresholds within one level, the comfort level, the profile written", "[procedures][touch]")
{
    TouchTest test;
    ScriptedPlayerSide side(test.player());
    Script script;
    script.hidden = {2, 5, 9, 3, 7, 12, 4, 6, 10};
    script.againAt = 5;
    test.begin(3);
    REQUIRE(run(test, side, script));

    const auto profile = test.profile();
    for (std::size_t m = 0; m < 9; ++m) {
        INFO("motor m" << m + 1);
        CHECK(std::abs(profile.threshold[m] - script.hidden[m]) <= 1);
    }
    CHECK(profile.comfort == script.hidden[4] + 2);   // the first level two above m5's threshold
    CHECK(profile.stimuli == test.stimuli());
    CHECK(profile.stimulusSeconds == Approx(test.stimuli() * (TouchTest::kOnSeconds + TouchTest::kGapSeconds)));

    // The prompts: "motor mK, level L: felt it?" for the thresholds, then "…: comfortable?" on m5,
    // ascending one level a step; no motor twice in a row while measuring thresholds.
    const std::regex felt(R"(motor m([1-9]), level ([0-9]+): felt it\?)"), comfortable(R"(motor m5, level ([0-9]+): comfortable\?)");
    std::size_t firstComfort = script.prompts.size();
    for (std::size_t i = 0; i < script.prompts.size(); ++i)
        if (std::regex_match(script.prompts[i], comfortable)) {
            firstComfort = i;
            break;
        }
    REQUIRE(firstComfort < script.prompts.size());
    for (std::size_t i = 0; i < firstComfort; ++i) {
        INFO(script.prompts[i]);
        std::smatch m;
        REQUIRE(std::regex_match(script.prompts[i], m, felt));
        CHECK(std::stoi(m[1]) == script.motors[i] + 1);
        if (i > 0) CHECK(script.motors[i] != script.motors[i - 1]);
    }
    for (std::size_t i = firstComfort; i < script.prompts.size(); ++i) {
        std::smatch m;
        REQUIRE(std::regex_match(script.prompts[i], m, comfortable));
        CHECK(std::stoi(m[1]) == profile.threshold[4] + 1 + static_cast<int>(i - firstComfort));
    }

    // The file and the summary both presenters give.
    const std::string path = (armadillo::test::scratchDir("procedures-touch") / "profile.json").string();
    test.save(path);
    const auto back = armadillo::link::loadTouchProfile(path);
    CHECK(back.threshold == profile.threshold);
    CHECK(back.comfort == profile.comfort);
    CHECK(test.summaryJson().rfind("{\"stimuli\":" + std::to_string(test.stimuli()) + ",", 0) == 0);
    CHECK(test.summary().find("comfortable level " + std::to_string(profile.comfort)) != std::string::npos);
}

TEST_CASE("TouchTest: a seed fixes the order; --no-comfort ends with the thresholds; cancel keeps nothing", "[procedures][touch]")
{
    auto order = [](std::uint64_t seed, bool comfort, int& comfortPrompts) {
        TouchTest test;
        ScriptedPlayerSide side(test.player());
        Script script;
        script.hidden.fill(6);
        test.begin(seed, comfort);
        REQUIRE(run(test, side, script));
        comfortPrompts = static_cast<int>(std::count_if(script.prompts.begin(), script.prompts.end(),
                                                        [](const std::string& p) { return p.find("comfortable") != std::string::npos; }));
        if (! comfort) CHECK(test.profile().comfort == 0);
        return script.motors;
    };
    int c1 = 0, c2 = 0, c3 = 0;
    const auto a = order(9, true, c1), b = order(9, true, c2), quick = order(9, false, c3);
    CHECK(a == b);
    CHECK(c1 > 0);
    CHECK(c3 == 0);
    CHECK(std::vector<int>(a.begin(), a.begin() + static_cast<long>(quick.size())) == quick);   // the same thresholds, no comfort step

    TouchTest cancelled;
    cancelled.begin(1);
    CHECK(cancelled.state() == TouchTest::State::Presenting);
    cancelled.cancel();
    CHECK(cancelled.state() == TouchTest::State::Idle);
    CHECK(cancelled.question().empty());
}
