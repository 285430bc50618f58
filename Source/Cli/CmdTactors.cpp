// `armadillo tactors test`: buzzes each channel of a tactor rig in turn and names it, so the
// wiring can be checked (issue 33, docs/TACTORS.md).
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/TactorOptions.h"
#include "Core/Clock.h"
#include "Core/Errors.h"
#include "Live/Outputs/TactorTest.h"
#include <iostream>

namespace armadillo::cli {

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

        live::TactorTest test(config, motors);   // IoError / InputError before anything sounds
        installInterruptHandlers();
        std::cerr << "armadillo tactors: " << test.describe() << "\n";
        test.run({level, on, gap},
                 [&](int c, int m) {
                     const std::string port = config.device == "jack" ? " (tactor_" + std::to_string(c + 1) + ")" : "";
                     if (m < 0) std::cout << "channel " << c + 1 << port << ": silent (- in the map)\n" << std::flush;
                     else std::cout << "channel " << c + 1 << port << ": motor m" << m + 1 << ", " << live::TactorTest::motorPlace(m) << "\n" << std::flush;
                 },
                 [] { return interrupted(); });
        return interrupted() ? int(core::kExitFailure) : int(core::kExitOk);
    });
}

} // namespace armadillo::cli
