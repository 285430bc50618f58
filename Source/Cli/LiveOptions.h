#pragma once
// The option groups of the live commands (play, read, navigate, the guided procedures), each
// declared once with its help and its parsing: the source (a device on a serial port, the
// simulator, an OSC sender), the left arm, and the outputs (sound, files, OSC out). A command
// takes a group whole, or picks the members that mean the same for it (pickOptions); the scene
// (SceneOptions.h), the mapping (MapOptions.h), the tactors (TactorOptions.h), MQTT
// (MqttOptions.h) and the reader's voice (ReaderIo.h) are groups of their own.
#include "Cli/CommandLine.h"
#include "Live/Session/LiveSession.h"
#include "Live/Stage/StageControl.h"
#include <string>
#include <vector>

namespace armadillo::cli {

/// --port, --simulate, --motion, --osc-in, --format, --osc-format, --mount, --calibrate-mount,
/// --baud, --v2, --calibration, --unpaced, --data-timeout.
std::vector<OptionSpec> sourceOptionSpecs();
/// --motion-left, --port-left, --osc-in-left, --osc-format-left, --mount-left,
/// --calibrate-mount-left, --calibration-left, --arms-log.
std::vector<OptionSpec> leftArmOptionSpecs();
/// --seconds, --out, --audio-device, --no-audio, --audio-in, --stem, --loop, --tactile, --log, --osc-out.
std::vector<OptionSpec> outputOptionSpecs();
/// The members of `group` named in `names`, in that order (a command that takes only some).
std::vector<OptionSpec> pickOptions(const std::vector<OptionSpec>& group, const std::vector<std::string>& names);

/// What the source group chose beyond the configuration.
struct SourceChoice {
    bool osc = false;        ///< the arm is an OSC sender (--osc-in, or --port with --format ngimu-slip)
    std::string mountOut;    ///< --calibrate-mount OUT.json ("" without it)
};
/// The source group into `config` (one of --port, --simulate, --osc-in; UsageError otherwise).
/// Files (mount, calibration) are read later, once every output was checked.
SourceChoice readSourceOptions(const CommandLine& cl, live::LiveConfig& config);
/// A guided procedure's device (touch-profile, calibrate, braille --adaptive): a port or the
/// simulator, from the source group.
struct DeviceChoice {
    std::string port;          ///< --port ("" with --simulate)
    int baud = 57600;          ///< --baud
    bool simulate = false;     ///< --simulate
};
/// Exactly one of --port and --simulate (UsageError saying so, with `usage` when given);
/// --baud only with --port.
DeviceChoice readDeviceOptions(const CommandLine& cl, const std::string& usage = {});
/// The left arm group into `config`; returns --calibrate-mount-left's file ("" without it).
std::string readLeftArmOptions(const CommandLine& cl, live::LiveConfig& config);
/// The outputs group into `config`; `soundByDefault`: the default sound card when neither --out
/// nor --audio-device nor --no-audio is given (a missing card is then a warning).
void readOutputOptions(const CommandLine& cl, live::LiveConfig& config, bool soundByDefault);

/// --control-bind, --control-allow: who reaches --control-in (docs/SECURITY.md).
std::vector<OptionSpec> controlListenOptionSpecs();
/// Those two into the listener's settings: loopback unless --control-bind says otherwise.
/// UsageError (exit 2) naming the option for an address that is not one, a malformed list, or
/// either option without --control-in.
live::StageControlListen readControlListenOptions(const CommandLine& cl);

/// --web PORT, --web-bind ADDR: the instrument as a web page (docs/INTERFACES.md "The web page").
std::vector<OptionSpec> webOptionSpecs();
/// Those two into config.web: UsageError (exit 2) for a port outside 0..65535, an address that is
/// not a numeric IPv4/IPv6 address, or --web-bind without --web.
void readWebOptions(const CommandLine& cl, live::LiveConfig& config);
/// After start(): the page's address on stderr ("armadillo play: web: http://127.0.0.1:PORT/");
/// with --web-bind the address with its token and a QR code of it. Nothing without --web.
void announceWebPage(live::LiveSession& session, const std::string& who);
/// What the page's server said since the last call (commands taken, clients refused), on stderr.
void reportWebPage(live::LiveSession& session, const std::string& who, const std::string& lineStart = {});

} // namespace armadillo::cli
