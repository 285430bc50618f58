// The instrument's core (live::Instrument, issue 45), which every clock holds: `play` on the
// source's clock (LiveSession) and the app, the plugin and Pd on the block clock (BlockControl).
// What it decides once for both: when the mapping's notes are silenced (the first moment of a
// panic, whoever started it, and not again until resume), what a step publishes, and the
// mapping's view of a step.
#include "Core/Pose.h"
#include "Live/Session/Instrument.h"
#include "LoopSlots.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::live;

namespace {

constexpr double kDt = 0.005;   // the 200 Hz control step

struct Clock {
    Instrument instrument;
    double t = 0.0;
    int silenced = 0;   // how often the mapping was told to end its notes

    explicit Clock(const char* scene = "theremin") { instrument.loop().replace(test::loopSlot(scene)); }

    /// One packet's or block's work: the stage, then one step with the arm at `elevationDeg`.
    Instrument::Stepped step(double elevationDeg = 0.0, bool gesture = false, bool levelsOut = true)
    {
        if (instrument.beginStage().silenceMapping) ++silenced;
        ControlStep s;
        s.automation = core::Pose {elevationDeg, 20.0, 0.0};
        s.dt = kDt;
        s.panicGesture = gesture;
        t += kDt;
        Instrument::Stepped out = instrument.step(s, t, levelsOut);
        if (out.silenceMapping) ++silenced;
        return out;
    }
};

bool anyOn(const core::MotorLevels& levels)
{
    for (float l : levels)
        if (l > 0.0f) return true;
    return false;
}

} // namespace

TEST_CASE("instrument: a stage panic silences the mapping once, at the step it starts, until resume", "[live][instrument][panic]")
{
    Clock c;
    for (int i = 0; i < 20; ++i) CHECK_FALSE(c.step().panicked);
    CHECK(c.silenced == 0);
    c.instrument.stage().apply({core::StageCommand::Kind::Panic, 0});
    const Instrument::Stepped first = c.step();
    CHECK(first.panicked);
    CHECK(c.silenced == 1);
    c.instrument.stage().apply({core::StageCommand::Kind::Panic, 0});   // a second panic while in panic
    for (int i = 0; i < 50; ++i) CHECK(c.step().panicked);
    CHECK(c.silenced == 1);
    c.instrument.stage().apply({core::StageCommand::Kind::Resume, 0});
    CHECK_FALSE(c.step().panicked);
    CHECK(c.silenced == 1);
    c.instrument.stage().apply({core::StageCommand::Kind::Panic, 0});   // a new panic after resume: silenced again
    c.step();
    CHECK(c.silenced == 2);
}

TEST_CASE("instrument: the panic gesture silences the mapping at its own step, and the stage's panic it starts does not again",
          "[live][instrument][panic]")
{
    Clock c;
    int firstPanicStep = -1, silencedAt = -1;
    for (int i = 0; i < static_cast<int>(2.5 / kDt); ++i) {
        const int before = c.silenced;
        const Instrument::Stepped s = c.step(-85.0, true);   // hanging straight down
        if (s.panicked && firstPanicStep < 0) firstPanicStep = i;
        if (c.silenced != before && silencedAt < 0) silencedAt = i;
    }
    REQUIRE(firstPanicStep >= 0);                   // the gesture fired (after 2 s)
    CHECK(firstPanicStep > static_cast<int>(1.9 / kDt));
    CHECK(silencedAt == firstPanicStep);            // the mapping heard it at that very step
    CHECK(c.silenced == 1);                         // and not again when the stage's panic began the next block
    CHECK(c.instrument.stage().panicked());         // the gesture's panic is the stage's, held until resume
    for (int i = 0; i < 40; ++i) CHECK(c.step(0.0, true).panicked);
    c.instrument.stage().resume();
    CHECK_FALSE(c.step(0.0, true).panicked);
    CHECK(c.silenced == 1);
}

TEST_CASE("instrument: a step publishes its frame with the levels that reached the motors, zeros when none did", "[live][instrument]")
{
    Clock c;
    Instrument::Stepped s;
    for (int i = 0; i < 100 && !anyOn(s.result.levels); ++i) s = c.step(10.0);
    REQUIRE(anyOn(s.result.levels));   // the probe: this scene drives motors at this pose
    ArmFrame f = c.instrument.published().latest();
    CHECK(f.t == Approx(c.t));
    CHECK(f.motors == s.result.levels);
    const std::uint64_t steps = c.instrument.published().steps();

    s = c.step(10.0, false, false);   // an offline block: nothing reached the motors
    REQUIRE(anyOn(s.result.levels));
    f = c.instrument.published().latest();
    CHECK(f.motors == core::MotorLevels {});
    CHECK(c.instrument.published().steps() == steps + 1);
}

TEST_CASE("instrument: the mapping's view of a step: both arms, the scene, the gestures, stage commands only in panic",
          "[live][instrument][mapping]")
{
    Clock c;
    Instrument::Stepped s = c.step(10.0);
    mapping::MappingInput in = c.instrument.mappingInput(s, 1.25);
    CHECK(in.t == 1.25);
    CHECK(in.arm[0] == &s.result.arm);
    CHECK(in.arm[1] == nullptr);   // one arm
    CHECK(in.gestures == c.instrument.published().stepGestures());
    CHECK(in.gestureCount == c.instrument.published().stepGestureCount());
    CHECK_FALSE(in.stageOnly);
    c.instrument.stage().panic();
    s = c.step(10.0);
    CHECK(c.instrument.mappingInput(s, 1.3).stageOnly);

    // Two arms: the left arm's state rides in the step once it is on.
    c.instrument.stage().resume();
    c.instrument.leftArm().setOn(true);
    s = c.step(10.0);
    REQUIRE(s.leftArm != nullptr);
    CHECK(c.instrument.mappingInput(s, 1.4).arm[1] == s.leftArm);
    c.instrument.leftArm().setOn(false);
    CHECK(c.step(10.0).leftArm == nullptr);
}
