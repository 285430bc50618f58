#include "Live/Session/ProcedurePages.h"
#include "Link/Calibration.h"
#include "Link/TouchProfile.h"

namespace armadillo::live {

// ------------------------------------------------------------------------------------------------
// The sensitivity test

namespace {

bool testRunning(const procedures::TouchTest& test) noexcept
{
    return test.state() == procedures::TouchTest::State::Presenting || test.state() == procedures::TouchTest::State::Asking;
}

} // namespace

void TouchTestPage::command(web::TouchCommand command, procedures::TouchTest& test, const Hooks& hooks, std::uint64_t seed)
{
    using State = procedures::TouchTest::State;
    using C = web::TouchCommand;
    (void) status(test, hooks);   // up to date before the command
    const bool running = testRunning(test);
    if (const std::string why = hooks.unavailable(); !why.empty()) {
        note_ = "not available: " + why;
    } else if (command == C::Begin) {
        if (running) {
            note_ = "a test runs already: answer it, or cancel it first";
        } else {
            hooks.begin(seed);
            finished_ = false;
            result_.clear();
            profile_.clear();
            note_ = "begun: one motor at a time; answer each stimulus once it has played";
        }
    } else if (command == C::Cancel) {
        note_ = running ? "cancelled: nothing kept; the motors are the scene's again" : "no test runs";
        if (running) hooks.end(false);
    } else if (test.state() != State::Asking) {
        note_ = running ? "wait: the stimulus is still playing" : "no test runs: begin it first";
    } else if (command == C::Again) {
        test.again();
        note_ = "again: the same stimulus";
    } else {
        const bool comfort = test.comfortStep();
        test.answer(command == C::Felt);
        note_ = command == C::Felt ? (comfort ? "answered: comfortable / felt" : "answered: felt") : "answered: not felt";
    }
}

web::TouchTestStatus TouchTestPage::status(procedures::TouchTest& test, const Hooks& hooks)
{
    using State = procedures::TouchTest::State;
    web::TouchTestStatus t;
    t.why = hooks.unavailable();
    t.available = t.why.empty();
    (void) test.poll();   // a stimulus played to its end: the test asks now
    if (test.state() == State::Done) {
        result_ = test.summary();
        profile_ = link::touchProfileToJson(test.profile());
        finished_ = true;
        note_ = "complete: " + result_ + ". " + hooks.finishedHint;
        hooks.end(true);
    }
    t.running = testRunning(test);
    t.asking = test.state() == State::Asking;
    t.comfort = test.comfortStep();
    t.finished = finished_;
    t.stimuli = test.stimuli();
    t.question = t.asking ? test.question() : std::string();
    if (t.asking && test.loweredTo() > 0) t.question += " (the safety stage let level " + std::to_string(test.loweredTo()) + " through)";
    t.result = result_;
    t.note = note_;
    return t;
}

// ------------------------------------------------------------------------------------------------
// The guided device calibration

void CalibrationPage::command(web::ProcedureCommand command, const Hooks& hooks)
{
    using C = web::ProcedureCommand;
    std::string why;
    const procedures::DeviceCalibration* procedure = hooks.procedure(why);
    if (procedure == nullptr) {
        note_ = "not available: " + why;
        return;
    }
    if (command == C::Begin) {
        if (hooks.begin(why)) {
            note_ = "begun: keep the arm as the step asks";
            file_.clear();
        } else {
            note_ = "not begun: " + why;
        }
        return;
    }
    if (! procedure->running()) {
        note_ = "no calibration runs: begin it first";
        return;
    }
    if (command == C::Next) {
        note_ = hooks.next(why) ? "step taken" : "not yet: " + why;
    } else if (command == C::Skip) {
        hooks.skip();
        note_ = "step skipped: it keeps the starting calibration's numbers";
    } else {
        hooks.cancel();
        note_ = "cancelled: nothing kept";
        return;
    }
    procedure = hooks.procedure(why);
    if (procedure != nullptr && procedure->finished()) {
        const std::string measured = procedure->measuredList(true), kept = procedure->measuredList(false);
        note_ = "calibration complete: " + (measured.empty() ? std::string("nothing measured") : "measured " + measured) +
                (kept.empty() ? std::string() : "; kept " + kept) + ". " + hooks.finishedHint;
        file_ = link::calibrationToJson(procedure->result());
    }
}

web::ProcedureStatus CalibrationPage::status(const Hooks& hooks) const
{
    web::ProcedureStatus c;
    const procedures::DeviceCalibration* procedure = hooks.procedure(c.why);
    c.available = procedure != nullptr;
    c.steps = procedures::DeviceCalibration::kStepCount;
    if (procedure != nullptr) {
        c.running = procedure->running();
        c.finished = procedure->finished();
        if (c.running || c.finished) {
            c.step = procedure->stepNumber();
            c.title = procedure->stepTitle();
            c.instruction = c.finished ? std::string() : procedure->instruction();
            c.progress = procedure->progress();
            c.ready = procedure->ready();
        }
    }
    c.note = note_;
    return c;
}

} // namespace armadillo::live
