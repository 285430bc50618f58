#pragma once
// Live braille training in the app (thesis §4.4.1; the braille scene with braille.mode =
// training): the current trial "n of N" and its prompt, an answer field with an Answer button
// (Return submits), "right" / "wrong: it was 'x'" after each answer with the running score, and
// at the end "Training complete: k of N right" with Save log... (atomic write). The answers go to
// the scene through braille::TrainingAnswerFeeder, one at a time, each once the previous one is
// scored — exactly as `armadillo play --training-log` does.
//
// Accessibility is the point: every control has a title, a description and keyboard focus; each
// new prompt and each result is announced to screen readers, and focus stays in the answer field
// between trials. Threads: message thread only (its own timer polls the scene's lock-free
// progress); it never keeps a pointer to the scene, which the processor may replace at any time.
#include "Braille/TrainingFeeder.h"
#include "Plugin/PerkinsKeys.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

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
    void resized() override;
    void paint(juce::Graphics&) override;

private:
    void timerCallback() override;
    void follow();
    void submit();
    void save();
    void show(const std::vector<braille::TrainingNotice>& notices);
    void announce(const juce::String& text);

    ArmadilloProcessor& processor_;
    std::atomic<float>* mode_ = nullptr;   // braille.mode (nullptr if this build has no braille scene)
    braille::TrainingAnswerFeeder feeder_;
    std::uint64_t generation_ = 0;         // the engine whose training the feeder follows
    bool wanted_ = false, complete_ = false;
    juce::Label heading_, trial_, prompt_, score_, result_;
    juce::TextEditor answer_;
    juce::TextButton answerButton_ {"Answer"}, save_ {"Save log..."};
    std::string log_;                      // the complete training's log, copied once at the end
    std::unique_ptr<juce::FileChooser> chooser_;
    TrainingKeys keys_;                    // Perkins chords (F2), repeat (F3), stop speech (F4), display keys
};

} // namespace armadillo::plugin
