// What a reader training alone gets from the core beyond the adaptive plan (issue 26): the
// deafblind feedback sequence (the right cell again, then the "next" cue), the arm gestures read
// by the tactile player on its control thread, the §4.4.1 answers added to a reader profile, and
// the session log's rows. Expected motor sets come from the braille cell definitions written out
// here (dots 1-2-3 the left column, 4-5-6 the right; row r = dots r+1 and r+4; left dot on grid
// column 0, right on column 2, index = 3·row + col), never from the code under test.
#include "Access/Feedback.h"
#include "Access/ProfileRecorder.h"
#include "Access/SessionLog.h"
#include "Access/TactilePlayer.h"
#include "Common/RealtimeGuard.h"
#include "Core/Errors.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;
using namespace armadillo::access;
using armadillo::test::RealtimeGuard;

namespace {
constexpr std::uint16_t bit(int row, int col) { return static_cast<std::uint16_t>(1u << (3 * row + col)); }
}

TEST_CASE("deafblind feedback: wrong, then the right cell again, then the next cue, never overlapping", "[access][feedback]")
{
    // 'e' = dots 1 and 5: row 0 the left dot, row 1 the right dot, row 2 empty (a pause).
    const auto s = feedbackSequence(false, "e", 10.0f);
    // The wrong sensation (3 buzzes, 0.5 s) and its 0.6 s pause; the cell from 1.1 s, rows 0.6 s apart.
    REQUIRE(s.size() == 3 + 2 + 3);
    const double cellStart = 0.5 + feedbackPause(false);
    CHECK(s[3].at == Approx(cellStart));
    CHECK(s[3].motors == bit(0, 0));
    CHECK(s[4].at == Approx(cellStart + 0.6));
    CHECK(s[4].motors == bit(1, 2));
    // The "next" cue: the underside line wrist → elbow, after the cell (3 rows: 0.4+0.2+0.4+0.2+0.4+0.5)
    // and half a second of stillness.
    const double cue = cellStart + 2.1 + 0.5;
    for (int r = 0; r < 3; ++r) {
        CHECK(s[static_cast<std::size_t>(5 + r)].motors == bit(r, 1));
        CHECK(s[static_cast<std::size_t>(5 + r)].at == Approx(cue + 0.1 * r));
    }
    // Nothing overlaps: each segment starts after the one before has ended.
    for (std::size_t i = 1; i < s.size(); ++i) CHECK(s[i].at >= s[i - 1].at + s[i - 1].duration - 1e-9);

    // Right: no cell, the cue after the hum and its pause. Not letters (a side, "here!"): no cell.
    const auto r = feedbackSequence(true, "e", 10.0f);
    REQUIRE(r.size() == 1 + 3);
    CHECK(r[1].at == Approx(0.4 + feedbackPause(true)));
    CHECK(feedbackSequence(false, "here!", 10.0f).size() == 3 + 3);
    CHECK(feedbackSequence(false, "", 10.0f).size() == 3 + 3);

    // Played: the cell's first row is felt alone on its motor while it is on.
    TactilePlayer p(TactileConfig {}, 0.005);
    p.play(s, 0.0);
    int aloneOnM1 = 0;
    for (int i = 0; i < 2000 && p.completed() < 1; ++i) {
        const double t = p.clock();
        const auto levels = p.onPacket(0.0);
        if (t > cellStart + 0.05 && t < cellStart + 0.35) {
            aloneOnM1 += levels[0] > 0;
            for (int m = 1; m < 9; ++m) CHECK(levels[static_cast<std::size_t>(m)] == 0);
        }
    }
    CHECK(p.completed() == 1);
    CHECK(aloneOnM1 > 50);
}

TEST_CASE("tactile player: the roll rate it is given is read for twists, with no allocation", "[player][gestures][realtime]")
{
    ARMADILLO_REQUIRE_GUARD_SEES_ALLOCATION();
    TactilePlayer p(TactileConfig {}, 0.005);
    auto twist = [](double t, double start) { return t >= start && t < start + 0.3 ? 6.0 * std::sin(2.0 * kPi * (t - start) / 0.3) : 0.0; };
    std::uint64_t allocations = 0;
    double t = 0.0;
    for (; t < 3.0; t += 0.005) {
        RealtimeGuard guard;
        (void) p.onPacket(t, twist(t, 0.5));
        allocations += guard.allocations();
    }
    CHECK(p.repeats() == 1);
    CHECK(p.skips() == 0);
    for (; t < 6.0; t += 0.005) (void) p.onPacket(t, twist(t, 3.5) + twist(t, 4.0));
    CHECK(p.repeats() == 1);
    CHECK(p.skips() == 1);
    for (; t < 8.0; t += 0.005) (void) p.onPacket(t);   // no roll rate given: nothing read
    CHECK(p.repeats() == 1);
    CHECK(allocations == 0);
}

TEST_CASE("profile recorder: the §4.4.1 answers become one session of the reader profile, saved after each", "[adaptive][recorder]")
{
    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/recorder-reader.json";
    std::remove(path.c_str());
    {
        ProfileRecorder r(path, "rows", "2026-01-01T00:00:00Z");
        CHECK(r.session() == 1);
        CHECK(loadReaderProfile(path).sessions.size() == 1);   // saved at once
        r.record("sides", "left", "Right", false, 2.5, 3.0);
        r.record("letters", "e", "e", true, 1.25, 7.5);
        const auto saved = loadReaderProfile(path);   // saved after every answer
        REQUIRE(saved.answers.size() == 2);
        CHECK(saved.answers[0].stage == "sides");
        CHECK(saved.answers[0].answer == "right");   // lower case, as the log
        CHECK_FALSE(saved.answers[0].correct);
        CHECK(saved.answers[1].correct);
        CHECK(saved.answers[1].rt == Approx(1.25));
        CHECK(saved.answers[1].session == 1);
        CHECK(saved.sessions.back().seconds == Approx(7.5));
    }
    ProfileRecorder second(path, "rows", "2026-01-02T00:00:00Z");
    CHECK(second.session() == 2);
    second.record("hold", "here", "here", true, -1.0, 1.0);
    // Another session saves the file meanwhile (the app's adaptive training): nothing is lost.
    auto other = loadReaderProfile(path);
    other.sessions.push_back({3, "2026-01-02T00:05:00Z", "dots", 60.0});
    other.answers.push_back({3, "letters", "dots", "k", "k", true, 1.0, 2.0});
    saveReaderProfile(path, other);
    second.record("letters", "e", "i", false, 2.0, 90.0);
    const auto saved = loadReaderProfile(path);
    CHECK(saved.answers.size() == 5);
    CHECK(saved.sessions.size() == 3);
    CHECK(saved.answers[3].session == 3);
    CHECK(saved.answers[4].session == 2);
    CHECK(saved.sessions[1].seconds == Approx(90.0));
    std::remove(path.c_str());
    CHECK_THROWS(ProfileRecorder("/nonexistent-dir/reader.json", "rows", "x"));
}

TEST_CASE("session log: a row has the §4.4.1 log's thirteen columns", "[adaptive][log]")
{
    PlannedTrial trial {"letters", "e", "e", "which letter?"};
    std::string log;
    appendSessionLogRow(log, 1.5, "answer", &trial, 3, "", -1, 0, 0, false, "i", 0);
    CHECK(log == "1.5,answer,letters,3,e,,,,,,,i,0\n");
    log.clear();
    appendSessionLogRow(log, 2.0, "row", &trial, 3, "", 0, 1, static_cast<braille::MotorSet>(bit(1, 2)), true, "", -1);
    CHECK(log == "2,row,letters,3,e,,,,1,2,6,,\n");
    log.clear();
    appendSessionLogRow(log, 0.25, "gesture", &trial, 3, "", -1, 0, 0, false, "two twists", -1);
    CHECK(log == "0.25,gesture,letters,3,e,,,,,,,two twists,\n");
    CHECK(std::string(kSessionLogHeader) == "t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct\n");
}

TEST_CASE("tactile player: the reader's touch profile scales each motor's level before the engine", "[player]")
{
    TactilePlayer p(TactileConfig {}, 0.005);
    auto gains = TactileConfig::unitMotorGains();
    gains[0] = 1.5f;    // m1 felt weakly: raised
    gains[2] = 0.5f;    // m3 felt strongly: lowered
    gains[4] = -1.0f;   // refused: counts as 1
    p.setMotorGains(gains);
    TactileSegment s;
    s.duration = 0.3;
    s.motors = bit(0, 0) | bit(0, 2) | bit(1, 1);   // motors m1, m3, m5
    s.level = 6.0f;
    s.soft = true;   // no jump-start spike: the level asked is the level sent
    p.play({s}, 0.0);
    for (int i = 0; i < 200 && p.completed() < 1; ++i) (void) p.onPacket(0.0);
    REQUIRE(p.completed() == 1);
    CHECK(p.maxLevel(0) == 9);   // 6 × 1.5
    CHECK(p.maxLevel(2) == 3);   // 6 × 0.5
    CHECK(p.maxLevel(4) == 6);
    gains.fill(1.0f);
    gains[1] = 4.0f;   // clamped to the top level (the safety stage still has the last word)
    p.setMotorGains(gains);
    s.motors = bit(0, 1);
    p.play({s}, 0.0);
    for (int i = 0; i < 200 && p.completed() < 2; ++i) (void) p.onPacket(0.0);
    CHECK(p.maxLevel(1) <= 15);
    CHECK(p.maxLevel(1) >= 14);
}
