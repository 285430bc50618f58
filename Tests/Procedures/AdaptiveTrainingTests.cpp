// procedures::AdaptiveTraining through a scripted presenter: the script reads each trial's
// expectation from the session log's `trial` row (what a reader who reads the arm perfectly would
// know) and answers right, wrong, again or skip as it says; the stimuli on the motors, the prompts,
// the verdicts, the log and the reader profile are checked, and a session stopped early keeps its
// log and profile (docs/CHANGES.md, issue 32).
#include "Access/ReaderProfile.h"
#include "Common/ScratchDir.h"
#include "Core/AtomicFile.h"
#include "Procedures/AdaptiveTraining.h"
#include "ScriptedPresenter.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

using armadillo::procedures::AdaptiveChoices;
using armadillo::procedures::AdaptiveTraining;
using armadillo::test::ScriptedPlayerSide;
namespace acc = armadillo::access;

namespace {

constexpr int kUnderside = (1 << 1) | (1 << 4) | (1 << 7);
constexpr int kAll = 0x1FF;
constexpr int kOuter = kAll & ~kUnderside;

std::vector<std::vector<std::string>> csvRows(const std::string& text)
{
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> f(1);
        bool quoted = false;
        for (char c : line) {
            if (c == '"') quoted = ! quoted;
            else if (c == ',' && ! quoted) f.emplace_back();
            else f.back() += c;
        }
        rows.push_back(f);
    }
    return rows;
}

/// The "next" cue in a sequence of motor sets: the underside line swept wrist → elbow.
bool hasSweep(const std::vector<int>& sets)
{
    for (std::size_t i = 2; i < sets.size(); ++i)
        if (sets[i - 2] == (1 << 1) && sets[i - 1] == (1 << 4) && sets[i] == (1 << 7)) return true;
    return false;
}

/// The expectation of the newest trial, from the log the procedure writes.
std::string expectedNow(const AdaptiveTraining& training)
{
    std::string expected;
    for (const auto& r : csvRows(training.logText()))
        if (r.size() == 13 && r[1] == "trial") expected = r[4];
    return expected;
}

std::filesystem::path dir(const std::string& name)
{
    auto d = armadillo::test::scratchDir("procedures-training") / name;
    std::filesystem::create_directories(d);
    return d;
}

} // namespace

TEST_CASE("AdaptiveTraining: a scripted reader's session — prompts, stimuli, verdicts, log and profile", "[procedures][training]")
{
    acc::TactilePlayer player(armadillo::tactile::TactileConfig {}, 0.0);
    ScriptedPlayerSide side(player);
    AdaptiveTraining training(player);
    AdaptiveTraining::Options o;
    o.profilePath = (dir("session") / "reader.json").string();
    o.logPath = (dir("session") / "training.csv").string();
    o.trials = 5;
    o.stages = {"letters"};
    o.level = 5.0f;
    o.seed = 3;
    training.start(o);
    CHECK(training.session() == 1);
    CHECK(std::filesystem::exists(o.profilePath));   // refused now if it could not be written
    CHECK(std::filesystem::exists(o.logPath));

    enum class Say { Right, Wrong, AgainThenRight, Skip };
    const Say script[] = {Say::Right, Say::Wrong, Say::AgainThenRight, Say::Skip, Say::Right};
    int n = 0;
    for (const Say say : script) {
        ++n;
        side.clear();
        REQUIRE(side.runUntil([&] { return training.poll(); }));
        // The trial began with the "next" sweep (wrist → elbow on the underside line) and ended with
        // "your turn" (the underside line tapped).
        CHECK(hasSweep(side.sets()));
        CHECK(side.sets().back() == kUnderside);
        CHECK(training.question() == "which letter?");
        CHECK(training.prompt() == "Trial " + std::to_string(n) + " of 5: which letter?");
        const std::string expected = expectedNow(training);
        REQUIRE(! expected.empty());
        if (say == Say::AgainThenRight) {
            training.again();
            CHECK(training.state() == AdaptiveTraining::State::Drawing);
            CHECK(training.prompt().empty());   // no question while drawing
            side.clear();
            REQUIRE(side.runUntil([&] { return training.poll(); }));
            CHECK(side.sets().size() >= 3);
            CHECK(side.sets()[0] == (1 << 1));   // the trial again, from its "next" cue
            CHECK(side.sets()[2] == (1 << 7));
        }
        side.clear();
        std::string feedback;
        switch (say) {
        case Say::Right:
        case Say::AgainThenRight: feedback = training.answer(" " + expected + " ", 2.0); break;   // spaces do not count
        case Say::Wrong: feedback = training.answer("q", 2.0); break;
        case Say::Skip: feedback = training.skip(2.0); break;
        }
        const auto& v = training.lastVerdict();
        if (say == Say::Right || say == Say::AgainThenRight) {
            CHECK(v.correct);
            CHECK(v.text == "right");
        } else if (say == Say::Wrong) {
            CHECK_FALSE(v.correct);
            CHECK(v.text == "wrong: it was '" + expected + "', you said 'q'");
        } else {
            CHECK(v.skipped);
            CHECK(v.text == "skipped: it was '" + expected + "'");
        }
        CHECK(feedback.rfind(v.text, 0) == 0);
        // The feedback felt: all nine motors for right, the outer columns for wrong.
        REQUIRE(side.runUntil([&] { return ! side.sets().empty(); }));
        CHECK(side.sets().front() == (v.correct ? kAll : kOuter));
    }
    CHECK(training.state() == AdaptiveTraining::State::Done);
    CHECK(training.right() == 3);
    CHECK(training.answered() == 5);
    REQUIRE(side.runUntil([&] { return training.settled(); }));

    // The log on disk is the log in memory: one trial, answer and feedback row per trial, the
    // trial shown again has two "next" cues, rows carry their unit and step, one `end` (not stopped).
    CHECK(armadillo::core::readWholeFile(o.logPath) == training.logText());
    std::map<std::string, int> count, nextCues;
    for (const auto& r : csvRows(training.logText())) {
        REQUIRE(r.size() == 13);
        ++count[r[1]];
        if (r[1] == "cue" && r[5] == "next") ++nextCues[r[3]];
        if (r[1] == "row") CHECK(! r[8].empty());
        if (r[1] == "end") CHECK(r[11].empty());
    }
    CHECK(count["trial"] == 5);
    CHECK(count["answer"] == 5);
    CHECK(count["feedback"] == 5);
    CHECK(count["end"] == 1);
    CHECK(nextCues["3"] == 2);
    CHECK(nextCues["2"] == 1);
    // The profile: this session's answers, the skip as "(skipped)".
    const auto saved = acc::loadReaderProfile(o.profilePath);
    CHECK(saved.answers.size() >= 5);
    CHECK(std::count_if(saved.answers.begin(), saved.answers.end(), [](const auto& a) { return a.answer == "(skipped)"; }) == 1);
    REQUIRE(saved.sessions.size() == 1);
    CHECK(saved.sessions.back().method == "rows");
    const std::string summary = training.summaryJson(false);
    CHECK(summary.find("\"trials_done\":5") != std::string::npos);
    CHECK(summary.find("\"stopped\":false") != std::string::npos);
    CHECK(summary.find("\"correct\":3") != std::string::npos);
}

TEST_CASE("AdaptiveTraining: a session stopped early keeps every answer in its log and profile", "[procedures][training]")
{
    acc::TactilePlayer player(armadillo::tactile::TactileConfig {}, 0.0);
    ScriptedPlayerSide side(player);
    const std::string profile = (dir("stopped") / "reader.json").string();
    for (int session = 1; session <= 2; ++session) {
        AdaptiveTraining training(player);
        AdaptiveChoices c;
        c.trials = 12;
        c.stages = "letters";
        std::string why;
        REQUIRE(training.begin(profile, c, why));
        CHECK(training.logPath() == (dir("stopped") / ("reader-session" + std::to_string(session) + ".csv")).string());
        for (int k = 0; k < 3; ++k) {
            REQUIRE(side.runUntil([&] { return training.poll(); }));
            training.answer("a", 1.0);
        }
        training.stop();   // the reader stops: end of input, Ctrl-C, the window closed
        CHECK(training.state() == AdaptiveTraining::State::Idle);
        CHECK(training.answered() == 3);
        CHECK(training.summaryJson(true).find("\"trials_done\":3,\"stopped\":true") != std::string::npos);
        const auto rows = csvRows(armadillo::core::readWholeFile(training.logPath()));
        REQUIRE(! rows.empty());
        CHECK(rows.back()[1] == "end");
        CHECK(rows.back()[11] == "stopped");
        CHECK(std::count_if(rows.begin(), rows.end(), [](const auto& r) { return r.size() > 1 && r[1] == "answer"; }) == 3);
        const auto saved = acc::loadReaderProfile(profile);
        CHECK(std::count_if(saved.answers.begin(), saved.answers.end(), [&](const auto& a) { return a.session == session; }) >= 3);
        CHECK(static_cast<int>(saved.sessions.size()) == session);
        training.stop();   // twice: nothing more
        CHECK(armadillo::core::readWholeFile(training.logPath()) == training.logText());
    }
}

TEST_CASE("AdaptiveTraining: bad choices and unwritable files are refused before the first trial", "[procedures][training]")
{
    acc::TactilePlayer player(armadillo::tactile::TactileConfig {}, 0.0);
    AdaptiveTraining training(player);
    std::string why;
    AdaptiveChoices bad;
    bad.stages = "letters,hold";
    CHECK_FALSE(training.begin((dir("bad") / "r.json").string(), bad, why));
    CHECK(why.find("'hold'") != std::string::npos);
    CHECK_FALSE(training.begin((dir("bad") / "no/such/dir/r.json").string(), AdaptiveChoices {}, why));
    CHECK(training.state() == AdaptiveTraining::State::Idle);
    AdaptiveTraining::Options o;
    o.profilePath = (dir("bad") / "r2.json").string();
    o.method = "braille";
    CHECK_THROWS_AS(training.start(o), std::invalid_argument);
    o.method = "rows";
    o.logPath = (dir("bad") / "no/such/dir/log.csv").string();
    CHECK_THROWS(training.start(o));
    CHECK(training.state() == AdaptiveTraining::State::Idle);
}
