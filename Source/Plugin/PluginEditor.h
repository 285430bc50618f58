#pragma once
// The live performance UI: arm view, motor display, source, scene and preset selection,
// device/OSC panel and the scene's controls, a status line that tells what really happens
// (StatusLine.h) and the first-run welcome (WelcomePanel.h). Resizable from 720x520 up; all
// drawing scales, so 100% and 200% both stay sharp. Keyboard: Tab order follows the layout, the
// focused control has a visible outline, F1 opens the welcome/help.
#include "Plugin/ArmView.h"
#include "Plugin/Controls.h"
#include "Plugin/DevicePanel.h"
#include "Plugin/MotorDisplay.h"
#include "Plugin/PerformanceView.h"
#include "Plugin/SceneControls.h"
#include "Live/Session/StatusLine.h"
#include "Plugin/TrainingPanel.h"
#include "Plugin/WelcomePanel.h"
#include <juce_audio_processors/juce_audio_processors.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class ArmadilloEditor : public juce::AudioProcessorEditor, private juce::Timer, private juce::FocusChangeListener {
public:
    explicit ArmadilloEditor(ArmadilloProcessor& processor);
    ~ArmadilloEditor() override;
    void paint(juce::Graphics&) override;
    void paintOverChildren(juce::Graphics&) override;
    void resized() override;
    bool keyPressed(const juce::KeyPress&) override;
    void mouseDown(const juce::MouseEvent&) override;

    /// Tests and screenshots: the parts by role.
    WelcomePanel& welcome() noexcept { return welcome_; }
    TrainingPanel& training() noexcept { return training_; }
    juce::Label& statusLine() noexcept { return statusLine_; }
    PerformanceView& performance() noexcept { return performance_; }
    /// Opens the welcome (Help button, F1).
    void showHelp();
    /// Opens the performance view (Stage menu, F11).
    void showPerformance();

private:
    void timerCallback() override;
    void globalFocusChanged(juce::Component* focused) override;
    void updateStatusLine();
    void showSetupMenu();
    void showStageMenu();
    void chooseSetList();
    void scrollIntoView(juce::Component& focused);
    juce::Rectangle<int> focusRingArea() const;

    ArmadilloProcessor& processor_;
    juce::Label title_, status_, statusLine_;
    ChoiceBox source_, scene_, preset_;
    juce::Label sourceLabel_, sceneLabel_, presetLabel_;
    juce::ToggleButton wander_ {"Wander"};
    juce::TextButton dismiss_ {"OK"};
    juce::TextButton about_ {"About"};
    juce::TextButton help_ {"Help"};
    juce::TextButton setup_ {"Setup..."};
    juce::TextButton stage_ {"Stage..."};                        // set list, performance view, panic (issue 28)
    juce::TextButton mappingButton_ {"Mapping..."};              // MappingPanel in its own window
    juce::Component::SafePointer<juce::DialogWindow> mappingWindow_;
    juce::TextButton readerButton_ {"Reader..."};                // ReaderPanel in its own window (issue 26)
    juce::Component::SafePointer<juce::DialogWindow> readerWindow_;
    /// Opens a panel in a window of its own, or brings the open one to the front.
    void openWindow(juce::Component::SafePointer<juce::DialogWindow>& window, const std::function<std::unique_ptr<juce::Component>()>& make,
                    juce::Point<int> size, const juce::String& title);
    juce::Component::SafePointer<juce::DialogWindow> tactorsWindow_;   // TactorsPanel (issue 33)
    void showTactors();
    juce::Component::SafePointer<juce::DialogWindow> navigationWindow_;   // NavigationPanel (issue 34)
    void showNavigation();
    juce::Component::SafePointer<juce::DialogWindow> mqttWindow_;   // MqttPanel (issue 35)
    juce::Component::SafePointer<juce::DialogWindow> webWindow_;    // WebPanel (issue 47)
    void showMqtt();
    void showWebPage();
    std::unique_ptr<juce::FileChooser> chooser_;
    std::unique_ptr<juce::AudioProcessorValueTreeState::ComboBoxAttachment> sourceAttachment_, sceneAttachment_;
    ArmView armView_;
    MotorDisplay motors_;
    DevicePanel device_;
    juce::Viewport deviceView_;   // scrolls the device panel when the window is too low for it
    SceneControls sceneControls_;
    TrainingPanel training_;   // below the arm view while the braille scene trains
    WelcomePanel welcome_;
    PerformanceView performance_;
    live::StatusLine statusTracker_;
    juce::Rectangle<int> lastRing_;
};

} // namespace armadillo::plugin
