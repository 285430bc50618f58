#pragma once
// The MQTT window (issue 35, docs/MQTT.md "In the app"): the broker, the topics whose messages the
// arm reads (and the urgent ones), an optional configuration file, how a message is shown (read by
// rolling the arm, or timed), Connect, a test message sent to the first topic (it comes back
// through the broker and is shown like any message), and the status. The messages themselves are
// listed in the Reader window. Every control titled, reached with Tab; what happens is announced.
#include "Plugin/Controls.h"
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class MqttPanel : public juce::Component, private juce::Timer {
public:
    explicit MqttPanel(ArmadilloProcessor& processor);
    ~MqttPanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    juce::Label& status() noexcept { return status_; }
    juce::ToggleButton& connectToggle() noexcept { return connect_; }
    juce::TextButton& testButton() noexcept { return test_; }

private:
    void timerCallback() override;
    void say(const juce::String& text);

    ArmadilloProcessor& processor_;
    juce::Label heading_, brokerLabel_, topicsLabel_, urgentLabel_, configLabel_, configFile_, displayLabel_, status_;
    juce::TextEditor broker_, topics_, urgent_;
    juce::TextButton chooseConfig_ {"Configuration file..."}, clearConfig_ {"None"}, test_ {"Send a test message"};
    juce::ToggleButton connect_ {"Connect"};
    ChoiceBox display_;
    std::unique_ptr<juce::FileChooser> chooser_;
    juce::String said_;
};

} // namespace armadillo::plugin
