#include "Braille/Reading.h"
#include "Braille/RollReader.h"
#include "TestArm.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::braille;
using namespace armadillo::braille::test;

namespace {
struct Tally {
    int advances = 0, forward = 0, backward = 0, directionChanges = 0;
    std::vector<double> advanceTimes;
};

Tally run(RollReader& reader, const Motion& m)
{
    Tally t;
    for (const ArmState& s : m.states) {
        const RollUpdate u = reader.update(s);
        if (u.directionChanged) ++t.directionChanges;
        if (u.advanced) {
            ++t.advances;
            (u.posture == ReadingPosture::Forward ? t.forward : t.backward)++;
            t.advanceTimes.push_back(s.t);
        }
    }
    return t;
}

/// Rolls in `steps` steps of `stepDeg` from `roll0`, each step taking 0.15 s and then held 0.35 s
/// (a slow, deliberate reader), with the pose given by `pose(roll)`.
template <typename PoseOf>
void rollSteps(Motion& m, PoseOf pose, double roll0, double stepDeg, int steps)
{
    double r = roll0;
    for (int i = 0; i < steps; ++i) {
        m.move(pose(r), pose(r + stepDeg), 0.15);
        r += stepDeg;
        m.hold(pose(r), 0.35);
    }
}
} // namespace

TEST_CASE("Posture zones: within 30 deg of vertical forward, of horizontal backward, else invalid", "[braille][roll]")
{
    const RollReaderParams p;
    auto axisOf = [](const Pose& pose) { return Eigen::Vector3d(poseToQuaternion(pose) * Eigen::Vector3d::UnitX()); };
    CHECK(RollReader::classify(axisOf(hanging(0)), p) == ReadingPosture::Forward);
    CHECK(RollReader::classify(axisOf(hanging(40, 25)), p) == ReadingPosture::Forward);    // 25° off vertical
    CHECK(RollReader::classify(axisOf(level(0, 25)), p) == ReadingPosture::Backward);
    CHECK(RollReader::classify(axisOf(level(0, -28)), p) == ReadingPosture::Backward);
    CHECK(RollReader::classify(axisOf(level(0, 45)), p) == ReadingPosture::Invalid);
    CHECK(RollReader::classify(axisOf(hanging(0, 35)), p) == ReadingPosture::Invalid);   // 55° below horizontal
}

TEST_CASE("The roll angle comes from the orientation: normal heading when hanging, roll about the axis when level", "[braille][roll]")
{
    for (double r : {-150.0, -40.0, 0.0, 33.0, 170.0}) {
        const Eigen::Quaterniond q = poseToQuaternion(level(r));
        CHECK(RollReader::rollAngle(ReadingPosture::Backward, q * Eigen::Vector3d::UnitX(), q * Eigen::Vector3d::UnitY()) ==
              Approx(r).margin(1e-9));
        // Hanging: the heading of the normal turns one for one with the roll.
        const Eigen::Quaterniond h0 = poseToQuaternion(hanging(0)), h1 = poseToQuaternion(hanging(r));
        const double a0 = RollReader::rollAngle(ReadingPosture::Forward, h0 * Eigen::Vector3d::UnitX(), h0 * Eigen::Vector3d::UnitY());
        const double a1 = RollReader::rollAngle(ReadingPosture::Forward, h1 * Eigen::Vector3d::UnitX(), h1 * Eigen::Vector3d::UnitY());
        CHECK(std::abs(wrapDeg180(a1 - a0)) == Approx(std::abs(r)).margin(1e-9));
    }
}

TEST_CASE("A scripted roll reads a word forward then backward, one advance per 15 deg step", "[braille][roll]")
{
    const BrailleDocument doc = translateText("exit", {});
    ReadingCursor cursor(layoutDocument(doc, DisplayMethod::Rows));
    ActiveReading reading;
    reading.setCursor(&cursor);

    Motion m;
    m.hold(hanging(0), 0.5);
    // Forward: 12 rows (4 letters × 3), rolling one way then sweeping back the other way — the
    // thesis's two styles of §4.3.1 — 6 steps each.
    rollSteps(m, [](double r) { return hanging(r); }, 0.0, 15.5, 6);
    rollSteps(m, [](double r) { return hanging(r); }, 6 * 15.5, -15.5, 6);
    const std::size_t forwardEnd = m.states.size();
    // Raise the forearm to level (through the invalid zone), then 12 steps backward.
    m.move(hanging(0), level(0, -5), 1.5);
    m.hold(level(0, -5), 0.5);
    rollSteps(m, [](double r) { return level(r, -5); }, 0.0, -16.0, 12);

    std::string shown;
    int forwardAdvances = 0, backwardAdvances = 0, directionChanges = 0, advancesDuringTurn = 0;
    for (std::size_t i = 0; i < m.states.size(); ++i) {
        const ArmState& s = m.states[i];
        const ReadEvent e = reading.update(s.t, s.q * Eigen::Vector3d::UnitX(), s.q * Eigen::Vector3d::UnitY(), true);
        directionChanges += e.roll.directionChanged ? 1 : 0;
        if (!e.stepped) continue;
        if (i >= forwardEnd && i < forwardEnd + 300) ++advancesDuringTurn;
        (e.roll.posture == ReadingPosture::Forward ? forwardAdvances : backwardAdvances)++;
        REQUIRE(e.step.kind == StepKind::Cell);
        const auto& u = cursor.units()[static_cast<std::size_t>(e.step.unit)];
        shown += doc.messages[0].symbols[static_cast<std::size_t>(u.symbol)].print + std::to_string(e.step.step + 1) + " ";
    }
    CHECK(forwardAdvances == 12);
    CHECK(backwardAdvances == 12);
    CHECK(advancesDuringTurn == 0);
    CHECK(directionChanges == 1);
    CHECK(shown == "e1 e2 e3 x1 x2 x3 i1 i2 i3 t1 t2 t3 t1 t2 t3 i1 i2 i3 x1 x2 x3 e1 e2 e3 ");
}

TEST_CASE("Thresholds re-arm around the new angle: 14 deg wobbles never advance, 15 deg does", "[braille][roll]")
{
    RollReader reader;
    Motion m;
    m.hold(hanging(0), 0.3);
    for (int i = 0; i < 10; ++i) {   // back and forth across ±14° of the anchor: no advance
        m.move(hanging(0), hanging(14), 0.2);
        m.move(hanging(14), hanging(-14), 0.4);
        m.move(hanging(-14), hanging(0), 0.2);
    }
    CHECK(run(reader, m).advances == 0);

    Motion n;
    n.t = m.t;
    n.move(hanging(0), hanging(15.2), 0.2);    // one advance; anchor now 15.2
    n.hold(hanging(15.2), 0.3);
    n.move(hanging(15.2), hanging(1.0), 0.3);  // back 14.2: not yet
    n.hold(hanging(1.0), 0.3);
    const Tally t = run(reader, n);
    CHECK(t.advances == 1);
    Motion o;
    o.t = n.t;
    o.move(hanging(1.0), hanging(-0.5), 0.1);  // 15.7 from the anchor: the second advance
    o.hold(hanging(-0.5), 0.3);
    CHECK(run(reader, o).advances == 1);
}

TEST_CASE("Nothing advances from drift, noise or an invalid posture", "[braille][roll]")
{
    SECTION("slow drift of the orientation under 15 deg")
    {
        RollReader reader;
        Motion m;
        m.move(hanging(0), hanging(14), 120.0);   // two minutes of slow drift
        CHECK(run(reader, m).advances == 0);
    }
    SECTION("sensor noise and motor transients of a few degrees")
    {
        RollReader reader;
        std::mt19937_64 rng(7);
        std::normal_distribution<double> noise(0.0, 2.0);
        Motion m;
        for (int i = 0; i < 6000; ++i) {
            const double spike = (i % 400 == 0) ? 8.0 : 0.0;   // a motor kick every 2 s
            m.add({-85.0 + std::clamp(noise(rng), -4.0, 4.0), 90.0, std::clamp(noise(rng), -4.0, 4.0) + spike});
        }
        CHECK(run(reader, m).advances == 0);
    }
    SECTION("rolling with the forearm 45 deg from vertical and horizontal")
    {
        RollReader reader;
        Motion m;
        rollSteps(m, [](double r) { return Pose {-45.0, 30.0, r}; }, 0.0, 20.0, 12);
        rollSteps(m, [](double r) { return Pose {45.0, 30.0, r}; }, 0.0, 20.0, 12);
        CHECK(run(reader, m).advances == 0);
    }
    SECTION("no valid orientation")
    {
        RollReader reader;
        Motion m;
        rollSteps(m, [](double r) { return hanging(r); }, 0.0, 20.0, 6);
        for (auto& s : m.states) s.valid = false;
        CHECK(run(reader, m).advances == 0);
    }
}

TEST_CASE("The dead time after an advance swallows a second step that comes too soon", "[braille][roll]")
{
    RollReaderParams p;
    p.deadTime = 0.2;
    RollReader reader(p);
    Motion m;
    m.hold(hanging(0), 0.2);
    m.move(hanging(0), hanging(16), 0.02);    // advance at once
    m.move(hanging(16), hanging(40), 0.05);   // 24° more inside the dead time
    m.move(hanging(40), hanging(28), 0.05);   // settles 12° from the anchor: nothing more
    m.hold(hanging(28), 0.5);
    const Tally t = run(reader, m);
    CHECK(t.advances == 1);

    RollReader fast(p);
    Motion k;
    k.hold(hanging(0), 0.2);
    k.move(hanging(0), hanging(16), 0.02);
    k.move(hanging(16), hanging(40), 0.05);
    k.hold(hanging(40), 0.5);                 // stays 24° on: advances once the dead time is over
    const Tally u = run(fast, k);
    REQUIRE(u.advances == 2);
    CHECK(u.advanceTimes[1] - u.advanceTimes[0] >= p.deadTime - 1e-9);
}

TEST_CASE("Roll comes from the orientation: a gyro that contradicts it changes nothing", "[braille][roll]")
{
    // The same scripted reading twice: once with the gyro the motion implies, once with a gyro
    // that says the opposite (a large bias against the roll). Every advance, its direction and
    // its time must be the same, and the count must be the orientation's: 6 steps of 16 deg.
    Motion truthful;
    truthful.hold(hanging(0), 0.3);
    rollSteps(truthful, [](double r) { return hanging(r); }, 0.0, 16.0, 6);
    REQUIRE(truthful.states.size() > 100);
    Motion lying = truthful;
    for (std::size_t i = 1; i < lying.states.size(); ++i) {
        const double dt = lying.states[i].t - lying.states[i - 1].t;
        const Eigen::AngleAxisd step(lying.states[i - 1].q.conjugate() * lying.states[i].q);
        const Eigen::Vector3d rate = dt > 0.0 ? Eigen::Vector3d(step.axis() * step.angle() / dt) : Eigen::Vector3d::Zero();
        lying.states[i].gyro = -rate + Eigen::Vector3d(0.5, 0.0, 0.0);   // reversed, plus 29 deg/s bias
        truthful.states[i].gyro = rate;
    }
    RollReader a, b;
    const Tally t = run(a, truthful), l = run(b, lying);
    CHECK(t.forward == 6);
    CHECK(l.forward == t.forward);
    CHECK(l.backward == t.backward);
    CHECK(l.advanceTimes == t.advanceTimes);
}
