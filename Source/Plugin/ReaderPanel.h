#pragma once
// The reader's settings (issue 26), in their own window (the editor's "Reader..." button):
// self-voicing and the braille display (auto / on / off, speech rate, repeat, stop), the reader's
// touch profile (load a profile made by `armadillo touch-profile`, or clear it: saved in the
// plugin state and applied to every scene through EngineConfig::motorGain, under the SafetyStage)
// and the progress report of a reader profile (Access/Report.h: accuracy per stage and session,
// letters per minute, the confusion matrix, the published figures), readable line by line with
// the arrow keys and spoken. Every control has a title, a description and keyboard focus; every
// change is announced (and so spoken and shown on the display). Message thread only.
#include "Plugin/PerkinsKeys.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <memory>

namespace armadillo::plugin {

class ArmadilloProcessor;

class ReaderPanel : public juce::Component, private juce::Timer {
public:
    explicit ReaderPanel(ArmadilloProcessor& processor);
    ~ReaderPanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    /// Loads a touch profile file into the settings. "" or why not (also announced).
    juce::String loadTouchProfile(const juce::File& file);
    /// Shows (and announces) the progress report of a reader profile file.
    juce::String showReport(const juce::File& file);
    juce::String reportText() const { return report_.getText(); }
    /// The message list (issue 35): the messages received over MQTT, newest last (tests).
    juce::String messagesText() const { return messages_.getText(); }
    juce::String touchSummary() const { return touch_.getText(); }
    /// Y = felt, N = not felt, R = again while the sensitivity test asks; F3 repeats, F4 stops speech.
    bool keyPressed(const juce::KeyPress& key) override;
    /// The adaptive training's choices as shown (tests).
    juce::Slider& trialsControl() noexcept { return adaptiveTrials_; }
    juce::Slider& levelControl() noexcept { return adaptiveLevel_; }
    juce::TextEditor& stagesControl() noexcept { return adaptiveStages_; }
    juce::ComboBox& methodControl() noexcept { return adaptiveMethod_; }
    juce::String adaptiveStateText() const { return adaptiveState_.getText(); }
    juce::TextEditor& adaptiveAnswerField() noexcept { return adaptiveAnswer_; }
    juce::String testStateText() const { return testState_.getText(); }
    /// The panel's actions as its buttons and keys run them (tests).
    void answerTestForTests(bool felt) { answerTest(felt); }
    void followForTests() { timerCallback(); }
    /// The adaptive stages as typed: kept in the settings when usable, else refused (announced).
    juce::String takeStages();

private:
    // The constructor's parts, in order: speech and the braille display, the touch profile and the
    // sensitivity test, the adaptive training and its choices, the progress report and messages.
    void setUpVoice();
    void setUpTouch();
    void setUpAdaptive();
    void setUpAdaptiveChoices();
    void setUpReport();
    void timerCallback() override;
    void refresh();
    void announce(const juce::String& text);
    void choose(bool profile);
    void startTest();
    void answerTest(bool felt);
    void followTest();
    void saveProfile();
    void startAdaptive();
    void answerAdaptive();
    void followAdaptive();
    void showReaderProfile();
    void followMessages();

    ArmadilloProcessor& processor_;
    juce::Label heading_, voiceLabel_, rateLabel_, voiceState_, touch_, reportHeading_;
    juce::ComboBox voice_;
    juce::Slider rate_;
    juce::ToggleButton armFeedback_ {"Training feedback on the arm (deafblind: no screen, no sound needed)"};
    juce::TextButton repeat_ {"Repeat (F3)"}, stop_ {"Stop speech (F4)"};
    juce::TextButton loadTouch_ {"Load touch profile..."}, clearTouch_ {"No touch profile"};
    juce::TextButton startTest_ {"Sensitivity test"}, felt_ {"Felt (Y)"}, notFelt_ {"Not felt (N)"}, again_ {"Again (R)"};
    juce::TextButton saveTouch_ {"Save touch profile..."};
    juce::Label testState_;
    juce::TextButton adaptiveStart_ {"Adaptive training..."}, adaptiveAgain_ {"Show again"};
    juce::TextEditor adaptiveAnswer_;
    juce::Label adaptiveState_;
    // The adaptive training's choices (the settings adaptiveTrials … : the CLI's --trials --stages --method --level).
    juce::Label trialsLabel_, stagesLabel_, methodLabel_, levelLabel_, readerProfile_;
    juce::Slider adaptiveTrials_, adaptiveLevel_;
    juce::TextEditor adaptiveStages_;
    juce::ComboBox adaptiveMethod_;
    juce::TextButton forgetReader_ {"No reader profile"};
    juce::String shownReader_ {"?"};
    bool comfortAnnounced_ = false;
    TrainingKeys adaptiveKeys_;            // chords (F2), F3, F4 in the adaptive answer field
    juce::File readerFile_;
    double promptedAt_ = 0.0;              // ms, when the prompt was said (the response time)
    // Messages on the arm (issue 35): the recent ones, read line by line like the report.
    juce::Label messagesHeading_;
    juce::TextEditor messages_;
    std::uint64_t lastMessageId_ = 0;
    juce::TextButton loadReport_ {"Progress report..."};
    juce::TextEditor report_;
    std::unique_ptr<juce::FileChooser> chooser_;
    juce::String shownTouch_ {"?"}, shownVoice_;
};

} // namespace armadillo::plugin
