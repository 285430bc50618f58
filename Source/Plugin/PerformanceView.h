#pragma once
// The performance view (docs/STAGE.md, issue 28): what a performer reads from across a stage, in
// large type — the cue playing and the next one (number and name), each arm's source (which one,
// live or silent: the status line's own counters), the nine motors' levels, and PANIC — with a
// big PANIC button. Opened from the editor's Stage menu; it covers the editor but its status line.
//
// Keys while it shows (those of `armadillo play --keys`, live/StageControl.h): n or Space next
// cue, b previous cue, p or Escape panic, r resume, 1–9 a cue, c closes the view. The Training
// panel is never open at the same time (the view closes it), so its chord keys cannot clash.
// Message thread only.
#include "Core/Types.h"
#include "Live/Session/StatusLine.h"
#include <juce_audio_processors/juce_audio_processors.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class PerformanceView : public juce::Component, private juce::Timer {
public:
    explicit PerformanceView(ArmadilloProcessor& processor);
    ~PerformanceView() override;

    /// Shows the view and gives it the keyboard.
    void open();
    void close();
    std::function<void()> onClose;

    void paint(juce::Graphics&) override;
    void resized() override;
    bool keyPressed(const juce::KeyPress&) override;

    /// Tests: the text lines the view shows now (cue, next, arms, panic), refreshed by the timer.
    juce::String cueLine() const { return cueLine_; }
    juce::String nextLine() const { return nextLine_; }
    juce::String armLine() const { return armLine_; }
    juce::String stateLine() const { return stateLine_; }
    juce::TextButton& panicButton() noexcept { return panic_; }
    /// Refreshes the lines now (the timer does it ten times a second).
    void refresh();

private:
    void timerCallback() override { refresh(); }
    juce::Rectangle<int> motorArea() const;

    /// The buttons' text in proportion to their height (the stock look caps it at 16 px): PANIC
    /// and the steps must be readable from across a stage.
    struct LargeText : juce::LookAndFeel_V4 {
        juce::Font getTextButtonFont(juce::TextButton&, int buttonHeight) override
        {
            return juce::Font(juce::jlimit(14.0f, 96.0f, static_cast<float>(buttonHeight) * 0.45f), juce::Font::bold);
        }
    };
    LargeText largeText_;   // before the buttons: they use it until they are gone
    ArmadilloProcessor& processor_;
    juce::TextButton panic_ {"PANIC"}, resume_ {"Resume"}, previous_ {"< Previous"}, next_ {"Next >"}, close_ {"Close"};
    juce::Label cue_, nextCue_, arms_, state_;
    juce::String cueLine_, nextLine_, armLine_, stateLine_;
    live::StatusLine sourceTracker_;     // the status line's counters: live or silent
    core::MotorLevels levels_ {};
    int motorCount_ = 9;
};

} // namespace armadillo::plugin
