// The one-at-a-time answer feeder of live training (the CLI's and the app's), against the real
// braille scene through the Scene API, and against a fake scene for what the real one cannot
// be made to do on demand (a full answer queue).
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Braille/BrailleScene.h"
#include "Braille/TrainingFeeder.h"
#include "Common/RealtimeGuard.h"
#include "TestArm.h"
#include <catch2/catch.hpp>
#include <sstream>
#include <string>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::braille;
using namespace armadillo::braille::test;
using Kind = TrainingNotice::Kind;
using Refusal = TrainingAnswerFeeder::Refusal;

namespace {
class NullCanvas final : public MotorCanvas {
public:
    void setLevel(int, float) override {}
    void clearLevels() override {}
    void trigger(const PatternRequest&) override {}
    void stopVoice(int) override {}
};
class NullEvents final : public EventSink {
public:
    void emit(const char*, float) override {}
};

/// The braille scene in training mode, run by hand: control() happens only in idle().
struct TrainingScene {
    std::unique_ptr<Scene> scene = makeBrailleScene();
    BrailleSceneControls* controls = nullptr;
    NullCanvas canvas;
    NullEvents events;

    explicit TrainingScene(std::uint64_t seed)
    {
        SceneConfig c;
        c.seed = seed;
        c.resourceDir = std::string(ARMADILLO_SOURCE_DIR) + "/Resources";
        scene->prepare(c);
        scene->setParameter(kParamMode, 2.0f);
        controls = dynamic_cast<BrailleSceneControls*>(scene.get());
        REQUIRE(controls);
    }
    /// One control update with the arm's full state (orientation, gyro, accelerometer).
    void feed(const ArmState& arm)
    {
        SceneOutput out {canvas, events};
        ControlInput in;
        in.arm = arm;
        in.dt = kDt;
        scene->control(in, out);
    }
    void idle(int updates)
    {
        SceneOutput out {canvas, events};
        for (int i = 0; i < updates; ++i) {
            ControlInput in;
            in.arm.q = poseToQuaternion(hanging(0));
            in.arm.valid = true;
            in.dt = kDt;
            scene->control(in, out);
        }
    }
};

std::vector<Kind> kinds(const std::vector<TrainingNotice>& v)
{
    std::vector<Kind> k;
    for (const auto& n : v) k.push_back(n.kind);
    return k;
}

/// The answer column of the log's answer rows, in order.
std::vector<std::string> loggedAnswers(const std::string& csv)
{
    std::vector<std::string> answers;
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);   // the header has an "answer" column too
    while (std::getline(in, line)) {
        if (line.find(",answer,") == std::string::npos) continue;
        const auto last = line.rfind(','), before = line.rfind(',', last - 1);
        answers.push_back(line.substr(before + 1, last - before - 1));
    }
    return answers;
}

/// A scene whose answer queue can be made full.
class FakeScene final : public BrailleSceneControls {
public:
    bool full = false;
    std::vector<std::string> received;
    int trial = 0, correct = 0;
    bool submitAnswer(const std::string& a) noexcept override
    {
        if (full) return false;
        received.push_back(a);
        return true;
    }
    std::string trainingLogCsv() const override { return {}; }
    int trainingTrial() const noexcept override { return trial; }
    int trainingCorrect() const noexcept override { return correct; }
    int trainingTrialCount() const noexcept override { return 2; }
    std::string trainingPrompt(int i) const override { return "prompt " + std::to_string(i); }
    std::string trainingExpected(int i) const override { return "x" + std::to_string(i); }
};
} // namespace

TEST_CASE("Feeder: one answer at a time, each result belongs to its trial", "[braille][training][feeder]")
{
    TrainingScene s(3);
    TrainingAnswerFeeder feeder;
    auto n = feeder.poll(*s.controls);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Prompt});
    CHECK(n[0].trial == 0);
    CHECK(n[0].trialCount == s.controls->trainingTrialCount());
    CHECK(n[0].prompt == "left, right or both?");
    CHECK(feeder.poll(*s.controls).empty());   // announced once

    // Two answers typed before the first is scored: only the first goes to the scene.
    const std::string first = s.controls->trainingExpected(0);
    REQUIRE(feeder.add(first) == Refusal::None);
    REQUIRE(feeder.add("  zz \r\n") == Refusal::None);
    CHECK(feeder.poll(*s.controls).empty());
    CHECK(feeder.awaitingScore());
    CHECK(feeder.waiting() == 1);
    CHECK(feeder.poll(*s.controls).empty());   // not scored yet: nothing more handed over
    CHECK(feeder.waiting() == 1);

    s.idle(1);
    n = feeder.poll(*s.controls);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Result, Kind::Prompt});
    CHECK(n[0].trial == 0);
    CHECK(n[0].right);
    CHECK(n[0].answer == first);
    CHECK(n[0].correct == 1);
    CHECK(n[0].answered == 1);
    CHECK(resultText(n[0]) == "correct");
    CHECK(n[1].trial == 1);
    CHECK(n[1].prompt == s.controls->trainingPrompt(1));
    CHECK(feeder.waiting() == 0);   // the second answer went with that poll, for trial 2
    CHECK(feeder.awaitingScore());

    s.idle(1);
    n = feeder.poll(*s.controls);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Result, Kind::Prompt});
    CHECK_FALSE(n[0].right);
    CHECK(n[0].answer == "zz");
    CHECK(n[0].correct == 1);
    CHECK(resultText(n[0]) == "wrong, it was '" + s.controls->trainingExpected(1) + "'");
    CHECK(loggedAnswers(s.controls->trainingLogCsv()) == std::vector<std::string> {first, "zz"});
}

TEST_CASE("Feeder: a whole session to completion, the log holds exactly the answers typed", "[braille][training][feeder]")
{
    TrainingScene s(5);
    TrainingAnswerFeeder feeder;
    const int count = s.controls->trainingTrialCount();
    REQUIRE(count > 20);
    // Everything typed ahead at once (as a fast typist or a pasted file would), every fifth wrong.
    std::vector<std::string> typed;
    for (int i = 0; i < count; ++i) {
        typed.push_back(i % 5 == 2 ? std::string("\xC3\xA9t\xC3\xA9") : s.controls->trainingExpected(i));   // "été"
        REQUIRE(feeder.add(typed.back()) == Refusal::None);
    }
    std::vector<TrainingNotice> all;
    for (int round = 0; round < 4 * count && !feeder.finished(); ++round) {
        auto n = feeder.poll(*s.controls);
        all.insert(all.end(), n.begin(), n.end());
        s.idle(1);
    }
    REQUIRE(feeder.finished());
    int prompts = 0, results = 0, right = 0;
    for (const auto& n : all) {
        if (n.kind == Kind::Prompt) CHECK(n.trial == prompts++);
        if (n.kind == Kind::Result) {
            CHECK(n.trial == results);
            CHECK(n.answer == typed[static_cast<std::size_t>(results)]);
            CHECK(n.answered == results + 1);
            ++results;
            right += n.right ? 1 : 0;
            CHECK(n.correct == right);
        }
    }
    CHECK(prompts == count);
    CHECK(results == count);
    REQUIRE(all.back().kind == Kind::Complete);
    CHECK(all.back().correct == s.controls->trainingCorrect());
    CHECK(all.back().trialCount == count);
    CHECK(right == s.controls->trainingCorrect());
    CHECK(loggedAnswers(s.controls->trainingLogCsv()) == typed);   // unicode logged as typed
    CHECK(feeder.add("left") == Refusal::Finished);
    CHECK(feeder.poll(*s.controls).empty());
}

TEST_CASE("Feeder: bad answers are refused, with a reason, and never reach the scene", "[braille][training][feeder]")
{
    FakeScene scene;
    TrainingAnswerFeeder feeder;
    CHECK(feeder.add("") == Refusal::Empty);
    CHECK(feeder.add(" \t\r\n ") == Refusal::Empty);
    CHECK(feeder.add(std::string(TrainingAnswerFeeder::kMaxAnswerBytes + 1, 'a')) == Refusal::TooLong);
    CHECK(feeder.add(std::string(1 << 20, 'b')) == Refusal::TooLong);
    std::string e32;
    for (int i = 0; i < 32; ++i) e32 += "\xC3\xA9";   // 32 × "é" = 64 bytes
    CHECK(feeder.add(e32) == Refusal::TooLong);
    CHECK(feeder.add("\xE2\x82") == Refusal::NotUtf8);          // cut short
    CHECK(feeder.add("\xC0\xAF") == Refusal::NotUtf8);          // overlong '/'
    CHECK(feeder.add("\xED\xA0\x80") == Refusal::NotUtf8);      // a surrogate
    CHECK(feeder.add("\xF4\x90\x80\x80") == Refusal::NotUtf8);  // above U+10FFFF
    CHECK(feeder.add("a\tb") == Refusal::ControlCharacter);
    CHECK(feeder.add("a\nb") == Refusal::ControlCharacter);
    CHECK(feeder.add(std::string("a\0b", 3)) == Refusal::ControlCharacter);
    CHECK(feeder.waiting() == 0);
    for (auto r : {Refusal::Empty, Refusal::TooLong, Refusal::NotUtf8, Refusal::ControlCharacter, Refusal::Finished})
        CHECK_FALSE(TrainingAnswerFeeder::refusalText(r).empty());
    CHECK(TrainingAnswerFeeder::refusalText(Refusal::None).empty());

    // At the limit, and unicode (an e-acute is 2 bytes): accepted, handed over unchanged.
    CHECK(feeder.add(std::string(TrainingAnswerFeeder::kMaxAnswerBytes, 'a')) == Refusal::None);
    const std::string e31 = e32.substr(2);
    CHECK(feeder.add(e31) == Refusal::None);
    feeder.poll(scene);
    REQUIRE(scene.received.size() == 1);
    CHECK(scene.received[0].size() == TrainingAnswerFeeder::kMaxAnswerBytes);
    scene.trial = 1;
    feeder.poll(scene);
    REQUIRE(scene.received.size() == 2);
    CHECK(scene.received[1] == e31);
}

TEST_CASE("Feeder: a full answer queue keeps the answer waiting, handed over on a later poll", "[braille][training][feeder]")
{
    FakeScene scene;
    TrainingAnswerFeeder feeder;
    scene.full = true;
    REQUIRE(feeder.add("x0") == Refusal::None);
    CHECK(kinds(feeder.poll(scene)) == std::vector<Kind> {Kind::Prompt});
    CHECK(feeder.waiting() == 1);
    CHECK_FALSE(feeder.awaitingScore());
    scene.full = false;
    CHECK(feeder.poll(scene).empty());
    CHECK(scene.received == std::vector<std::string> {"x0"});
    scene.trial = 1;
    scene.correct = 1;
    auto n = feeder.poll(scene);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Result, Kind::Prompt});
    CHECK(n[0].right);
    CHECK(n[0].expected == "x0");

    // The scene was rebuilt (the app's engine changed): reset starts over at its trial 1.
    feeder.reset();
    FakeScene fresh;
    n = feeder.poll(fresh);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Prompt});
    CHECK(n[0].trial == 0);

    // Completion is reported once, then answers are refused.
    fresh.trial = 2;
    n = feeder.poll(fresh);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Complete});
    CHECK(n[0].trialCount == 2);
    CHECK(feeder.finished());
    CHECK(feeder.poll(fresh).empty());
    CHECK(feeder.add("x") == Refusal::Finished);
}

namespace {
/// The hanging arm rolled by `rollDeg`, turning at `rollRate` rad/s about the forearm, with an
/// extra acceleration `push` m/s² along it: the accelerometer is gravity (+g up, as the arm
/// tracker gives it) plus the push, in the device frame (x = the forearm axis).
ArmState hangingArm(double rollDeg, double rollRate, double push)
{
    ArmState a;
    a.q = poseToQuaternion(hanging(rollDeg));
    a.gyro = Eigen::Vector3d(rollRate, 0.0, 0.0);
    a.accel = a.q.conjugate() * Eigen::Vector3d(0.0, 9.80665, 0.0) + Eigen::Vector3d(push, 0.0, 0.0);
    a.valid = true;
    return a;
}

/// A push along the forearm (6 cm out in 0.2 s and back, minimum jerk) at roll `rollDeg`.
void pushArm(TrainingScene& s, double rollDeg)
{
    for (int i = 0; i < 80; ++i) {
        const double u = (i % 40) / 40.0, a = 0.06 / 0.04 * (60.0 * u - 180.0 * u * u + 120.0 * u * u * u);
        s.feed(hangingArm(rollDeg, 0.0, i < 40 ? a : -a));
    }
    for (int i = 0; i < 100; ++i) s.feed(hangingArm(rollDeg, 0.0, 0.0));
}

/// Rolls by `steps` steps of 16° (0.2 s each, ≈ 1.4 rad/s), a still moment after each.
double rollArm(TrainingScene& s, double roll, int steps)
{
    for (int i = 0; i < steps; ++i) {
        for (int k = 1; k <= 40; ++k) s.feed(hangingArm(roll + 16.0 * k / 40.0, 1.4, 0.0));
        roll += 16.0;
        for (int k = 0; k < 60; ++k) s.feed(hangingArm(roll, 0.0, 0.0));
    }
    return roll;
}
} // namespace

TEST_CASE("Feeder: 'here' answered by a push of the arm in the hold stage, logged as a gesture", "[braille][training][feeder][push]")
{
    TrainingScene s(7);
    TrainingAnswerFeeder feeder;
    feeder.poll(*s.controls);
    for (int i = 0; i < 100; ++i) s.feed(hangingArm(0.0, 0.0, 0.0));
    // A push outside the hold stage answers nothing.
    REQUIRE(s.controls->trainingExpected(0) != "here");
    pushArm(s, 0.0);
    CHECK(s.controls->trainingTrial() == 0);
    CHECK(s.controls->trainingArmAnswers() == 0);
    // The sides trials typed; then the first hold trial.
    int hold = 0;
    while (s.controls->trainingExpected(hold) != "here") REQUIRE(feeder.add(s.controls->trainingExpected(hold++)) == Refusal::None);
    for (int round = 0; round < 100 && s.controls->trainingTrial() < hold; ++round) {
        feeder.poll(*s.controls);
        s.feed(hangingArm(0.0, 0.0, 0.0));
    }
    REQUIRE(s.controls->trainingTrial() == hold);
    CHECK(kinds(feeder.poll(*s.controls)).back() == Kind::Prompt);
    const std::string prompt = s.controls->trainingPrompt(hold);
    REQUIRE(prompt.rfind("stop on row ", 0) == 0);
    const int row = prompt[12] - '0';

    double roll = rollArm(s, 0.0, 3 + row);   // one full cell, then the asked row of the next
    pushArm(s, roll);
    auto n = feeder.poll(*s.controls);
    REQUIRE(kinds(n) == std::vector<Kind> {Kind::Result, Kind::Prompt});
    CHECK(n[0].byArm);
    CHECK(n[0].trial == hold);
    CHECK(n[0].answer == "here");
    CHECK(n[0].right);
    CHECK(resultText(n[0]) == "correct (here, by the arm)");
    CHECK(n[1].trial == hold + 1);

    // The next hold trial: stopped a row short, the push is scored wrong.
    const int row2 = s.controls->trainingPrompt(hold + 1)[12] - '0';
    roll = rollArm(s, roll, 3 + (row2 % 3) + 1 + (3 - row));   // to the next cell's start, then a wrong row
    pushArm(s, roll);
    n = feeder.poll(*s.controls);
    REQUIRE_FALSE(n.empty());
    CHECK(n[0].byArm);
    CHECK_FALSE(n[0].right);
    CHECK(resultText(n[0]) == "wrong, it was 'here' (here, by the arm)");

    // The log: a gesture row ("push") right before each arm answer, same trial and time.
    std::istringstream log(s.controls->trainingLogCsv());
    std::vector<std::string> rows;
    for (std::string l; std::getline(log, l);) rows.push_back(l);
    int gestures = 0;
    for (std::size_t i = 0; i + 1 < rows.size(); ++i)
        if (rows[i].find(",gesture,hold,") != std::string::npos) {
            ++gestures;
            CHECK(rows[i].substr(rows[i].size() - 6) == ",push,");
            CHECK(rows[i + 1].find(",answer,hold,") != std::string::npos);
            CHECK(rows[i].substr(0, rows[i].find(',')) == rows[i + 1].substr(0, rows[i + 1].find(',')));
        }
    CHECK(gestures == 2);
    CHECK(loggedAnswers(s.controls->trainingLogCsv()).back() == "here");
}

TEST_CASE("The scene's control in training stays real-time: typed answers, a push's answer, a trial restarted", "[braille][training][realtime]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the probe catches an allocation before a zero is trusted
        int* volatile p = new int(5);
        CHECK(probe.allocations() >= 1);
        delete p;
    }
    TrainingScene s(7);
    for (int i = 0; i < 10; ++i) s.feed(hangingArm(0.0, 0.0, 0.0));
    int hold = 0;
    while (s.controls->trainingExpected(hold) != "here") ++hold;
    std::uint64_t allocations = 0, locks = 0;
    auto guarded = [&](const ArmState& a) {
        RealtimeGuard guard;
        s.feed(a);
        allocations += guard.allocations();
        locks += guard.locks();
    };
    for (int i = 0; i < hold; ++i) {   // (submitted from this thread, outside the guard)
        REQUIRE(s.controls->submitAnswer(s.controls->trainingExpected(i)));
        guarded(hangingArm(0.0, 0.0, 0.0));
        s.controls->collectTrainingLog();
    }
    REQUIRE(s.controls->trainingTrial() == hold);
    s.controls->restartTrainingTrial();
    for (int i = 0; i < 100; ++i) guarded(hangingArm(0.0, 0.0, 0.0));
    for (int i = 0; i < 80; ++i) {   // the push (as pushArm), each update guarded
        const double u = (i % 40) / 40.0, a = 0.06 / 0.04 * (60.0 * u - 180.0 * u * u + 120.0 * u * u * u);
        guarded(hangingArm(0.0, 0.0, i < 40 ? a : -a));
    }
    for (int i = 0; i < 100; ++i) guarded(hangingArm(0.0, 0.0, 0.0));
    CHECK(s.controls->trainingArmAnswers() == 1);
    CHECK(s.controls->trainingTrial() == hold + 1);
    CHECK(allocations == 0);
    CHECK(locks == 0);
}
