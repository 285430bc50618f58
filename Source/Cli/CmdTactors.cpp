// `armadillo tactors test`: buzzes each channel of a tactor rig in turn and names it, so the
// wiring can be checked (issue 33, docs/TACTORS.md).
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/TactorOptions.h"
#include "Core/Clock.h"
#include "Core/Errors.h"
#include "Live/TactorOutput.h"
#include "Tactile/TactileEngine.h"
#include <chrono>
#include <cmath>
#include <iostream>
#include <thread>

namespace armadillo::cli {

namespace {

/// Where motor index m sits on the right forearm (docs/TACTILE.md: index = 3·row + col).
std::string motorPlace(int m)
{
    if (m >= 9) return "back " + std::to_string(m - 8);
    static const char* rows[] = {"wrist", "middle", "elbow"};
    static const char* cols[] = {"left", "underside", "right"};
    return std::string(rows[m / 3]) + ", " + cols[m % 3];
}

} // namespace

int runTactors(const Arguments& args)
{
    return guarded("tactors", [&] {
        std::vector<OptionSpec> options {
            {"--level", "L", "the level of each buzz (1..15, default 5: the motors' rating)"},
            {"--on", "SECONDS", "how long each channel buzzes (0.05..2, default 0.5)"},
            {"--gap", "SECONDS", "silence between two channels (0..5, default 0.5)"},
            {"--back-motors", "", "the map may name the back motors 10..12"},
        };
        const auto tactorSpecs = tactorOptionSpecs(true);
        options.insert(options.begin(), tactorSpecs.begin(), tactorSpecs.end());
        options.front().required = true;
        CommandLine cl("tactors", "test --tactors DEVICE|jack [--tactor-map MAP] [--tactor-model MODEL] [options]",
                       "Buzzes each channel of the tactor output in turn, channel 1 first, and names it on stdout\n"
                       "(\"channel 3 (tactor_3): motor m3, wrist, right\"), so a rig's wiring can be checked against\n"
                       "the map. Each buzz is the motor's level through the tactile engine and its safety stage,\n"
                       "as in play. Silent channels (- in the map) are named and skipped.",
                       options);
        if (args.empty() || args.front() != "test") {
            if (!args.empty() && (args.front() == "--help" || args.front() == "-h")) {
                std::cout << cl.helpText();
                return int(core::kExitOk);
            }
            throw UsageError("tactors: the subcommand is 'test' (armadillo tactors test --tactors DEVICE|jack)");
        }
        if (!cl.parse(Arguments(args.begin() + 1, args.end()))) return int(core::kExitOk);
        const int motors = cl.has("--back-motors") ? core::kGridMotors + core::kBackMotors : core::kGridMotors;
        live::TactorOutputConfig config = tactorConfig(cl, motors);
        const double level = cl.number("--level", 5.0), on = cl.number("--on", 0.5), gap = cl.number("--gap", 0.5);
        if (!(level >= 1.0 && level <= 15.0)) throw UsageError("--level must lie in 1..15");
        if (!(on >= 0.05 && on <= 2.0)) throw UsageError("--on must lie in 0.05..2 s");
        if (!(gap >= 0.0 && gap <= 5.0)) throw UsageError("--gap must lie in 0..5 s");

        live::TactorOutput output(config);   // IoError / InputError before anything sounds
        tactile::TactileConfig tc;
        tc.motorCount = motors;
        tactile::TactileEngine engine;
        engine.prepare(tc);
        installInterruptHandlers();
        output.start();
        std::cerr << "armadillo tactors: " << output.describe() << "\n";
        constexpr double kStep = 0.005;   // the control rate of a live rig (200 Hz)
        double t = 0.0;
        const auto start = std::chrono::steady_clock::now();
        // Runs the engine for `seconds`, pushing each step to the output on the wall clock.
        const auto run = [&](double seconds) {
            const double end = t + seconds;
            while (t < end - 1e-9 && !interrupted()) {
                output.push(t, engine.tick(t == 0.0 ? 0.0 : kStep));
                t += kStep;
                std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(t)));
            }
        };
        run(0.1);
        for (int c = 0; c < output.channels() && !interrupted(); ++c) {
            const int m = config.map.motor[static_cast<std::size_t>(c)];
            const std::string port = config.device == "jack" ? " (tactor_" + std::to_string(c + 1) + ")" : "";
            if (m < 0) {
                std::cout << "channel " << c + 1 << port << ": silent (- in the map)\n" << std::flush;
                continue;
            }
            std::cout << "channel " << c + 1 << port << ": motor m" << m + 1 << ", " << motorPlace(m) << "\n" << std::flush;
            engine.setSoftLevel(m, static_cast<float>(level));
            run(on);
            engine.clearLevels();
            run(gap);
        }
        engine.allOff();
        output.push(t, engine.tick(kStep));
        run(0.05);
        output.stop();
        if (output.failed()) throw core::IoError("the tactor output stopped during the test (its JACK server or sound card went away)");
        return interrupted() ? int(core::kExitFailure) : int(core::kExitOk);
    });
}

} // namespace armadillo::cli
