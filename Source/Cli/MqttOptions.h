#pragma once
// The MQTT options of `play` and `mqtt check` (docs/MQTT.md, INTERFACES.md): the broker
// (--mqtt HOST[:PORT], --mqtt-config FILE) and, for play, messages shown on the arm
// (--messages TOPIC, --urgent TOPIC, --message-display timed|roll, --message-shorthand).
#include "Cli/CommandLine.h"
#include "Mapping/Mapper.h"
#include "Mqtt/ArmMessages.h"
#include "Live/Session/LiveSession.h"
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace armadillo::cli {

/// --mqtt and --mqtt-config (both commands).
std::vector<OptionSpec> mqttBrokerOptionSpecs();
/// --messages, --urgent, --message-display, --message-shorthand (play).
std::vector<OptionSpec> mqttMessageOptionSpecs();

/// The configuration --mqtt-config reads (InputError, exit 3, naming the file) with --mqtt's
/// broker over the file's; `topics` (from --messages / --urgent / --topic) are added to the file's.
/// False when neither option is given. `brokerOption`: the broker's option name (mqtt check: --broker).
bool readMqttOptions(const CommandLine& cl, mqtt::MqttConfig& config, const char* brokerOption = "--mqtt");

/// Messages on the arm during `play` and `read` (both run Cli/LiveCommand.h's session), as the
/// command line says them: the live session owns the service (LiveConfig::messages); this prints
/// its connection changes, refusals and what was shown on the arm.
class PlayMessages {
public:
    /// Main loop: connection changes and what the session handed to the arm, said on `err`.
    void poll(live::LiveSession& session, std::ostream& err, const char* lineStart);
    /// The command whose stderr lines these are ("play", "read"): "armadillo NAME: …".
    void setCommand(const std::string& name) { who_ = "armadillo " + name + ": "; }
    /// Also tells each message handed to the arm here (play's --speak / --brlapi: ReaderIo::note),
    /// as the training's prompts are.
    void setMirror(std::function<void(const std::string&)> mirror) { mirror_ = std::move(mirror); }

private:
    std::function<void(const std::string&)> mirror_;
    std::string who_ = "armadillo play: ";
    mqtt::ConnectionState shownState_ = mqtt::ConnectionState::Stopped;
    std::uint64_t shownRefused_ = 0, shownDropped_ = 0;
};

/// For play: every MQTT option read into the session's description (`on` false when there is no
/// broker). UsageError for messages without a broker or without the braille scene.
/// `parameters`: the scene's --param list (the reader's braille.grade and braille.method).
live::LiveConfig::Messages readPlayMessages(const CommandLine& cl, const std::string& scene, const std::vector<std::string>& parameters,
                                            const std::string& resourceDir);

} // namespace armadillo::cli
