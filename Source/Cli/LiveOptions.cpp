#include "Cli/LiveOptions.h"
#include "Cli/SceneOptions.h"
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Osc/HostPort.h"
#include "Link/Mount.h"
#include "Osc/OscDialects.h"
#include "Web/QrText.h"
#include <iostream>
#include <stdexcept>

namespace armadillo::cli {

std::vector<OptionSpec> controlListenOptionSpecs()
{
    return {
        {"--control-bind", "ADDR", "with --control-in: the address it listens on (default 127.0.0.1: this machine only);\n"
                                   "an interface's address, or 0.0.0.0 (every IPv4 interface) or :: (every interface)\n"
                                   "for a tablet on stage; see --control-allow (docs/SECURITY.md)"},
        {"--control-allow", "ADDR[/BITS],...", "with --control-in: only these senders (IPv4 or IPv6, with an optional prefix\n"
                                               "length: 192.168.1.23,10.0.0.0/24); a datagram from anyone else is refused,\n"
                                               "counted and its sender named once on stderr"},
    };
}

live::StageControlListen readControlListenOptions(const CommandLine& cl)
{
    live::StageControlListen listen;
    if (!cl.has("--control-in")) {
        for (const char* o : {"--control-bind", "--control-allow"})
            if (cl.has(o)) throw UsageError(std::string(o) + " sets who reaches the stage-control port: give --control-in PORT too");
        return listen;
    }
    if (cl.has("--control-bind")) {
        listen.bind = cl.value("--control-bind");
        if (!osc::isIpAddress(listen.bind))
            throw UsageError("--control-bind: '" + listen.bind + "' is not an IPv4 or IPv6 address (such as 127.0.0.1, 192.168.1.20, 0.0.0.0 or ::)");
    }
    if (cl.has("--control-allow")) {
        try {
            listen.allow = osc::AllowList::parse(cl.value("--control-allow"));
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--control-allow: ") + e.what());
        }
    }
    return listen;
}

std::vector<OptionSpec> webOptionSpecs()
{
    return {
        {"--web", "PORT", "the running instrument as a web page at http://127.0.0.1:PORT/ (0 = a free port; the address\n"
                          "is printed on stderr): status, orientation, stage, scene parameters, messages, the walk, the\n"
                          "device calibration (docs/INTERFACES.md \"The web page\"); this machine only unless --web-bind"},
        {"--web-bind", "ADDR", "with --web: listen on this address of the machine instead (0.0.0.0 or :: for every\n"
                               "interface: a phone on the Wi-Fi); every request then needs the session's token, which\n"
                               "the printed address and its QR code carry (docs/SECURITY.md)"},
    };
}

void readWebOptions(const CommandLine& cl, live::LiveConfig& config)
{
    if (!cl.has("--web")) {
        if (cl.has("--web-bind")) throw UsageError("--web-bind sets where the web page listens: give --web PORT too");
        return;
    }
    config.web.on = true;
    config.web.port = static_cast<int>(cl.integer("--web", 0, 0, 65535));
    if (cl.has("--web-bind")) {
        config.web.bind = cl.value("--web-bind");
        if (!web::isNumericAddress(config.web.bind))
            throw UsageError("--web-bind: '" + config.web.bind + "' is not an IPv4 or IPv6 address (such as 127.0.0.1, 192.168.1.20, 0.0.0.0 or ::)");
    }
}

void announceWebPage(live::LiveSession& session, const std::string& who)
{
    web::WebServer* server = session.webServer();
    if (server == nullptr) return;
    const std::string address = server->address();
    std::cerr << who << "web: " << address << "\n";
    if (!server->tokenRequired()) return;
    std::cerr << who << "web: open on the network; the address carries the session's token (scan to open it on a phone):\n";
    for (const std::string& line : web::qrLines(address)) std::cerr << line << "\n";
}

void reportWebPage(live::LiveSession& session, const std::string& who, const std::string& lineStart)
{
    if (web::WebServer* server = session.webServer())
        for (const std::string& line : server->takeLines()) std::cerr << lineStart << who << "web: " << line << "\n";
}

std::vector<OptionSpec> sourceOptionSpecs()
{
    return {
        {"--port", "NAME", "serial port of the device (see `armadillo ports`; ptys and /dev/rfcomm* work too)"},
        {"--simulate", "", "the built-in simulated forearm (in-process, paced like a 57 600-baud link)"},
        {"--motion", "FILE", "with --simulate: pose or quaternion CSV to act out (looped); default a wandering arm"},
        {"--osc-in", "PORT", "listen for OSC sensor messages on this UDP port, and on the same TCP port (ZIG SIM's\n"
                             "TCP option), no motor output; OSC and ZIG SIM's JSON are told apart by their first\n"
                             "byte; the sender's format is detected from its first messages and printed"},
        {"--format", "NAME", "with --port: what the serial port speaks: thesis (the board's protocol, default) or\n"
                             "ngimu-slip (an NGIMU over USB: SLIP-framed OSC, read like --osc-in)"},
        {"--osc-format", "NAME", "with --osc-in: force the sender's format (auto, armadillo, sensors2osc, zigsim,\n"
                                 "gyrosc, touchosc, ngimu)"},
        {"--mount", "FILE|PRESET", "with --osc-in: how the sensor is strapped on: a mount file (--calibrate-mount) or a\n"
                                   "preset (identity, phone-screen-up, phone-screen-up-top-to-elbow, ngimu); default: the\n"
                                   "format's usual one (phones: phone-screen-up)"},
        {"--calibrate-mount", "OUT.json", "with --osc-in: the guided mount calibration (arm level ahead, arm hanging down,\n"
                                          "optionally a quarter roll); instructions on stderr; writes OUT.json for --mount"},
        {"--baud", "B", "serial speed (default 57600, 8N1)"},
        {"--v2", "", "with --port: offer the v2 framing (sequence numbers, CRC, the board's clock;\n"
                     "docs/DEVICE.md 2b) on every connect; a board that does not take it gets v1 as\n"
                     "usual. The summary then adds \"v2\", \"seq_gaps\" and \"crc_failures\""},
        {"--calibration", "CAL.json", "device calibration (default: the built-in one, which matches the simulator)"},
        {"--unpaced", "", "with --simulate: no wire pacing (as fast as the host can go)"},
        {"--data-timeout", "SECONDS", "with --port or --osc-in (and --port-left, --osc-in-left): no usable sensor data from\n"
                                      "either arm within this time is an error naming the port and what was heard instead\n"
                                      "(exit 4; default 5, 0 = wait for ever)"},
    };
}

std::vector<OptionSpec> leftArmOptionSpecs()
{
    return {
        {"--motion-left", "FILE", "two arms: with --simulate, a second simulated forearm (the left arm) acting out FILE\n"
                                  "(pose or quaternion CSV; - = a wandering arm); scenes see both arms"},
        {"--port-left", "NAME", "two arms: the left arm's own device (its motor packets go back to it)"},
        {"--osc-in-left", "PORT", "two arms: the left arm is an OSC sender on this UDP (and TCP) port, read like --osc-in\n"
                                  "(format detected, its own mount); with any right-arm source"},
        {"--osc-format-left", "NAME", "with --osc-in-left: force the left sender's format (as --osc-format)"},
        {"--mount-left", "FILE|PRESET", "with --osc-in-left: how the left arm's sensor is strapped on (as --mount)"},
        {"--calibrate-mount-left", "OUT.json", "with --osc-in-left: the guided mount calibration of the left arm's sensor\n"
                                               "(as --calibrate-mount; instructions on stderr prefixed 'left arm')"},
        {"--calibration-left", "CAL.json", "the left arm's device calibration (default: the built-in one)"},
        {"--arms-log", "A.csv", "two arms: t,qw,qx,qy,qz,left_qw,left_qx,left_qy,left_qz per control update"},
    };
}

std::vector<OptionSpec> outputOptionSpecs()
{
    return {
        {"--seconds", "N", "stop after N seconds (default: run until interrupted)"},
        {"--out", "OUT.wav", "record the scene's audio, 16-bit stereo, instead of playing it. Recordings (--out, --log,\n"
                             "--tactile, --arms-log) are readable under their own name while they grow (a crash\n"
                             "keeps all but the last second); a file already there is kept as NAME.1 (docs/SECURITY.md)"},
        {"--audio-device", "NAME", "ALSA device to play on (default: 'default'; e.g. hw:1, plughw:1,0); an error if it\n"
                                   "cannot be opened"},
        {"--no-audio", "", "no sound at all (no --out, no sound card)"},
        {"--audio-in", "FILE.wav", "a recording to play out (to the sound card or --out, under the scene's sound) while\n"
                                   "scenes that listen (score, audio-touch, layered-keyboard) follow it; its sample rate is used unless\n"
                                   "--sample-rate is given. Given several times, each file is a stem named by its file\n"
                                   "name (drums.wav, bass.wav ...), as --stem"},
        {"--stem", "NAME=FILE.wav", "audio-touch: a stem felt apart on its own motors (drums, bass, other, vocals;\n"
                                    "repeatable; docs/INSTRUMENTS.md); the stems are played out together"},
        {"--loop", "", "with --audio-in or --stem: start the recording again at its end (without it, the session\n"
                       "ends with the recording unless --seconds ends it first)"},
        {"--tactile", "T.csv", "every motor packet: t,m1..m9; the last row is the all-off sent at the end"},
        {"--log", "SESSION.csv", "one row per sensor packet: t, raw counts, calibrated SI values, qw,qx,qy,qz"},
        {"--osc-out", "HOST:PORT", "send orientation, pose, gyro, motors and gestures as OSC; with --map, the target of\n"
                                   "the mapping's OSC destinations that name none (and only those are sent)"},
    };
}

std::vector<OptionSpec> pickOptions(const std::vector<OptionSpec>& group, const std::vector<std::string>& names)
{
    std::vector<OptionSpec> o;
    for (const std::string& name : names)
        for (const OptionSpec& s : group)
            if (s.name == name) o.push_back(s);
    return o;
}

SourceChoice readSourceOptions(const CommandLine& cl, live::LiveConfig& config)
{
    SourceChoice choice;
    const int sources = int(cl.has("--port")) + int(cl.has("--simulate")) + int(cl.has("--osc-in"));
    if (sources != 1) throw UsageError("choose exactly one source: --port NAME, --simulate or --osc-in PORT");
    if (cl.has("--motion") && !cl.has("--simulate")) throw UsageError("--motion drives the simulator: use it with --simulate");
    if (cl.has("--unpaced") && !cl.has("--simulate")) throw UsageError("--unpaced applies to --simulate");
    if (cl.has("--baud") && !cl.has("--port")) throw UsageError("--baud applies to --port");
    if (cl.has("--v2") && !cl.has("--port")) throw UsageError("--v2 applies to --port");
    const std::string portFormat = cl.has("--format") ? cl.value("--format") : std::string("thesis");
    if (cl.has("--format") && !cl.has("--port")) throw UsageError("--format applies to --port (--osc-in detects its format; --osc-format forces one)");
    if (portFormat != "thesis" && portFormat != "ngimu-slip")
        throw UsageError("--format: unknown serial format '" + portFormat + "' (thesis or ngimu-slip)");
    const bool slipOsc = cl.has("--port") && portFormat == "ngimu-slip";
    if (slipOsc) {
        // The NGIMU over USB: SLIP-framed OSC through the same serial code as the board.
        config.source = live::LiveConfig::Source::Osc;
        config.oscSerialPort = cl.value("--port");
        if (config.oscSerialPort.empty()) throw UsageError("--port needs a device name");
        config.oscSerialBaud = static_cast<int>(cl.integer("--baud", 115200, 300, 4000000));
        if (cl.has("--v2")) throw UsageError("--v2 is the thesis board's framing: not with --format ngimu-slip");
    } else if (cl.has("--port")) {
        config.source = live::LiveConfig::Source::Port;
        config.port = cl.value("--port");
        if (config.port.empty()) throw UsageError("--port needs a device name");
        config.baud = static_cast<int>(cl.integer("--baud", 57600, 300, 4000000));
        config.link.link.negotiateV2 = cl.has("--v2");
    } else if (cl.has("--simulate")) {
        config.source = live::LiveConfig::Source::Simulator;
        config.motionFile = cl.value("--motion");
        config.simulatorBaud = cl.has("--unpaced") ? 0.0 : 57600.0;
    } else {
        config.source = live::LiveConfig::Source::Osc;
        config.oscInPort = static_cast<int>(cl.integer("--osc-in", 0, 1, 65535));
    }
    const bool oscSource = cl.has("--osc-in") || slipOsc;
    choice.osc = oscSource;
    for (const char* o : {"--osc-format", "--mount", "--calibrate-mount"})
        if (cl.has(o) && !oscSource) throw UsageError(std::string(o) + " applies to --osc-in (or --port with --format ngimu-slip)");
    if (cl.has("--osc-format") && !osc::parseOscFormat(cl.value("--osc-format"), config.osc.format))
        throw UsageError("--osc-format: unknown format '" + cl.value("--osc-format") + "' (one of " + osc::oscFormatNames() + ")");
    const std::string mountOut = cl.value("--calibrate-mount");
    choice.mountOut = mountOut;
    if (cl.has("--calibrate-mount") && mountOut.empty()) throw UsageError("--calibrate-mount needs an output file");
    if (cl.has("--calibrate-mount") && cl.has("--mount")) throw UsageError("--calibrate-mount finds the mount: it cannot go with --mount");
    if (!mountOut.empty()) {   // the calibration sees the sensor's own axes
        config.osc.mountGiven = true;
        config.osc.mount = link::Mount {};
    }

    if (cl.has("--calibrate") && oscSource) throw UsageError("--calibrate needs raw counts: use --port or --simulate");
    return choice;
}

std::string readLeftArmOptions(const CommandLine& cl, live::LiveConfig& config)
{
    if (int(cl.has("--motion-left")) + int(cl.has("--port-left")) + int(cl.has("--osc-in-left")) > 1)
        throw UsageError("the left arm is --motion-left (simulated), --port-left (a device) or --osc-in-left (an OSC sender): one of them");
    for (const char* o : {"--osc-format-left", "--mount-left", "--calibrate-mount-left"})
        if (cl.has(o) && !cl.has("--osc-in-left")) throw UsageError(std::string(o) + " applies to --osc-in-left");
    const std::string leftMountOut = cl.value("--calibrate-mount-left");
    if (cl.has("--calibrate-mount-left") && leftMountOut.empty()) throw UsageError("--calibrate-mount-left needs an output file");
    if (cl.has("--calibrate-mount-left") && cl.has("--mount-left"))
        throw UsageError("--calibrate-mount-left finds the mount: it cannot go with --mount-left");
    if (cl.has("--motion-left")) {
        if (!cl.has("--simulate")) throw UsageError("--motion-left drives a second simulated arm: use it with --simulate");
        config.leftSource = live::LiveConfig::LeftSource::Simulator;
        config.leftMotionFile = cl.value("--motion-left") == "-" ? std::string() : cl.value("--motion-left");
        if (cl.value("--motion-left").empty()) throw UsageError("--motion-left needs a motion file (or - for a wandering arm)");
    } else if (cl.has("--port-left")) {
        config.leftSource = live::LiveConfig::LeftSource::Port;
        config.leftPort = cl.value("--port-left");
        if (config.leftPort.empty()) throw UsageError("--port-left needs a device name");
        config.leftBaud = static_cast<int>(cl.integer("--baud", 57600, 300, 4000000));
    } else if (cl.has("--osc-in-left")) {
        config.leftSource = live::LiveConfig::LeftSource::Osc;
        config.leftOscInPort = static_cast<int>(cl.integer("--osc-in-left", 0, 1, 65535));
        if (config.source == live::LiveConfig::Source::Osc && config.oscSerialPort.empty() && config.oscInPort == config.leftOscInPort)
            throw UsageError("--osc-in-left needs a port of its own (--osc-in listens on " + std::to_string(config.oscInPort) + ")");
        if (cl.has("--osc-format-left") && !osc::parseOscFormat(cl.value("--osc-format-left"), config.leftOsc.format))
            throw UsageError("--osc-format-left: unknown format '" + cl.value("--osc-format-left") + "' (one of " + osc::oscFormatNames() + ")");
    }
    for (const char* o : {"--calibration-left", "--arms-log"})
        if (cl.has(o) && config.leftSource == live::LiveConfig::LeftSource::None)
            throw UsageError(std::string(o) + " applies to two arms (--motion-left, --port-left or --osc-in-left)");
    if (cl.has("--calibration-left") && config.leftSource == live::LiveConfig::LeftSource::Osc)
        throw UsageError("--calibration-left is a device's calibration: an OSC sender sends SI units (--mount-left says how it is worn)");
    if (cl.has("--calibration-left")) config.leftCalibration = link::loadCalibration(cl.value("--calibration-left"));
    config.armsLog = cl.value("--arms-log");
    return leftMountOut;
}

void readOutputOptions(const CommandLine& cl, live::LiveConfig& config, bool soundByDefault)
{
    const double seconds = cl.number("--seconds", -1.0);
    if (cl.has("--seconds") && !(seconds > 0.0 && seconds <= 7 * 24 * 3600.0))
        throw UsageError("--seconds must be a positive number of seconds (at most a week)");
    if (cl.has("--osc-out")) {
        config.oscOut = cl.value("--osc-out");
        try {
            osc::parseHostPort(config.oscOut);
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--osc-out: ") + e.what());
        }
    }
    config.audioOut = cl.value("--out");
    const int audioChoices = int(cl.has("--out")) + int(cl.has("--audio-device")) + int(cl.has("--no-audio"));
    if (audioChoices > 1) throw UsageError("choose one of --out FILE, --audio-device NAME and --no-audio");
    if (cl.has("--tactor-sound") && cl.has("--no-audio")) throw UsageError("--tactor-sound hands the scene's sound to the tactors: drop --no-audio");
    if (cl.has("--audio-device")) {
        config.soundCard = cl.value("--audio-device");
        if (config.soundCard.empty()) throw UsageError("--audio-device needs an ALSA device name");
    } else if (!cl.has("--out") && !cl.has("--no-audio") && soundByDefault) {   // (read: the braille scene is silent)
        config.soundCard = "default";
        config.soundCardOptional = true;   // headless machines have none: say so, play on
    }
    config.tactileOut = cl.value("--tactile");
    config.logOut = cl.value("--log");
    config.audioStems = readStemOptions(cl, config.engine);
    if (!config.audioStems.empty() && cl.has("--no-audio")) throw UsageError("stems are played out: they cannot go with --no-audio");
    if (config.audioStems.empty() && cl.has("--audio-in")) {
        if (cl.value("--audio-in").empty()) throw UsageError("--audio-in needs a WAV file");
        if (cl.has("--no-audio")) throw UsageError("--audio-in plays the recording out: it cannot go with --no-audio");
        config.audioIn = cl.value("--audio-in");
    }
    config.audioInLoop = cl.has("--loop");
    if (cl.has("--loop") && !cl.has("--audio-in") && !cl.has("--stem"))
        throw UsageError("--loop repeats the --audio-in recording: use it with --audio-in or --stem");
}

DeviceChoice readDeviceOptions(const CommandLine& cl, const std::string& usage)
{
    if (cl.has("--port") == cl.has("--simulate"))
        throw UsageError(usage.empty() ? std::string("choose exactly one of --port NAME and --simulate") : usage);
    if (cl.has("--baud") && !cl.has("--port")) throw UsageError("--baud applies to --port");
    DeviceChoice d;
    d.port = cl.value("--port");
    d.simulate = cl.has("--simulate");
    d.baud = static_cast<int>(cl.integer("--baud", 57600, 300, 4000000));
    return d;
}

} // namespace armadillo::cli
