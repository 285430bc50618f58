// The "stage" destination (docs/MAPPING.md, docs/STAGE.md; issue 28): any event the mapping
// reads — a gesture, a learned posture entered, a threshold crossed upward, a zone entered —
// steps the set list or panics, once per rising edge, never again while the source is held.
#include "Common/RealtimeGuard.h"
#include "Core/Errors.h"
#include "Mapping/MappingHelpers.h"
#include <catch2/catch.hpp>
#include <memory>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;
using armadillo::test::RealtimeGuard;

namespace {

/// A Mapper stepping poses and gestures, keeping every stage command it fired.
struct StageRig {
    Mapper mapper;
    std::unique_ptr<MappingOutput> out = std::make_unique<MappingOutput>();
    std::vector<StageEvent> fired;

    explicit StageRig(const MappingDocument& doc) { mapper.replace(MappingSet::build(doc)); }
    explicit StageRig(const std::string& json) : StageRig(parseMappingDocument(json, "stage.json")) {}

    /// One update; the number of stage commands it fired.
    std::size_t step(const ArmState& arm, double t, const GestureIn* g = nullptr, int count = 0, bool stageOnly = false)
    {
        MappingInput in;
        in.t = t;
        in.arm[0] = &arm;
        in.gestures = g;
        in.gestureCount = count;
        in.stageOnly = stageOnly;
        mapper.process(in, *out);
        for (int i = 0; i < out->stageCount; ++i) fired.push_back(out->stage[static_cast<std::size_t>(i)]);
        const auto n = static_cast<std::size_t>(out->stageCount);
        out->clear();
        return n;
    }
    std::size_t elevation(double el, double t) { return step(armAt(el, 0.0, 0.0, t), t); }
};

} // namespace

TEST_CASE("Stage destinations are read, written back and refused when wrong, naming file, line and column", "[mapping][stage]")
{
    const MappingDocument doc = parseMappingDocument(R"({"version": 1, "mappings": [
        {"source": "gesture:roll", "to": {"stage": "next"}},
        {"source": "gesture:punch", "to": {"stage": "prev"}},
        {"source": "elevation", "threshold": 60, "to": {"stage": "cue", "cue": 3}},
        {"source": "posture:down", "to": {"stage": "panic"}},
        {"source": "azimuth", "zones": [[0, 90, 1]], "to": {"stage": "resume"}}],
        "postures": [{"name": "down", "examples": [[1, 0, 0, 0]]}]})", "stage.json");
    REQUIRE(doc.mappings.size() == 5);
    using K = core::StageCommand::Kind;
    const K expected[] {K::CueNext, K::CuePrev, K::CueGoto, K::Panic, K::Resume};
    for (std::size_t i = 0; i < 5; ++i) {
        CHECK(doc.mappings[i].to.kind == DestinationKind::Stage);
        CHECK(doc.mappings[i].to.stage == expected[i]);
    }
    CHECK(doc.mappings[2].to.number == 3);
    const MappingDocument back = parseMappingDocument(toJson(doc), "saved.json");
    for (std::size_t i = 0; i < 5; ++i) CHECK(back.mappings[i].to.stage == expected[i]);
    CHECK(back.mappings[2].to.number == 3);
    CHECK(toJson(doc).find(R"("stage": "cue", "cue": 3)") != std::string::npos);

    // Line 2, column of the bad value.
    const std::string unknown = parseMessage("{\"version\": 1, \"mappings\": [\n  {\"source\": \"gesture:roll\", \"to\": {\"stage\": \"skip\"}}]}");
    CHECK_THAT(unknown, Catch::Contains("bad.json:2"));
    CHECK_THAT(unknown, Catch::Contains("column"));
    CHECK_THAT(unknown, Catch::Contains("unknown stage command \"skip\""));
    CHECK_THAT(parseMessage(R"({"version": 1, "mappings": [{"source": "gesture:roll", "to": {"stage": "cue"}}]})"), Catch::Contains("needs \"cue\""));
    CHECK_THAT(parseMessage(R"({"version": 1, "mappings": [{"source": "gesture:roll", "to": {"stage": "cue", "cue": -1}}]})"), Catch::Contains("cue"));
    CHECK_THAT(parseMessage(R"({"version": 1, "mappings": [{"source": "gesture:roll", "to": {"stage": "next", "cue": 2}}]})"),
               Catch::Contains("only with \"stage\": \"cue\""));
    CHECK_THAT(parseMessage(R"({"version": 1, "mappings": [{"source": "gesture:roll", "to": {"stage": "next", "channel": 2}}]})"), Catch::Contains("channel"));
    // A continuous source without threshold or zones has no edge to act on.
    CHECK_THAT(parseMessage(R"({"version": 1, "mappings": [{"source": "elevation", "to": {"stage": "next"}}]})"), Catch::Contains("needs an event"));
    CHECK_THAT(parseMessage(R"({"version": 1, "mappings": [{"source": "gesture:roll", "to": {"stage": 1}}]})"), Catch::Contains("bad.json:1"));
}

TEST_CASE("A threshold fires its stage command once as it is crossed upward, not while held", "[mapping][stage]")
{
    StageRig rig(R"({"version": 1, "mappings": [{"source": "elevation", "threshold": 40, "to": {"stage": "next"}}]})");
    CHECK(rig.elevation(0.0, 0.00) == 0);
    CHECK(rig.elevation(39.0, 0.01) == 0);
    CHECK(rig.elevation(41.0, 0.02) == 1);   // the rising edge
    for (int i = 0; i < 200; ++i) CHECK(rig.elevation(45.0 + 10.0 * (i % 3), 0.03 + i * 0.005) == 0);   // held: nothing more
    CHECK(rig.elevation(38.0, 1.10) == 0);   // back below, but within the 3° hysteresis: still on
    CHECK(rig.elevation(41.0, 1.11) == 0);
    CHECK(rig.elevation(30.0, 1.12) == 0);   // off (no command on the falling edge)
    CHECK(rig.elevation(50.0, 1.13) == 1);   // a second rising edge
    REQUIRE(rig.fired.size() == 2);
    CHECK(rig.fired[0].command.kind == core::StageCommand::Kind::CueNext);
    CHECK(rig.fired[0].t == Approx(0.02));
    CHECK(rig.fired[1].t == Approx(1.13));
    CHECK(rig.fired[0].mapping == 0);
}

TEST_CASE("A source already on when the mapping is loaded does not fire until it goes off and on", "[mapping][stage]")
{
    StageRig rig(R"({"version": 1, "mappings": [{"source": "elevation", "threshold": 40, "to": {"stage": "panic"}},
                                                {"source": "elevation", "zones": [[10, 90, 1]], "to": {"stage": "cue", "cue": 2}}]})");
    CHECK(rig.elevation(70.0, 0.00) == 0);
    CHECK(rig.elevation(75.0, 0.01) == 0);
    CHECK(rig.elevation(-20.0, 0.02) == 0);
    CHECK(rig.elevation(70.0, 0.03) == 2);
    REQUIRE(rig.fired.size() == 2);
    CHECK(rig.fired[0].command.kind == core::StageCommand::Kind::Panic);
    CHECK(rig.fired[1].command.kind == core::StageCommand::Kind::CueGoto);
    CHECK(rig.fired[1].command.cue == 2);
}

TEST_CASE("Each gesture event, a zone entered and a posture entered fire their stage command once", "[mapping][stage]")
{
    MappingDocument doc = parseMappingDocument(R"({"version": 1, "mappings": [
        {"source": "gesture:roll", "to": {"stage": "next"}},
        {"source": "gesture:punch", "to": {"stage": "prev"}},
        {"source": "azimuth", "zones": [[0, 90, 1], [90, 180, 2]], "to": {"stage": "resume"}},
        {"source": "posture:hang", "to": {"stage": "cue", "cue": 5}}],
        "postures": [{"name": "hang", "examples": [[1, 0, 0, 0]], "radius": 20}]})", "stage.json");
    // The posture: the forearm hanging (elevation −80°, azimuth 200°), as the orientation the arm has there.
    const Eigen::Quaterniond hang = poseToQuaternion(Pose {-80.0, 200.0, 0.0});
    doc.postures[0].examples = {{hang.w(), hang.x(), hang.y(), hang.z()}};
    StageRig rig(doc);
    const ArmState level = armAt(0.0, 270.0, 0.0);   // outside every zone and the posture
    CHECK(rig.step(level, 0.00) == 0);               // the first reading (primes the zones and the posture)

    GestureIn roll {"roll", 1.0f}, punch {"punch", 12.0f}, strike {"strike", 1.0f};
    CHECK(rig.step(level, 0.01, &roll, 1) == 1);
    CHECK(rig.step(level, 0.02) == 0);
    CHECK(rig.step(level, 0.03, &roll, 1) == 1);      // every gesture event is an edge of its own
    CHECK(rig.step(level, 0.04, &strike, 1) == 0);    // a gesture no stage mapping names
    CHECK(rig.step(level, 0.05, &punch, 1) == 1);

    CHECK(rig.step(armAt(0.0, 45.0, 0.0), 0.06) == 1);    // zone 1 entered
    CHECK(rig.step(armAt(0.0, 60.0, 0.0), 0.07) == 0);    // moving inside it
    CHECK(rig.step(armAt(0.0, 120.0, 0.0), 0.08) == 1);   // zone 2 entered
    CHECK(rig.step(level, 0.09) == 0);                    // left: nothing

    ArmState hanging = armAt(-80.0, 200.0, 0.0);
    CHECK(rig.step(hanging, 0.10) == 1);                  // posture entered
    for (int i = 0; i < 50; ++i) CHECK(rig.step(hanging, 0.11 + i * 0.005) == 0);   // held
    REQUIRE(rig.fired.size() == 6);
    CHECK(rig.fired[0].command.kind == core::StageCommand::Kind::CueNext);
    CHECK(rig.fired[1].command.kind == core::StageCommand::Kind::CueNext);
    CHECK(rig.fired[2].command.kind == core::StageCommand::Kind::CuePrev);
    CHECK(rig.fired[3].command.kind == core::StageCommand::Kind::Resume);
    CHECK(rig.fired[4].command.kind == core::StageCommand::Kind::Resume);
    CHECK(rig.fired[5].command.kind == core::StageCommand::Kind::CueGoto);
    CHECK(rig.fired[5].command.cue == 5);
    CHECK(rig.fired[5].mapping == 3);
}

TEST_CASE("In panic only stage mappings run, and a panic does not make a held source fire again", "[mapping][stage]")
{
    StageRig rig(R"({"version": 1, "mappings": [
        {"source": "elevation", "threshold": 40, "to": {"stage": "panic"}},
        {"source": "elevation", "threshold": -40, "invert": true, "to": {"midi": "note", "note": 60}},
        {"source": "gesture:select", "to": {"stage": "resume"}},
        {"source": "elevation", "to": {"midi": "cc", "cc": 7}}]})");
    CHECK(rig.elevation(0.0, 0.00) == 0);
    CHECK(rig.elevation(50.0, 0.01) == 1);
    // The front end panics: every note ended, the mapping's state forgotten — but the stage
    // mapping's edge is kept, so the arm still raised does not panic again after a resume.
    rig.mapper.panic(0.02, *rig.out);
    rig.out->clear();
    GestureIn select {"select", 1.0f};
    const ArmState raised = armAt(55.0, 0.0, 0.0);
    CHECK(rig.step(raised, 0.03, nullptr, 0, true) == 0);
    MappingInput in;
    in.t = 0.04;
    in.arm[0] = &raised;
    in.gestures = &select;
    in.gestureCount = 1;
    in.stageOnly = true;
    rig.mapper.process(in, *rig.out);
    CHECK(rig.out->stageCount == 1);             // the mapped resume is heard in panic
    CHECK(rig.out->stage[0].command.kind == core::StageCommand::Kind::Resume);
    CHECK(rig.out->midiCount == 0);              // nothing else is sent
    rig.out->clear();
    CHECK(rig.step(raised, 0.05) == 0);          // held through the panic: no second panic
    CHECK(rig.elevation(0.0, 0.06) == 0);
    CHECK(rig.elevation(60.0, 0.07) == 1);
}

TEST_CASE("Stage commands are emitted without allocation, free, lock or throw", "[mapping][stage][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    {   // the probe first: it sees an allocation
        RealtimeGuard probe;
        auto p = std::make_unique<std::vector<int>>(10);
        CHECK(probe.allocations() >= 2);
    }
    StageRig rig(R"({"version": 1, "mappings": [
        {"source": "elevation", "threshold": 0, "to": {"stage": "next"}},
        {"source": "elevation", "zones": [[-90, -30, 1], [30, 90, 2]], "to": {"stage": "prev"}},
        {"source": "gesture:roll", "to": {"stage": "cue", "cue": 1}},
        {"source": "gesture:*", "to": {"stage": "panic"}},
        {"source": "gesture:select", "to": {"stage": "resume"}}]})");
    std::uint64_t allocations = 0, frees = 0, locks = 0, throws = 0;
    int fired = 0;
    GestureIn g[2] {{"roll", 1.0f}, {"select", 1.0f}};
    for (int i = 0; i < 4000; ++i) {
        const double t = i * 0.005;
        const ArmState arm = armAt(80.0 * std::sin(t * 3.0), 0.0, 0.0, t);
        MappingInput in;
        in.t = t;
        in.arm[0] = &arm;
        in.gestures = g;
        in.gestureCount = i % 50 == 0 ? 2 : 0;
        in.stageOnly = i % 7 == 0;
        {
            RealtimeGuard guard;
            rig.mapper.process(in, *rig.out);
            if (i % 500 == 499) rig.mapper.panic(t, *rig.out);
            allocations += guard.allocations();
            frees += guard.deallocations();
            locks += guard.locks();
            throws += guard.throws();
        }
        fired += rig.out->stageCount;
        CHECK(rig.out->dropped == 0);
        rig.out->clear();
    }
    CHECK(fired > 100);   // the sway crosses 0 and enters the zones some 19 times each, gestures 80 times
    CHECK(allocations == 0);
    CHECK(frees == 0);
    CHECK(locks == 0);
    CHECK(throws == 0);
}
