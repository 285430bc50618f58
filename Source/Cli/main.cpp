// `armadillo`: the engine headless — fusion, rendering, the live device link and braille.
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Core/Types.h"
#include <iostream>

namespace armadillo::cli {

const std::vector<CommandInfo>& commands()
{
    static const std::vector<CommandInfo> table {
        {"ports", "list the serial ports found (name, description, USB ids)", runPorts},
        {"fuse", "offline orientation fusion of an IMU file with the SR-UKF", runFuse},
        {"render", "offline, deterministic run of a scene on a motion file (WAV + tactile CSV)", runRender},
        {"play", "the live engine headless: device/simulator/OSC in, motors and audio out", runPlay},
        {"braille", "the braille cells of a text and the row sensations the display shows", runBraille},
    };
    return table;
}

} // namespace armadillo::cli

namespace {
void printHelp()
{
    std::cout << "usage: armadillo COMMAND [options]    (armadillo COMMAND --help for each)\n\n"
                 "ARMadillo: forearm orientation, instruments you feel, Arm Braille.\n\ncommands:\n";
    for (const auto& c : armadillo::cli::commands()) {
        std::string name = "  " + std::string(c.name);
        name.resize(12, ' ');
        std::cout << name << c.summary << "\n";
    }
    std::cout << "\nscenes: monitor theremin cymbal panel sound-design compass braille score\n"
                 "exit codes: 0 ok, 1 failure, 2 bad usage, 3 bad input, 4 device or I/O failure\n";
}
} // namespace

int main(int argc, char** argv)
{
    if (argc < 2) {
        printHelp();
        return armadillo::kExitUsage;
    }
    const std::string command = argv[1];
    if (command == "--help" || command == "-h" || command == "help") {
        printHelp();
        return armadillo::kExitOk;
    }
    if (command == "--version") {
        std::cout << "armadillo 0.1.0\n";
        return armadillo::kExitOk;
    }
    const armadillo::cli::Arguments args(argv + 2, argv + argc);
    for (const auto& c : armadillo::cli::commands())
        if (command == c.name) return c.run(args);
    std::cerr << "armadillo: unknown command '" << command << "' (see 'armadillo --help')\n";
    return armadillo::kExitUsage;
}
