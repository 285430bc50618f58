#pragma once
// The two guided procedures as the web page presents them, written once for both of the page's
// presenters (SessionWebView: `play`, `read`, `navigate`; BlockWebView: the app and Pd): the
// sensitivity test (procedures::TouchTest) and the guided device calibration
// (procedures::DeviceCalibration). Here are the rules a command follows in each state, the notes
// the page reads after it, the status the page shows and the finished file it offers. What
// differs between instruments is only where the motors and the samples are: each presenter
// gives its Hooks.
//
// Threads: the caller's. Not thread-safe: a presenter calls each page from one thread at a time
// (SessionWebView under its lock, BlockWebView on the message thread), and file() under the lock
// it uses for the rest.
#include "Procedures/DeviceCalibration.h"
#include "Procedures/TouchTest.h"
#include "Web/WebInstrument.h"
#include <cstdint>
#include <functional>
#include <string>

namespace armadillo::live {

class TouchTestPage {
public:
    struct Hooks {
        /// "" when the instrument has motors to test, else why not (shown as the page's reason).
        std::function<std::string()> unavailable;
        /// The test begins with this seed and its player takes the motors from the next step.
        std::function<void(std::uint64_t seed)> begin;
        /// The motors back to the scene and the test cancelled; `keep`: it finished, and its
        /// profile becomes the instrument's own where it has one.
        std::function<void(bool keep)> end;
        /// After "complete: <result>." on the page: what the reader does with the profile now.
        std::string finishedHint;
    };

    /// One command from the page; `seed` begins a new test's random order.
    void command(web::TouchCommand command, procedures::TouchTest& test, const Hooks& hooks, std::uint64_t seed);
    /// The test polled on (a stimulus that played to its end makes it ask; a finished one is
    /// taken: result, profile file, then end(true)) and what the page shows of it.
    web::TouchTestStatus status(procedures::TouchTest& test, const Hooks& hooks);
    /// The measured profile as a file (link::touchProfileToJson), "" until a test finished.
    const std::string& file() const noexcept { return profile_; }

private:
    std::string note_, result_, profile_;
    bool finished_ = false;
};

class CalibrationPage {
public:
    struct Hooks {
        /// The running procedure, or null when this source has none (then `why` says so).
        std::function<const procedures::DeviceCalibration*(std::string& why)> procedure;
        /// Begins (only the samples from now on); false and why when it cannot.
        std::function<bool(std::string& why)> begin;
        std::function<bool(std::string& why)> next;
        std::function<void()> skip;
        std::function<void()> cancel;
        /// After "calibration complete: …." on the page: where the result went, what to do with it.
        std::string finishedHint;
    };

    void command(web::ProcedureCommand command, const Hooks& hooks);
    web::ProcedureStatus status(const Hooks& hooks) const;
    /// The finished calibration as a file (link::calibrationToJson), "" until one finished.
    const std::string& file() const noexcept { return file_; }

private:
    std::string note_, file_;
};

} // namespace armadillo::live
