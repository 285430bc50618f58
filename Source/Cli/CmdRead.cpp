// `armadillo read`: for a reader who wants only messages (issue 35, docs/MQTT.md). The braille
// scene with no text of its own (SceneConfig::messagesOnly) in play's live session
// (Cli/LiveCommand.h): the same source handling, MQTT client, presenter and status lines, so a
// message is shown exactly as `play --scene braille --mqtt … --messages …` shows it.
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/LiveCommand.h"
#include "Cli/SceneOptions.h"
#include <algorithm>

namespace armadillo::cli {

namespace {

/// read's options: play's own (same names, same help) where they mean the same here, and its own.
std::vector<OptionSpec> readOptionSpecs()
{
    const std::vector<std::string> fromPlay {"--port", "--simulate", "--motion", "--unpaced", "--baud", "--v2", "--calibration",
                                             "--seconds", "--tactile", "--log", "--osc-out", "--status-file", "--arm", "--profile",
                                             "--mqtt", "--mqtt-config", "--messages", "--urgent", "--message-display",
                                             "--message-shorthand", "--speak", "--speech", "--rate", "--brlapi", "--braille-display",
                                             "--control-bind", "--control-allow", "--web", "--web-bind"};
    const std::vector<OptionSpec> all = playOptionSpecs();
    std::vector<OptionSpec> o;
    for (const std::string& name : fromPlay) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const OptionSpec& s) { return s.name == name; });
        if (it != all.end()) o.push_back(*it);
    }
    const std::vector<OptionSpec> own {
        {"--grade", "1|2", "1 = uncontracted (default), 2 = contracted braille (as `armadillo braille --grade`)"},
        {"--method", "M", "how a cell is shown: rows (default), whole, columns, dots (docs/BRAILLE.md)"},
        {"--param", "ID=VALUE", "a braille scene parameter (repeatable): braille.level, braille.step, braille.passiveOn …\n"
                                "(docs/BRAILLE.md); not braille.mode, and --grade / --method for grade and method"},
        {"--data-timeout", "SECONDS", "with --port: no usable sensor data within this time is an error naming the port and\n"
                                      "what was heard instead (exit 4; default 5, 0 = wait for ever)"},
        {"--control-in", "PORT", "OSC on this UDP port (127.0.0.1 unless --control-bind): /armadillo/message \"text\" [priority]\n"
                                 "is a message too (priority >= 1: urgent); /armadillo/panic and /armadillo/resume as in play\n"
                                 "(docs/STAGE.md)"},
    };
    o.insert(o.end(), own.begin(), own.end());
    return o;
}

} // namespace

void readReaderOptions(const CommandLine& cl, engine::EngineConfig& engine)
{
    engine.scene = "braille";
    engine.sceneConfig.messagesOnly = true;
    const std::string arm = cl.value("--arm", "right");
    if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
    engine.sceneConfig.side = arm == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    for (const std::string& p : cl.values("--param")) {
        for (const char* own : {"braille.mode=", "braille.grade=", "braille.method="})
            if (p.rfind(own, 0) == 0)
                throw UsageError("--param " + p + ": read shows messages only (no mode of its own); --grade and --method choose grade and method");
        if (const std::string problem = engine::sceneParameterProblem("braille", p); !problem.empty()) throw UsageError("--param " + p + ": " + problem);
        engine.parameters.push_back(p);
    }
    if (cl.has("--grade")) {
        const std::string g = cl.value("--grade");
        if (g != "1" && g != "2") throw UsageError("--grade: '" + g + "' (1 or 2)");
        engine.parameters.push_back("braille.grade=" + g);
    }
    if (cl.has("--method")) {
        const std::string p = "braille.method=" + cl.value("--method");
        if (const std::string problem = engine::sceneParameterProblem("braille", p); !problem.empty())
            throw UsageError("--method: '" + cl.value("--method") + "' (rows, whole, columns or dots)");
        engine.parameters.push_back(p);
    }
    readProfileOption(cl, engine);
}

int runRead(const Arguments& args)
{
    return guarded("read", [&] {
        CommandLine cl(
            "read", "--mqtt HOST[:PORT] --messages TOPIC... (--port NAME | --simulate) [options]",
            "Messages only, for a reader who wants nothing else on the arm: the braille scene with no text\n"
            "of its own. Each message published on a --messages topic (or sent as OSC /armadillo/message to\n"
            "--control-in) is shown in Arm Braille exactly as `play --scene braille --mqtt ... --messages ...`\n"
            "shows it: the \"message waiting\" sensation, the sweep, the message read by rolling the arm\n"
            "(--message-display roll, the default) or drawn cell by cell (timed), two taps at its end.\n"
            "Between messages the arm is still. A broker that is down or goes away is retried (stderr says\n"
            "so); a port missing at start is exit 4. Runs for --seconds or until SIGINT/SIGTERM, turns every\n"
            "motor off and prints play's JSON summary line with \"mqtt\":{...} (docs/MQTT.md).",
            readOptionSpecs());
        if (!cl.parse(args)) return 0;
        if (int(cl.has("--port")) + int(cl.has("--simulate")) != 1)
            throw UsageError("choose one source: --port NAME (the device) or --simulate");
        return runLiveSession(cl, {"read", true});
    });
}

} // namespace armadillo::cli
