#include "Cli/MqttOptions.h"
#include "Braille/Training.h"
#include "Core/Errors.h"

namespace armadillo::cli {

std::vector<OptionSpec> mqttBrokerOptionSpecs()
{
    return {
        {"--mqtt", "HOST[:PORT]", "the MQTT broker (default port 1883; docs/MQTT.md); over --mqtt-config's broker"},
        {"--mqtt-config", "FILE", "MQTT configuration (JSON, docs/MQTT.md): broker, client id, user/password, TLS CA file,\n"
                                  "protocol 3.1.1 or 5, keep-alive, reconnect back-off, message topics and text field"},
    };
}

std::vector<OptionSpec> mqttMessageOptionSpecs()
{
    return {
        {"--messages", "TOPIC", "with a broker (and, for play, --scene braille): show the messages of this topic on the arm\n"
                                "in Arm Braille (wildcards + and # allowed; repeatable), after the \"message waiting\" sensation"},
        {"--urgent", "TOPIC", "as --messages, and its messages interrupt the one being shown (repeatable)"},
        {"--message-display", "MODE", "roll (default: read it by rolling the arm, as any text) or timed (drawn cell by cell,\n"
                                      "framed by the sweep before and the double tap after)"},
        {"--message-shorthand", "", "the sign shorthand (thesis §5.3): a sign word of a message (EXIT, ENTRANCE ...) is\n"
                                    "shown as its shortest unique start (ex, en)"},
    };
}

bool readMqttOptions(const CommandLine& cl, mqtt::MqttConfig& config, const char* brokerOption)
{
    if (!cl.has(brokerOption) && !cl.has("--mqtt-config")) return false;
    if (cl.has("--mqtt-config")) config = mqtt::loadMqttConfig(cl.value("--mqtt-config"));
    if (cl.has(brokerOption)) {
        try {
            mqtt::parseBrokerAddress(cl.value(brokerOption), brokerOption, config.host, config.port);
        } catch (const core::InputError& e) {
            throw UsageError(e.what());
        }
    }
    return true;
}

namespace {

void addTopics(const CommandLine& cl, const char* option, bool urgent, mqtt::MqttConfig& config)
{
    for (const std::string& t : cl.values(option)) {
        if (const std::string why = mqtt::topicFilterProblem(t); !why.empty()) throw UsageError(std::string(option) + " '" + t + "': " + why);
        config.topics.push_back({t, 1, urgent});
    }
}

} // namespace

void PlayMessages::poll(live::LiveSession& session, std::ostream& err, const char* lineStart)
{
    const mqtt::MqttStatus s = session.messagesStatus();
    if (s.state != shownState_) {
        shownState_ = s.state;
        err << lineStart << who_ << "MQTT " << s.broker << ": " << mqtt::connectionStateName(s.state);
        if (s.state == mqtt::ConnectionState::Reconnecting && !s.lastError.empty()) err << " (" << s.lastError << ")";
        if (s.state == mqtt::ConnectionState::Connected && s.connects > 1) err << " again (reconnection " << s.connects - 1 << ")";
        err << "\n";
    }
    const mqtt::InboxStats in = session.messagesInbox();
    if (in.refused != shownRefused_) {
        shownRefused_ = in.refused;
        err << lineStart << who_ << in.lastRefusal << "\n";
    }
    if (in.droppedOldest != shownDropped_) {
        shownDropped_ = in.droppedOldest;
        err << lineStart << who_ << "the message queue was full: " << in.droppedOldest << " oldest message(s) dropped so far\n";
    }
    for (const std::string& line : session.presentMessages()) {
        err << lineStart << who_ << line << "\n";
        if (mirror_ && line.find(" on the arm: ") != std::string::npos) mirror_(line);
    }
}

/// For play: reads every MQTT option; null when there is no broker. UsageError for messages
/// without a broker or without the braille scene.
live::LiveConfig::Messages readPlayMessages(const CommandLine& cl, const std::string& scene, const std::vector<std::string>& parameters,
                                            const std::string& resourceDir)
{
    live::LiveConfig::Messages messages;
    mqtt::MqttConfig& config = messages.config;
    const bool broker = readMqttOptions(cl, config);
    const bool wantsMessages = cl.has("--messages") || cl.has("--urgent");
    for (const char* o : {"--message-display", "--message-shorthand"})
        if (cl.has(o) && !wantsMessages && (!broker || config.topics.empty())) throw UsageError(std::string(o) + " applies to --messages");
    if (!broker) {
        if (wantsMessages) throw UsageError("--messages needs a broker: --mqtt HOST[:PORT] or --mqtt-config FILE");
        return messages;
    }
    addTopics(cl, "--messages", false, config);
    addTopics(cl, "--urgent", true, config);
    // Without topics the broker serves the mapping's MQTT destinations only.
    if (!config.topics.empty() && scene != "braille") throw UsageError("--messages are read in Arm Braille: use --scene braille");
    mqtt::PresenterOptions& options = messages.options;
    const std::string display = cl.value("--message-display", "roll");
    if (display != "roll" && display != "timed") throw UsageError("--message-display: '" + display + "' (roll or timed)");
    options.timed = display == "timed";
    // The reader's grade and method, as the scene's --param sets them (labels: braille.grade=2,
    // braille.method=dots).
    for (const std::string& p : parameters) {
        if (p == "braille.grade=2") options.grade = 2;
        if (p.rfind("braille.method=", 0) == 0) braille::parseDisplayMethod(p.substr(15), options.method);
    }
    if (cl.has("--message-shorthand")) options.shorthand = braille::signShorthand(braille::defaultSignWords(resourceDir));
    messages.on = true;
    return messages;
}

} // namespace armadillo::cli
