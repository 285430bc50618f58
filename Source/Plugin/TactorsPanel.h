#pragma once
// The Tactors window (issue 33, docs/TACTORS.md): the motor grid on a tactor rig. In the
// standalone app a tactor output on a sound card or JACK, separate from the sound output (device,
// JACK connections, on/off); in a host the Tactors output bus, which the DAW enables and routes.
// Both: the actuator model, the channel map, the gain file, and a test button per channel that
// buzzes its motor and says which it is. Every control has an accessible title and is reached
// with Tab; what happens is announced (and spoken by the app's own voice).
#include "Plugin/Controls.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <array>

namespace armadillo::plugin {

class ArmadilloProcessor;

class TactorsPanel : public juce::Component, private juce::Timer {
public:
    explicit TactorsPanel(ArmadilloProcessor& processor);
    ~TactorsPanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    /// Tests: the parts by role.
    juce::Label& status() noexcept { return status_; }
    juce::TextButton& testButton(int channel) noexcept { return test_[static_cast<std::size_t>(channel)]; }
    juce::ToggleButton& outputToggle() noexcept { return output_; }
    juce::TextEditor& deviceEditor() noexcept { return device_; }
    static constexpr int kChannels = 12;

private:
    void timerCallback() override;
    void chooseGains();
    void say(const juce::String& text);

    ArmadilloProcessor& processor_;
    const bool standalone_;
    juce::Label heading_, intro_, deviceLabel_, connectLabel_, modelLabel_, mapLabel_, gainsLabel_, gainsFile_, testLabel_, status_;
    juce::TextEditor device_, connect_, map_;
    juce::ToggleButton output_ {"Tactor output on"};
    juce::ToggleButton sound_ {"Voice coil carries the scene's sound"};
    ChoiceBox model_;
    juce::TextButton gains_ {"Gain file..."}, clearGains_ {"No gain file"};
    std::array<juce::TextButton, kChannels> test_;
    std::unique_ptr<juce::FileChooser> chooser_;
    juce::String shown_;
};

} // namespace armadillo::plugin
