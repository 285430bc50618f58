// `armadillo touch-profile`: touch fitted to the reader (issue 26). Each of the nine motors gets a
// 1-up/2-down staircase for its detection threshold (Tactile/Staircase.h), interleaved so that no
// motor runs twice in a row; then a comfortable level is found on one motor by ascending steps.
// Every stimulus goes through the normal TactileEngine (soft target: no jump-start spike, so the
// level asked is the level felt) and its SafetyStage to the device; after each one, exactly one
// prompt line starting with "? " goes to stderr and the reader answers y or n on stdin.
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/ReaderIo.h"
#include "Cli/GuidedDevice.h"
#include "Core/Errors.h"
#include "Link/TouchProfile.h"
#include "Tactile/Staircase.h"
#include "Tactile/TactileEngine.h"
#include <algorithm>
#include <array>
#include <ctime>
#include <iostream>
#include <random>

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
                    {"--port", "NAME", "serial port of the device (ptys and /dev/rfcomm* work too)"},
                    {"--simulate", "", "the built-in simulated device (no motors: to try the procedure)"},
                    {"--out", "PROFILE.json", "where the profile goes (atomic)", true},
                    {"--baud", "B", "serial speed (default 57600, 8N1)"},
                    {"--on", "S", "seconds a stimulus lasts (default 0.25, at most 0.3: the safety stage's run limit)"},
                    {"--gap", "S", "seconds of stillness after a stimulus before the next may start (default 0.5)"},
                    {"--no-comfort", "", "skip the comfortable-level question"},
                    {"--unpaced", "", "count stimulus time by packets (1/303 s each at 57 600 baud), not by the wall\n"
                                      "clock: for a simulated reader that answers as fast as the link goes"},
                    {"--seed", "N", "order of the motors within each round (default 1)"},
                };
                const auto io = readerIoOptionSpecs();
                o.insert(o.end(), io.begin(), io.end());
                return o;
            }());
        if (!cl.parse(args)) return kExitOk;
        if (cl.has("--port") == cl.has("--simulate")) throw UsageError("choose exactly one of --port NAME and --simulate");
        if (cl.has("--baud") && !cl.has("--port")) throw UsageError("--baud applies to --port");
        const std::string out = cl.value("--out");
        if (out.empty()) throw UsageError("--out needs a file");
        const double onTime = cl.number("--on", 0.25);
        const double gapTime = cl.number("--gap", 0.5);
        if (!(onTime >= 0.05 && onTime <= 0.3)) throw UsageError("--on must lie in 0.05..0.3 s");
        if (!(gapTime >= 0.1 && gapTime <= 10.0)) throw UsageError("--gap must lie in 0.1..10 s");
        const int baud = static_cast<int>(cl.integer("--baud", 57600, 300, 4000000));
        const bool unpaced = cl.has("--unpaced");
        ReaderIo io(cl);

        TactilePlayer player(TactileConfig {}, unpaced ? 1.0 / device::lockStepRate(baud) : 0.0);   // right arm: index = motor m1…
        installInterruptHandlers();
        GuidedDevice device(cl.value("--port"), baud, cl.has("--simulate"), unpaced, player);

        int stimuli = 0;
        // Plays one stimulus (a soft level: no jump-start spike, so the level asked is the level
        // felt) and waits until it and the stillness after it are over. Each motor rests ≥ 3 s of
        // stimulus time between two of its stimuli: the safety stage's mean-power window would
        // otherwise lower a strong level repeated on one motor (the last motors left).
        std::array<double, device::kProfileMotors> lastStart {};
        lastStart.fill(-1e9);
        auto present = [&](int motor, int level) {
            const double wait = std::max(0.0, lastStart[static_cast<std::size_t>(motor)] + 3.0 - player.clock());
            TactileSegment s;
            s.at = wait;
            s.duration = onTime;
            s.motors = static_cast<std::uint16_t>(1u << motor);
            s.level = static_cast<float>(level);
            s.soft = true;
            device.waitFor(player.play({s}, gapTime));
            lastStart[static_cast<std::size_t>(motor)] = player.clock() - onTime - gapTime;
            ++stimuli;
            const int sent = player.maxLevel(motor);
            if (sent < level) io.note("(the safety stage lowered this stimulus to level " + std::to_string(sent) + ")");
        };
        // One stimulus and its one prompt line; 'r' or an unclear answer shows it again.
        auto ask = [&](int motor, int level, const std::string& question) {
            for (;;) {
                present(motor, level);
                const std::string a = io.askYesNo("motor m" + std::to_string(motor + 1) + ", level " + std::to_string(level) + ": " + question);
                if (a == "y") return true;
                if (a == "n") return false;
            }
        };

        std::array<Staircase, device::kProfileMotors> stairs {};
        std::mt19937_64 rng(static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 2147483647L)));
        io.status("touch profile: nine motors, one at a time; answer y if you felt it, n if not");
        int previous = -1;
        for (;;) {
            std::vector<int> order;
            for (int m = 0; m < device::kProfileMotors; ++m)
                if (!stairs[static_cast<std::size_t>(m)].done()) order.push_back(m);
            if (order.empty()) break;
            // Fisher-Yates with `%` (std::shuffle differs between standard libraries): a seed gives
            // the same order everywhere.
            for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[static_cast<std::size_t>(rng() % i)]);
            if (order.size() > 1 && order.front() == previous) std::swap(order.front(), order.back());
            for (int m : order) {
                Staircase& s = stairs[static_cast<std::size_t>(m)];
                s.answer(ask(m, s.level(), "felt? (y/n)"));
                previous = m;
            }
        }
        device::TouchProfile profile;
        for (std::size_t m = 0; m < device::kProfileMotors; ++m) {
            profile.threshold[m] = stairs[m].threshold();
            profile.felt[m] = stairs[m].felt();
        }
        if (!cl.has("--no-comfort")) {
            const int motor = profile.comfortMotor - 1;
            io.status("now a comfortable level: answer y when it is clear and comfortable, n while it is too faint");
            int level = std::min(kMaxLevel, profile.threshold[static_cast<std::size_t>(motor)] + 1);
            while (level < kMaxLevel && !ask(motor, level, "comfortable? (y/n)")) ++level;
            profile.comfort = level;
        }
        profile.stimuli = stimuli;
        profile.stimulusSeconds = stimuli * (onTime + gapTime);
        const std::time_t now = std::time(nullptr);
        char date[32];
        std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
        profile.date = date;
        device::saveTouchProfile(out, profile);
        std::string thresholds;
        for (std::size_t m = 0; m < device::kProfileMotors; ++m) thresholds += (m ? "," : "") + std::to_string(profile.threshold[m]);
        io.status("touch profile written: thresholds " + thresholds + (profile.comfort ? ", comfortable level " + std::to_string(profile.comfort) : ""));
        std::cout << "{\"stimuli\":" << stimuli << ",\"stimulus_seconds\":" << profile.stimulusSeconds << ",\"threshold\":[" << thresholds
                  << "],\"comfort\":" << profile.comfort << "}\n";
        return kExitOk;
    });
}

} // namespace armadillo::cli
