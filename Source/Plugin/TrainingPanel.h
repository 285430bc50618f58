#pragma once
// Live braille training in the app (thesis §4.4.1; the braille scene with braille.mode =
// training): the current trial "n of N" and its prompt, an answer field with an Answer button
// (Return submits), "correct" / "wrong, it was 'x'" after each answer with the running score and
// the results per expected answer (letter, side), and at the end "Training complete: k of N
// correct" with Save log... (atomic write). An answer that cannot be one for the trial (a typo:
// "lefy" where left, right or both is asked, two letters where one is) is not sent: it stays in
// the field to be corrected, then Return. The answers go to
// the scene through braille::TrainingAnswerFeeder, one at a time, each once the previous one is
// scored — exactly as `armadillo play --training-log` does.
//
// Accessibility is the point: every control has a title, a description and keyboard focus; each
// new prompt and each result is announced to screen readers, and focus stays in the answer field
// between trials. While a training runs the panel owns the keyboard (Tab cycles inside it; keys
// listed on the panel: Return send, F5 repeat the prompt, F6 skip, F8 stop; Escape leaves it). Threads: message thread only (its own timer polls the scene's lock-free
// progress); it never keeps a pointer to the scene, which the processor may replace at any time.
#include "Access/ProfileRecorder.h"
#include "Braille/TrainingFeeder.h"
#include "Plugin/PerkinsKeys.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace armadillo::plugin {

class ArmadilloProcessor;

class TrainingPanel : public juce::Component, private juce::Timer {
public:
    explicit TrainingPanel(ArmadilloProcessor& processor);
    ~TrainingPanel() override;
    /// The scene is braille and its mode is training: the owner shows the panel.
    bool wanted() const noexcept { return wanted_; }
    /// Called when wanted() changes (the owner lays itself out again).
    std::function<void()> onWantedChange;
    /// Called when the reader leaves the panel with Escape or stops the training (the owner
    /// puts the focus somewhere sensible outside).
    std::function<void()> onLeave;
    void resized() override;
    void paint(juce::Graphics&) override;
    bool keyPressed(const juce::KeyPress&) override;
    /// Tab from outside lands on the panel itself: it hands the focus to the answer field.
    void focusGained(FocusChangeType) override;

    // The panel's actions, as its keys and buttons run them (tests call them too).
    void submit();
    void repeatPrompt();
    void skip();
    void stop();
    void leave();
    /// Texts as shown (tests, screenshots).
    juce::String resultText() const { return result_.getText(); }
    juce::String scoreText() const { return score_.getText(); }
    juce::String tallyText() const { return tally_.getText(); }
    juce::String promptText() const { return prompt_.getText(); }
    juce::String trialText() const { return trial_.getText(); }
    /// Answers added to the reader profile by this training (0 without one).
    int recordedAnswers() const noexcept { return recorder_ ? recorder_->recorded() : 0; }
    juce::TextEditor& answerField() noexcept { return answer_; }

    /// Why `answer` cannot be an answer to a trial whose right answer is `expected` ("" when it
    /// can): sides take left/right/both, hold takes here, a letter trial one letter.
    static juce::String implausible(const juce::String& answer, const juce::String& expected);
    /// What Skip sends (scored wrong, logged as typed).
    static constexpr const char* kSkipAnswer = "(skipped)";

private:
    void timerCallback() override;
    void follow();
    void send(const juce::String& answer);
    void save();
    void show(const std::vector<braille::TrainingNotice>& notices);
    void announce(const juce::String& text);
    void record(const braille::TrainingNotice& result);

    ArmadilloProcessor& processor_;
    std::atomic<float>* mode_ = nullptr;   // braille.mode (nullptr if this build has no braille scene)
    braille::TrainingAnswerFeeder feeder_;
    std::uint64_t generation_ = 0;         // the engine whose training the feeder follows
    bool wanted_ = false, complete_ = false;
    juce::Label heading_, trial_, prompt_, score_, result_, tally_, keys_;
    juce::TextEditor answer_;
    juce::TextButton answerButton_ {"Answer"}, save_ {"Save log..."}, repeat_ {"Repeat (F5)"}, skip_ {"Skip (F6)"},
        stop_ {"Stop (F8)"};
    std::vector<std::pair<std::string, std::pair<int, int>>> tallyCounts_;   // expected → (correct, asked), in first-seen order
    juce::String lastPrompt_;
    std::vector<braille::TrainingNotice> heldBack_;   // prompts waiting for the arm feedback to end
    std::unique_ptr<access::ProfileRecorder> recorder_;   // this training's session in the reader profile
    juce::String recorderPath_, recorderError_;
    double promptedAtMs_ = 0.0, recorderStartMs_ = 0.0;
    std::string log_;                      // the complete training's log, copied once at the end
    std::unique_ptr<juce::FileChooser> chooser_;
    TrainingKeys chordKeys_;                   // Perkins chords (F2), repeat (F3), stop speech (F4), display keys
};

} // namespace armadillo::plugin
