#pragma once
// Adaptive braille training in the app (issue 26): the core's plan (Access/AdaptivePlan.h) over
// the reader's profile (Access/ReaderProfile.h, the file `armadillo braille --adaptive --reader`
// keeps), driven by the Reader window. Each trial: the cells drawn on the arm row by row (the
// CLI's passive drawing, docs/BRAILLE.md: 0.4 s on, 0.2 s between rows, 0.5 s between letters)
// through an access::TactilePlayer that the control step plays in place of the scene
// (BlockControl::setStimulus), the prompt said and shown; the answer (typed, chorded or from the
// display's keys) is recorded, scored, felt (Access/Feedback.h) and, when wrong, the right cell
// drawn again; the profile is saved after every answer (nothing lost when the app stops).
// JUCE-free; message thread only.
#include "Access/AdaptivePlan.h"
#include "Access/TactilePlayer.h"
#include <memory>
#include <string>

namespace armadillo::plugin {

class AdaptiveSession {
public:
    explicit AdaptiveSession(access::TactilePlayer& player) : player_(player) {}

    enum class State { Idle, Drawing, Answering, Done };
    State state() const noexcept { return state_; }
    /// Loads (or starts) the reader profile at `path` and draws the first trial. False and why.
    bool begin(const std::string& path, int trials, std::string& why);
    /// Timer: true when the drawing of a trial has just ended (say prompt() now).
    bool poll();
    /// "Trial 3 of 20: which letter?" while answering.
    std::string prompt() const;
    /// The answer to the current trial (letters; spaces do not count). Returns the feedback
    /// ("right", "wrong: it was 'e', you said 'i'"); the next trial is drawn after it, or the
    /// session ends ("Training complete: 14 of 20 right"). "" when not answering.
    std::string answer(const std::string& given, double responseSeconds);
    /// Shows the current trial again (while answering).
    void again();
    /// Ends the session early; the profile keeps what was answered.
    void stop();
    int right() const noexcept { return right_; }
    int trial() const noexcept { return number_; }
    const std::string& lastError() const noexcept { return saveError_; }

private:
    void drawTrial(bool withCue);
    int draw(const std::string& text, double after);
    void save();

    access::TactilePlayer& player_;
    std::unique_ptr<access::AdaptivePlanner> plan_;
    access::ReaderProfile reader_;
    access::AdaptiveOptions options_;
    access::PlannedTrial trial_;
    std::string path_, saveError_;
    State state_ = State::Idle;
    int trials_ = 0, number_ = 0, right_ = 0, waitingFor_ = 0;
    double startClock_ = 0.0;
    static constexpr float kLevel = 8.0f;
};

} // namespace armadillo::plugin
