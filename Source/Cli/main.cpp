// `armadillo`: the engine headless — fusion, rendering, the live device link and braille.
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/SceneOptions.h"
#include "Core/Types.h"
#include "Core/Version.h"
#include <iostream>
#include <sstream>

namespace armadillo::cli {

const std::vector<CommandInfo>& commands()
{
    static const std::vector<CommandInfo> table {
        {"ports", "list the serial ports found (name, description, USB ids)", runPorts},
        {"fuse", "offline orientation fusion of an IMU file with the SR-UKF", runFuse},
        {"render", "offline, deterministic run of a scene on a motion file (WAV + tactile CSV)", runRender},
        {"play", "the live engine headless: device/simulator/OSC in, motors and audio out", runPlay},
        {"braille", "the braille cells of a text and the row sensations the display shows", runBraille},
        {"resources", "where scores and other files are found; the scores playable by name", runResources},
        {"map", "mapping files (--map): check one, show a preset, learn a posture", runMap},
        {"score", "tactile scores from MIDI files and haptic files (score import FILE --out SCORE)", runScore},
        {"touch-profile", "the faintest level the reader feels on each motor, for --profile", runTouchProfile},
        {"calibrate", "the device calibration (thesis §2.4) step by step: Enter, s = skip, q = cancel", runCalibrate},
        {"tactors", "a tactor rig on a sound card or JACK: tactors test buzzes each channel in turn", runTactors},
        {"navigate", "walk a route guided by the arm alone: compass, arrivals, waypoint names (gpsd or simulated)", runNavigate},
        {"mqtt", "MQTT: check a broker (mqtt check --broker HOST[:PORT] --topic T)", runMqtt},
        {"read", "messages only: MQTT (and OSC) messages read on the arm in Arm Braille", runRead},
    };
    return table;
}

} // namespace armadillo::cli

namespace {

/// The top-level help; the man page (--man) is built from this same text.
std::string helpText()
{
    std::string s = "usage: armadillo COMMAND [options]    (armadillo COMMAND --help for each)\n"
                    "       armadillo --version | --help\n\n"
                    "ARMadillo: forearm orientation, instruments you feel, Arm Braille.\n\ncommands:\n";
    for (const auto& c : armadillo::cli::commands()) {
        std::string name = "  " + std::string(c.name);
        name.resize(16, ' ');
        s += name + c.summary + "\n";
    }
    s += "\noptions:\n"
         "  --version   print the version (" + std::string(armadillo::core::kVersion) + ") and exit\n"
         "  --help      this text\n"
         "\nscenes: " + armadillo::cli::sceneList() + "\n"
         "exit codes: 0 ok, 1 failure, 2 bad usage, 3 bad input, 4 device or I/O failure\n";
    return s;
}

/// One command's --help text, as the command itself prints it.
std::string commandHelp(const armadillo::cli::CommandInfo& c)
{
    std::ostringstream text;
    std::streambuf* const old = std::cout.rdbuf(text.rdbuf());
    c.run({"--help"});
    std::cout.rdbuf(old);
    return text.str();
}

/// Text for a roff no-fill block: backslashes doubled, a line's leading '.' or '\'' guarded.
std::string roffVerbatim(const std::string& text)
{
    std::string out;
    bool lineStart = true;
    for (const char ch : text) {
        if (lineStart && (ch == '.' || ch == '\'')) out += "\\&";
        if (ch == '\\') out += "\\e";
        else out += ch;
        lineStart = ch == '\n';
    }
    return out;
}

/// The manual page armadillo(1), generated at build time from the --help texts (so the two
/// never disagree). Not listed in --help: it is for the build, not for users.
void printManPage()
{
    std::cout << ".TH ARMADILLO 1 \"\" \"armadillo " << armadillo::core::kVersion << "\" \"User Commands\"\n"
              << ".SH NAME\narmadillo \\- forearm orientation, instruments you feel, Arm Braille\n"
              << ".SH SYNOPSIS\n.B armadillo\n.I COMMAND\n[options]\n"
              << ".SH DESCRIPTION\n.nf\n" << roffVerbatim(helpText()) << ".fi\n"
              << ".SH COMMANDS\n";
    for (const auto& c : armadillo::cli::commands())
        std::cout << ".SS " << c.name << "\n.nf\n" << roffVerbatim(commandHelp(c)) << ".fi\n";
    std::cout << ".SH FILES\n"
                 "Scores, braille word lists and example files are built into the program. Files in\n"
                 ".I $ARMADILLO_RESOURCES\n"
                 "and then in\n"
                 ".I ${XDG_DATA_HOME:-~/.local/share}/armadillo\n"
                 "add to them or override them (for example\n"
                 ".IR Scores/NAME.score );\n"
                 ".B armadillo resources\n"
                 "lists what is found.\n"
                 ".SH SEE ALSO\n"
                 "/usr/share/doc/armadillo/README.md, /usr/share/doc/armadillo/docs/INTERFACES.md\n";
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 2) {   // bad usage: the help goes to stderr, as every refusal does
        std::cerr << helpText();
        return armadillo::core::kExitUsage;
    }
    const std::string command = argv[1];
    if (command == "--help" || command == "-h" || command == "help") {
        std::cout << helpText();
        return armadillo::core::kExitOk;
    }
    if (command == "--version") {
        std::cout << "armadillo " << armadillo::core::kVersion << "\n";
        return armadillo::core::kExitOk;
    }
    if (command == "--man") {
        printManPage();
        return armadillo::core::kExitOk;
    }
    const armadillo::cli::Arguments args(argv + 2, argv + argc);
    for (const auto& c : armadillo::cli::commands())
        if (command == c.name) return c.run(args);
    std::cerr << "armadillo: unknown command '" << command << "' (see 'armadillo --help')\n";
    return armadillo::core::kExitUsage;
}
