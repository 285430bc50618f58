#pragma once
// The first-run welcome of the app (issue 24): what is playing now (the simulated arm or the
// device), how to hear it (the output device, a test tone), how to connect a real arm or a phone
// (shortcuts to the device panel and the OSC input), and where the audio input stands (JUCE's
// standalone app mutes it; the listening scenes need it: Unmute). Shown by itself at the app's
// first start until "Show at start" is cleared (remembered in ~/.config/armadillo/app.settings),
// and again with Help (F1). While shown it keeps Tab inside itself; Escape closes it.
// Message thread only.
#include <juce_gui_basics/juce_gui_basics.h>
#include <functional>

namespace armadillo::plugin {

class ArmadilloProcessor;

class WelcomePanel : public juce::Component, private juce::Timer {
public:
    explicit WelcomePanel(ArmadilloProcessor& processor);
    ~WelcomePanel() override;

    /// Shows (refreshing the text) and puts the keyboard focus on the first button.
    void open();
    void close();
    std::function<void()> onClose, onShowDevice, onShowOsc;

    /// Whether the app shows the welcome at start (the saved choice; true the first time).
    static bool showAtStart();
    static void setShowAtStart(bool show);

    /// The texts as shown (tests, screenshots).
    juce::String text() const;

    void paint(juce::Graphics&) override;
    void resized() override;
    bool keyPressed(const juce::KeyPress&) override;

private:
    void timerCallback() override;
    void refresh();

    ArmadilloProcessor& processor_;
    juce::Label heading_, playing_, hearing_, connecting_, input_, keys_;
    juce::TextButton testTone_ {"Test tone"}, audioSettings_ {"Audio settings..."}, device_ {"Device panel"},
        osc_ {"Phone / OSC input"}, unmute_ {"Unmute input"}, close_ {"Close"};
    juce::ToggleButton atStart_ {"Show this at start"};
};

} // namespace armadillo::plugin
