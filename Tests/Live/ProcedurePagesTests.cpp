// The web page's two guided procedures, written once for both presenters (ProcedurePages.h): the
// rules each command follows in each state, the notes the page reads, the finished file, and the
// hooks called exactly as the instrument needs them (the motors taken and given back once).
// The sensitivity test is played by the procedures' scripted presenter (5 ms control steps, no
// wall clock); the calibration is a real procedures::DeviceCalibration.
#include "Live/Session/ProcedurePages.h"
#include "Link/Calibration.h"
#include "Procedures/ScriptedPresenter.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using live::CalibrationPage;
using live::TouchTestPage;
using web::ProcedureCommand;
using web::TouchCommand;

namespace {

struct TouchRig {
    procedures::TouchTest test;
    TouchTestPage page;
    TouchTestPage::Hooks hooks;
    bool motors = true;
    int begun = 0, ended = 0, kept = 0;
    std::uint64_t seed = 0;
    TouchRig()
    {
        hooks.unavailable = [this] { return motors ? std::string() : std::string("no motors here"); };
        hooks.begin = [this](std::uint64_t s) {
            ++begun;
            seed = s;
            test.begin(s);
        };
        hooks.end = [this](bool keep) {
            ++ended;
            kept += keep ? 1 : 0;
            test.cancel();
        };
        hooks.finishedHint = "Use it.";
    }
};

} // namespace

TEST_CASE("TouchTestPage: a whole test through the page's commands; the motors taken once and given back once", "[live][web][touch]")
{
    TouchRig rig;
    test::ScriptedPlayerSide side(rig.test.player());
    web::TouchTestStatus s = rig.page.status(rig.test, rig.hooks);
    CHECK(s.available);
    CHECK_FALSE(s.running);

    rig.page.command(TouchCommand::Felt, rig.test, rig.hooks, 7);
    CHECK(rig.page.status(rig.test, rig.hooks).note == "no test runs: begin it first");
    rig.page.command(TouchCommand::Cancel, rig.test, rig.hooks, 7);
    CHECK(rig.page.status(rig.test, rig.hooks).note == "no test runs");
    CHECK(rig.ended == 0);

    rig.page.command(TouchCommand::Begin, rig.test, rig.hooks, 42);
    CHECK(rig.begun == 1);
    CHECK(rig.seed == 42);
    s = rig.page.status(rig.test, rig.hooks);
    CHECK(s.running);
    CHECK_FALSE(s.asking);
    rig.page.command(TouchCommand::Begin, rig.test, rig.hooks, 43);
    CHECK(rig.begun == 1);   // one test at a time
    CHECK(rig.page.status(rig.test, rig.hooks).note == "a test runs already: answer it, or cancel it first");
    rig.page.command(TouchCommand::Felt, rig.test, rig.hooks, 43);
    CHECK(rig.page.status(rig.test, rig.hooks).note == "wait: the stimulus is still playing");

    // A reader who feels level 6 and above everywhere, and finds two levels more comfortable.
    int answers = 0;
    bool sawComfort = false;
    while (! rig.page.status(rig.test, rig.hooks).finished) {
        side.clear();
        REQUIRE(side.runUntil([&] { return rig.page.status(rig.test, rig.hooks).asking; }));
        s = rig.page.status(rig.test, rig.hooks);
        REQUIRE_FALSE(s.question.empty());
        int level = 0;
        for (int l : side.highest()) level = std::max(level, l);
        const bool comfort = s.comfort;
        sawComfort = sawComfort || comfort;
        const bool felt = comfort ? level >= 8 : level >= 6;
        rig.page.command(felt ? TouchCommand::Felt : TouchCommand::NotFelt, rig.test, rig.hooks, 0);
        REQUIRE(++answers < 400);
        const std::string note = rig.page.status(rig.test, rig.hooks).note;
        if (note.rfind("complete: ", 0) == 0) break;
        CHECK(note == (felt ? (comfort ? "answered: comfortable / felt" : "answered: felt") : "answered: not felt"));
    }
    s = rig.page.status(rig.test, rig.hooks);
    CHECK(sawComfort);
    CHECK(s.finished);
    CHECK_FALSE(s.running);
    CHECK(s.note.rfind("complete: ", 0) == 0);
    CHECK(s.note.find(". Use it.") != std::string::npos);
    CHECK_FALSE(s.result.empty());
    CHECK(rig.ended == 1);   // given back once, kept
    CHECK(rig.kept == 1);
    CHECK(rig.page.file().find('{') == 0);
    (void) rig.page.status(rig.test, rig.hooks);
    CHECK(rig.ended == 1);   // a finished test is taken once

    // A new test clears the old result; cancel gives the motors back without keeping anything.
    rig.page.command(TouchCommand::Begin, rig.test, rig.hooks, 5);
    CHECK(rig.page.file().empty());
    rig.page.command(TouchCommand::Cancel, rig.test, rig.hooks, 5);
    CHECK(rig.ended == 2);
    CHECK(rig.kept == 1);
    CHECK(rig.page.status(rig.test, rig.hooks).note == "cancelled: nothing kept; the motors are the scene's again");
}

TEST_CASE("TouchTestPage: without motors every command says why and nothing begins", "[live][web][touch]")
{
    TouchRig rig;
    rig.motors = false;
    for (TouchCommand c : {TouchCommand::Begin, TouchCommand::Felt, TouchCommand::Cancel}) {
        rig.page.command(c, rig.test, rig.hooks, 1);
        const web::TouchTestStatus s = rig.page.status(rig.test, rig.hooks);
        CHECK_FALSE(s.available);
        CHECK(s.why == "no motors here");
        CHECK(s.note == "not available: no motors here");
    }
    CHECK(rig.begun == 0);
    CHECK(rig.ended == 0);
}

TEST_CASE("CalibrationPage: begin, a step not ready, skips to the end, the file; cancel; a source without one", "[live][web][calibration]")
{
    procedures::DeviceCalibration calibration;
    bool present = true;
    int begins = 0;
    CalibrationPage page;
    CalibrationPage::Hooks hooks;
    hooks.procedure = [&](std::string& why) -> const procedures::DeviceCalibration* {
        if (present) return &calibration;
        why = "this source sends OSC";
        return nullptr;
    };
    hooks.begin = [&](std::string&) {
        ++begins;
        calibration.begin(link::Calibration {});
        return true;
    };
    hooks.next = [&](std::string& why) { return calibration.next(why); };
    hooks.skip = [&] { calibration.skip(); };
    hooks.cancel = [&] { calibration.cancel(); };
    hooks.finishedHint = "Keep it.";

    page.command(ProcedureCommand::Next, hooks);
    CHECK(page.status(hooks).note == "no calibration runs: begin it first");
    page.command(ProcedureCommand::Begin, hooks);
    web::ProcedureStatus s = page.status(hooks);
    CHECK(begins == 1);
    CHECK(s.available);
    CHECK(s.running);
    CHECK(s.step == 1);
    CHECK(s.steps == procedures::DeviceCalibration::kStepCount);
    CHECK_FALSE(s.title.empty());
    page.command(ProcedureCommand::Next, hooks);   // no sample came: not ready
    s = page.status(hooks);
    CHECK(s.note.rfind("not yet: ", 0) == 0);
    CHECK(s.step == 1);
    for (int i = 0; i < procedures::DeviceCalibration::kStepCount && ! page.status(hooks).finished; ++i) page.command(ProcedureCommand::Skip, hooks);
    s = page.status(hooks);
    CHECK(s.finished);
    CHECK(s.note.rfind("calibration complete: nothing measured", 0) == 0);
    CHECK(s.note.find(". Keep it.") != std::string::npos);
    CHECK(page.file().find('{') == 0);

    page.command(ProcedureCommand::Begin, hooks);
    CHECK(page.file().empty());   // a new calibration: the old file is gone
    page.command(ProcedureCommand::Cancel, hooks);
    CHECK(page.status(hooks).note == "cancelled: nothing kept");
    CHECK_FALSE(page.status(hooks).running);

    present = false;
    page.command(ProcedureCommand::Begin, hooks);
    s = page.status(hooks);
    CHECK_FALSE(s.available);
    CHECK(s.why == "this source sends OSC");
    CHECK(s.note == "not available: this source sends OSC");
    CHECK(begins == 2);
}
