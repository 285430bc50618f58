#pragma once
// Adaptive braille training in the app (issue 26): the core's plan (Access/AdaptivePlan.h) over
// the reader's profile (Access/ReaderProfile.h, the file `armadillo braille --adaptive --reader`
// keeps), driven by the Reader window, with the CLI's choices (AdaptiveChoices: --trials,
// --stages, --method, --level). Each trial: the "next" cue, the cells drawn on the arm (the CLI's
// passive drawing, docs/BRAILLE.md: 0.4 s on, 0.2 s between rows, 0.5 s between letters), then
// the "your turn" cue, through an access::TactilePlayer that the control step plays in place of
// the scene (BlockControl::setStimulus); the prompt said and shown; the answer (typed, chorded,
// from the display's keys, or the arm: a twist and back shows the trial again, two skip it) is
// recorded, scored, felt (Access/Feedback.h) and, when wrong, the right cell drawn again (the
// confused letter next to it); every sensation is queued after the one before, so the next
// trial's cue never overlaps the feedback. The profile and the session log (the CLI's --log
// columns, Access/SessionLog.h, written next to the profile) are saved after every answer, so
// nothing is lost when the app stops. JUCE-free; message thread only.
#include "Access/AdaptivePlan.h"
#include "Access/TactilePlayer.h"
#include <memory>
#include <string>

namespace armadillo::plugin {

/// The CLI's `--trials --stages --method --level`, kept in the app's settings.
struct AdaptiveChoices {
    int trials = 20;                        ///< 1..10000
    std::string stages = "letters,words";   ///< comma list of letters, words, signs, contractions
    std::string method = "rows";            ///< rows, whole, columns, dots
    int level = 8;                          ///< 1..15
    /// "" when every choice is usable, else why not (naming the choice).
    std::string problem() const;
};

class AdaptiveSession {
public:
    explicit AdaptiveSession(access::TactilePlayer& player) : player_(player) {}

    enum class State { Idle, Drawing, Answering, Done };
    State state() const noexcept { return state_; }
    /// Loads (or starts) the reader profile at `path` and draws the first trial. False and why.
    bool begin(const std::string& path, const AdaptiveChoices& choices, std::string& why);
    /// Timer: true when the drawing of a trial has just ended (say prompt() now).
    bool poll();
    /// "Trial 3 of 20: which letter?" while answering.
    std::string prompt() const;
    /// The answer to the current trial (letters; spaces do not count). Returns the feedback
    /// ("right", "wrong: it was 'e', you said 'i'"); the next trial is drawn after it, or the
    /// session ends ("Training complete: 14 of 20 right"). "" when not answering.
    std::string answer(const std::string& given, double responseSeconds);
    /// Skips the current trial (scored wrong, logged "(skipped)"); the feedback as answer().
    std::string skip(double responseSeconds);
    /// Shows the current trial again (while answering).
    void again();

    enum class Gesture { None, Repeat, Skip };
    /// Timer: the arm's twists (TactilePlayer::repeats / skips) since the last call. While
    /// answering the newest is returned (and logged as a `gesture` row); the caller runs again()
    /// or skip(). Twists during a drawing are dropped (the reader feels the drawing go on).
    Gesture takeGesture();

    /// Ends the session early; the profile and log keep what was answered.
    void stop();
    int right() const noexcept { return right_; }
    int trial() const noexcept { return number_; }
    int trials() const noexcept { return choices_.trials; }
    const std::string& lastError() const noexcept { return saveError_; }
    /// The session log's file (next to the profile: "<profile>-session<N>.csv"), and its text.
    const std::string& logPath() const noexcept { return logPath_; }
    const std::string& logText() const noexcept { return log_; }

private:
    void drawTrial();
    /// Queues `segments` after what is queued; logs nothing. Returns the sequence's number.
    int queue(std::vector<access::TactileSegment> segments, double after);
    int draw(const std::string& text, double after);
    std::string finishAnswer(const std::string& given, bool correct, bool skipped, double responseSeconds);
    void save();
    double now() const;   ///< s of session time (the player's clock)

    access::TactilePlayer& player_;
    std::unique_ptr<access::AdaptivePlanner> plan_;
    access::ReaderProfile reader_;
    access::AdaptiveOptions options_;
    AdaptiveChoices choices_;
    access::PlannedTrial trial_;
    std::string path_, logPath_, log_, saveError_;
    State state_ = State::Idle;
    int number_ = 0, right_ = 0, waitingFor_ = 0, repeatsSeen_ = 0, skipsSeen_ = 0;
    double startClock_ = 0.0, queuedUntil_ = 0.0;
    float level_ = 8.0f;
};

} // namespace armadillo::plugin
