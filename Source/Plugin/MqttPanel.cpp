#include "Plugin/MqttPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"

namespace armadillo::plugin {

MqttPanel::MqttPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    auto& settings = processor_.settings();
    heading_.setText("Messages on the arm over MQTT", juce::dontSendNotification);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    brokerLabel_.setText("Broker", juce::dontSendNotification);
    topicsLabel_.setText("Topics", juce::dontSendNotification);
    urgentLabel_.setText("Urgent topics", juce::dontSendNotification);
    configLabel_.setText("Configuration", juce::dontSendNotification);
    displayLabel_.setText("Shown", juce::dontSendNotification);
    status_.setTitle("MQTT status");
    status_.setJustificationType(juce::Justification::topLeft);
    configFile_.setTitle("Configuration file name");
    for (auto* l : {&heading_, &brokerLabel_, &topicsLabel_, &urgentLabel_, &configLabel_, &configFile_, &displayLabel_, &status_}) addAndMakeVisible(*l);

    describe(broker_, "MQTT broker", "The broker's host and port, such as localhost:1883 (Mosquitto, Home Assistant's broker).");
    broker_.setText(settings[SettingIds::mqttBroker].toString(), false);
    describe(topics_, "Message topics", "Topics whose messages are read on the arm, comma-separated; + and # wildcards allowed.");
    topics_.setText(settings[SettingIds::mqttTopics].toString(), false);
    describe(urgent_, "Urgent topics", "Topics whose messages interrupt what is being read (a door's bell, an alarm).");
    urgent_.setText(settings[SettingIds::mqttUrgent].toString(), false);
    commitOnEnter(broker_, processor_.settings(), SettingIds::mqttBroker);
    commitOnEnter(topics_, processor_.settings(), SettingIds::mqttTopics);
    commitOnEnter(urgent_, processor_.settings(), SettingIds::mqttUrgent);
    describe(display_, "How messages are shown", "Read by rolling the arm as any text, or drawn by themselves, timed, framed as the training frames a cell.");
    display_.addItem("read by rolling the arm", 1);
    display_.addItem("timed, by themselves", 2);
    display_.setSelectedId(settings[SettingIds::messageDisplay].toString() == "timed" ? 2 : 1, juce::dontSendNotification);
    display_.onChange = [this] { processor_.settings().setProperty(SettingIds::messageDisplay, display_.getSelectedId() == 2 ? "timed" : "roll", nullptr); };
    describe(chooseConfig_, "MQTT configuration file", "Choose a configuration file (docs/MQTT.md: TLS, user, the JSON text field, the queue).");
    chooseConfig_.onClick = [this] {
        chooser_ = std::make_unique<juce::FileChooser>("Choose an MQTT configuration", juce::File(), "*.json");
        chooser_->launchAsync(juce::FileBrowserComponent::canSelectFiles | juce::FileBrowserComponent::openMode, [this](const juce::FileChooser& fc) {
            if (fc.getResult() != juce::File()) processor_.settings().setProperty(SettingIds::mqttConfig, fc.getResult().getFullPathName(), nullptr);
        });
    };
    describe(clearConfig_, "No configuration file", "Use the broker and topics above alone.");
    clearConfig_.onClick = [this] { processor_.settings().setProperty(SettingIds::mqttConfig, "", nullptr); };
    describe(connect_, "Connect to the broker", "Connect and subscribe; messages then wait for the braille scene, which shows them on the arm.");
    connect_.onClick = [this] {
        for (auto* e : {&broker_, &topics_, &urgent_}) e->onReturnKey();   // what was typed counts
        const auto why = processor_.setMessages(connect_.getToggleState());
        connect_.setToggleState(processor_.messages().running(), juce::dontSendNotification);
        say(why.isNotEmpty() ? why : (processor_.messages().running() ? juce::String("Connecting to ") + broker_.getText() : juce::String("Disconnected")));
    };
    describe(test_, "Send a test message", "Publish a short message to the first topic: it comes back through the broker and is shown like any message.");
    test_.onClick = [this] {
        auto* service = processor_.messages().service();
        if (service == nullptr || service->config().topics.empty()) {
            say("Connect with a topic first");
            return;
        }
        const auto& topic = service->config().topics.front().filter;
        if (topic.find_first_of("+#") != std::string::npos) {
            say("The first topic has a wildcard: publish to a concrete topic from elsewhere");
            return;
        }
        say(service->publishText(topic, "test") ? "Sent 'test' to " + juce::String(topic) : juce::String("The test message could not be queued"));
    };
    for (auto* c : std::initializer_list<juce::Component*> {&broker_, &topics_, &urgent_, &display_, &chooseConfig_, &clearConfig_, &connect_, &test_})
        addAndMakeVisible(*c);
    timerCallback();
    startTimerHz(4);
}

MqttPanel::~MqttPanel()
{
    stopTimer();
}

void MqttPanel::say(const juce::String& text)
{
    said_ = text;
    announce(processor_, "mqtt", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
    timerCallback();
}

void MqttPanel::timerCallback()
{
    const auto file = processor_.settings()[SettingIds::mqttConfig].toString();
    configFile_.setText(file.isEmpty() ? "none" : juce::File(file).getFileName(), juce::dontSendNotification);
    connect_.setToggleState(processor_.messages().running(), juce::dontSendNotification);
    test_.setEnabled(processor_.messages().running());
    juce::String line = "Status: " + juce::String(processor_.messages().describe());
    if (said_.isNotEmpty()) line << "\n" << said_;
    status_.setText(line, juce::dontSendNotification);
}

void MqttPanel::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff16202a));
}

void MqttPanel::resized()
{
    auto area = getLocalBounds().reduced(12);
    heading_.setBounds(area.removeFromTop(24));
    const auto row = [&area] { return takeRow(area); };
    constexpr int labelWidth = 120;
    auto r = row();
    brokerLabel_.setBounds(r.removeFromLeft(labelWidth));
    connect_.setBounds(r.removeFromRight(110));
    broker_.setBounds(r.reduced(0, 2));
    r = row();
    topicsLabel_.setBounds(r.removeFromLeft(labelWidth));
    topics_.setBounds(r.reduced(0, 2));
    r = row();
    urgentLabel_.setBounds(r.removeFromLeft(labelWidth));
    urgent_.setBounds(r.reduced(0, 2));
    r = row();
    displayLabel_.setBounds(r.removeFromLeft(labelWidth));
    display_.setBounds(r.removeFromLeft(260).reduced(0, 2));
    r = row();
    configLabel_.setBounds(r.removeFromLeft(labelWidth));
    clearConfig_.setBounds(r.removeFromRight(70));
    chooseConfig_.setBounds(r.removeFromRight(170));
    configFile_.setBounds(r);
    r = row();
    test_.setBounds(r.removeFromLeft(190));
    status_.setBounds(area);
}

} // namespace armadillo::plugin
