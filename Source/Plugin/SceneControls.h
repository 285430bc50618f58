#pragma once
// The current scene's own parameters (Scene::parameters()), built from the scene's specs and
// attached to the host parameters, plus the scene's text settings (braille text, score).
#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_gui_basics/juce_gui_basics.h>
#include <memory>
#include <vector>

namespace armadillo::plugin {

class ArmadilloProcessor;

class SceneControls : public juce::Component, private juce::Timer {
public:
    explicit SceneControls(ArmadilloProcessor& processor);
    ~SceneControls() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    int shownScene() const noexcept { return shownScene_; }
    int controlCount() const noexcept { return static_cast<int>(controls_.size()); }

private:
    void timerCallback() override;
    void rebuild();
    /// "Import a file…" in the score choice: a MIDI, WAV, AHAP or .haptic file, checked by importing
    /// it here (an error says what is wrong), then set as the score (the engine imports it as it loads).
    void chooseScoreFile(juce::ComboBox& box);

    struct Control {
        std::unique_ptr<juce::Label> label;
        std::unique_ptr<juce::Component> editor;
        std::unique_ptr<juce::AudioProcessorValueTreeState::SliderAttachment> slider;
        std::unique_ptr<juce::AudioProcessorValueTreeState::ComboBoxAttachment> combo;
    };
    ArmadilloProcessor& processor_;
    juce::Label heading_, note_;
    juce::Viewport viewport_;
    juce::Component content_;
    std::vector<Control> controls_;
    std::unique_ptr<juce::FileChooser> chooser_;
    int shownScene_ = -1;
};

} // namespace armadillo::plugin
