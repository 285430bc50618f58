#pragma once
// The live performance UI: arm view, motor display, source and scene selection, device/OSC panel
// and the scene's controls. Resizable; all drawing scales, so 100% and 200% both stay sharp.
#include "Plugin/ArmView.h"
#include "Plugin/DevicePanel.h"
#include "Plugin/MotorDisplay.h"
#include "Plugin/SceneControls.h"
#include "Plugin/TrainingPanel.h"
#include <juce_audio_processors/juce_audio_processors.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class ArmadilloEditor : public juce::AudioProcessorEditor, private juce::Timer {
public:
    explicit ArmadilloEditor(ArmadilloProcessor& processor);
    ~ArmadilloEditor() override;
    void paint(juce::Graphics&) override;
    void resized() override;

private:
    void timerCallback() override;

    ArmadilloProcessor& processor_;
    juce::Label title_, status_;
    juce::ComboBox source_, scene_;
    juce::Label sourceLabel_, sceneLabel_;
    juce::ToggleButton wander_ {"Wander"};
    juce::TextButton dismiss_ {"OK"};
    juce::TextButton about_ {"About"};
    juce::TextButton setup_ {"Setup..."};
    juce::TextButton mappingButton_ {"Mapping..."};              // MappingPanel in its own window
    juce::Component::SafePointer<juce::DialogWindow> mappingWindow_;
    juce::TextButton readerButton_ {"Reader..."};                // ReaderPanel in its own window (issue 26)
    juce::Component::SafePointer<juce::DialogWindow> readerWindow_;
    std::unique_ptr<juce::FileChooser> chooser_;
    std::unique_ptr<juce::AudioProcessorValueTreeState::ComboBoxAttachment> sourceAttachment_, sceneAttachment_;
    ArmView armView_;
    MotorDisplay motors_;
    DevicePanel device_;
    SceneControls sceneControls_;
    TrainingPanel training_;   // below the arm view while the braille scene trains
};

} // namespace armadillo::plugin
