#pragma once
// The MQTT options of `play` and `mqtt check` (docs/MQTT.md, INTERFACES.md): the broker
// (--mqtt HOST[:PORT], --mqtt-config FILE) and, for play, messages shown on the arm
// (--messages TOPIC, --urgent TOPIC, --message-display timed|roll, --message-shorthand).
#include "Cli/CommandLine.h"
#include "Mapping/Mapper.h"
#include "Mqtt/ArmMessages.h"
#include "Mqtt/MessageService.h"
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

/// Messages on the arm during `play` and `read` (both run Cli/LiveCommand.h's session): the core's
/// MessageService (the client, its inbox and the presenter that hands the messages to the braille
/// scene, as the app uses it) with the command line's status lines and summary. Declared before
/// the session it serves, so it outlives it.
class PlayMessages {
public:
    PlayMessages(mqtt::MqttConfig config, mqtt::PresenterOptions options);
    ~PlayMessages();
    void start();
    /// Main loop: connection changes and what the presenter did, said on `err` (`scene`: the
    /// braille scene showing the messages; null when there are no message topics).
    void poll(braille::BrailleSceneControls* scene, std::ostream& err, const char* lineStart);
    bool wantsMessages() const noexcept { return !service_.config().topics.empty(); }
    /// The command whose stderr lines these are ("play", "read"): "armadillo NAME: …".
    void setCommand(const std::string& name) { who_ = "armadillo " + name + ": "; }
    /// Also tells each message handed to the arm here (play's --speak / --brlapi: ReaderIo::note),
    /// as the training's prompts are. Set before start().
    void setMirror(std::function<void(const std::string&)> mirror) { mirror_ = std::move(mirror); }
    /// A text from OSC (`--control-in`'s /armadillo/message): queued as a message from "osc".
    void offerText(const std::string& text, int priority) { service_.offerText(text, "osc", priority); }
    /// live::MqttSink for the mapping's MQTT destinations (real-time: the client's SPSC outbox).
    static bool publishMapped(void* self, const mapping::MqttMessage& message);
    void stop();
    /// ,"mqtt":{...} for the summary line.
    std::string summaryJson() const;

private:
    mqtt::MessageService service_;
    std::function<void(const std::string&)> mirror_;
    std::string who_ = "armadillo play: ";
    mqtt::ConnectionState shownState_ = mqtt::ConnectionState::Stopped;
    std::uint64_t shownRefused_ = 0, shownDropped_ = 0;
};

/// For play: every MQTT option read; null when there is no broker.
/// UsageError for messages without a broker or without the braille scene.
/// `parameters`: the scene's --param list (the reader's braille.grade and braille.method).
std::unique_ptr<PlayMessages> readPlayMessages(const CommandLine& cl, const std::string& scene, const std::vector<std::string>& parameters,
                                               const std::string& resourceDir);

} // namespace armadillo::cli
