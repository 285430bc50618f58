// `armadillo touch-profile`: touch fitted to the reader (issue 26). The procedure itself — a
// 1-up/2-down staircase per motor for its detection threshold, interleaved so that no motor runs
// twice in a row, then a comfortable level by ascending steps, every stimulus a soft level through
// the normal TactileEngine and its SafetyStage — is procedures::TouchTest (Procedures/TouchTest.h),
// the same the app's Reader window runs. This file presents it: after each stimulus exactly one
// prompt line starting with "? " goes to stderr and the reader answers y or n on stdin (r shows it
// again); the profile is written to --out and one JSON line to stdout.
#include "Cli/CommandLine.h"
#include "Cli/LiveOptions.h"
#include "Cli/Commands.h"
#include "Cli/ReaderIo.h"
#include "Core/Errors.h"
#include "Link/TouchProfile.h"
#include "Live/Sources/GuidedDevice.h"
#include "Procedures/TouchTest.h"
#include <iostream>

namespace armadillo::cli {

int runTouchProfile(const Arguments& args)
{
    return guarded("touch-profile", [&]() -> int {
        CommandLine cl(
            "touch-profile", "(--port NAME | --simulate) --out PROFILE.json [options]",
            "Touch fitted to the reader: finds the faintest level the reader feels on each of the nine\n"
            "motors (a 1-up/2-down adaptive staircase per motor, interleaved), then a comfortable level.\n"
            "After each stimulus one line starting with '? ' is written to stderr; answer y (felt) or n\n"
            "(not felt) on stdin, one line each (r = show it again). Writes the touch profile (JSON:\n"
            "\"threshold\": nine levels m1..m9, \"comfort\", …; docs/INTERFACES.md) that render/play\n"
            "take with --profile. Stimuli pass the tactile engine and its safety stage like any scene's.\n"
            "Prints one JSON line at the end: {\"stimuli\":…,\"stimulus_seconds\":…,\"threshold\":[…]}.",
            [] {
                std::vector<OptionSpec> o {
                    {"--simulate", "", "the built-in simulated device (no motors: to try the procedure)"},
                    {"--out", "PROFILE.json", "where the profile goes (atomic)", true},
                    {"--on", "S", "seconds a stimulus lasts (default 0.25, at most 0.3: the safety stage's run limit)"},
                    {"--gap", "S", "seconds of stillness after a stimulus before the next may start (default 0.5)"},
                    {"--no-comfort", "", "skip the comfortable-level question"},
                    {"--unpaced", "", "count stimulus time by packets (1/303 s each at 57 600 baud), not by the wall\n"
                                      "clock: for a simulated reader that answers as fast as the link goes"},
                    {"--seed", "N", "order of the motors within each round (default 1)"},
                };
                const auto io = readerIoOptionSpecs();
                const auto device = pickOptions(sourceOptionSpecs(), {"--port", "--baud"});   // the source group (Cli/LiveOptions.h)
                o.insert(o.end(), device.begin(), device.end());
                o.insert(o.end(), io.begin(), io.end());
                return o;
            }());
        if (!cl.parse(args)) return core::kExitOk;
        const DeviceChoice choice = readDeviceOptions(cl);   // the source group (Cli/LiveOptions.h)
        const std::string out = cl.value("--out");
        if (out.empty()) throw UsageError("--out needs a file");
        const double onTime = cl.number("--on", 0.25);
        const double gapTime = cl.number("--gap", 0.5);
        if (!(onTime >= 0.05 && onTime <= 0.3)) throw UsageError("--on must lie in 0.05..0.3 s");
        if (!(gapTime >= 0.1 && gapTime <= 10.0)) throw UsageError("--gap must lie in 0.1..10 s");
        const int baud = choice.baud;
        const bool unpaced = cl.has("--unpaced");
        ReaderIo io(cl);

        procedures::TouchTest::Params params;
        params.onSeconds = onTime;
        params.gapSeconds = gapTime;
        params.packetPeriod = unpaced ? 1.0 / link::lockStepRate(baud) : 0.0;
        procedures::TouchTest test(params);   // right arm: index = motor m1…
        installInterruptHandlers();
        live::GuidedDevice device(choice.port, baud, choice.simulate, unpaced, test.player());
        device.setInterruptCheck(interrupted);

        io.status("touch profile: nine motors, one at a time; answer y if you felt it, n if not");
        test.begin(static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 2147483647L)), !cl.has("--no-comfort"));
        bool comfortSaid = false;
        while (test.state() != procedures::TouchTest::State::Done) {
            device.waitUntil([&] { return test.poll(); });   // the stimulus and the stillness after it
            if (const int sent = test.loweredTo(); sent > 0)
                io.note("(the safety stage lowered this stimulus to level " + std::to_string(sent) + ")");
            const std::string a = io.askYesNo(test.question() + " (y/n)");   // AnswersEnded (exit 3) when stdin ends
            if (a == "y" || a == "n") test.answer(a == "y");
            else test.again();   // 'r' or an unclear answer: the stimulus again
            if (test.comfortStep() && !comfortSaid && test.state() != procedures::TouchTest::State::Done) {
                io.status("now a comfortable level: answer y when it is clear and comfortable, n while it is too faint");
                comfortSaid = true;
            }
        }
        test.save(out);
        io.status("touch profile written: " + test.summary());
        std::cout << test.summaryJson() << "\n";
        return core::kExitOk;
    });
}

} // namespace armadillo::cli
