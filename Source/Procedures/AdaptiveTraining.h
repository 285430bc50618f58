#pragma once
// Adaptive braille training for a reader alone (issue 26), written once for
// `armadillo braille --train --adaptive` (Cli/GuidedTraining.cpp presents it on stdin/stderr, speech
// and a braille display) and the app's Reader window (Plugin/ReaderPanel.cpp):
//   1. the planner (Access/AdaptivePlan.h) picks the trial from the reader's whole history
//      (Access/ReaderProfile.h);
//   2. the "next" cue (the underside line swept wrist → elbow), the cells drawn on the arm (passive
//      drawing, docs/BRAILLE.md: 0.4 s on, 0.2 s between rows, 0.5 s between letters, a word gap
//      1.2 s) in the chosen method, then the "your turn" cue (the underside line tapped twice),
//      through an access::TactilePlayer (the CLI's device link or the app's control step plays it);
//   3. the presenter asks the trial's question once the drawing has ended (poll()) and gives the
//      answer (typed, chorded, from a braille display's keys) or asks for the trial again / skips
//      it (typed, or the arm: a twist and back = again, two = skip);
//   4. the answer is scored, recorded in the planner and felt (Access/Feedback.h): "right" all nine
//      motors hum, "wrong" the outer columns buzz three times, then the right cell again (the
//      confused letter next to it), then 2 s of stillness before the next trial's cue. Every
//      sensation is queued after the one before, so nothing overlaps.
//   5. the reader profile and the session log (the §4.4.1 log's columns, Access/SessionLog.h) are
//      written after every answer (atomic), so nothing is lost when a session stops: stop() — the
//      answers ended, Ctrl-C, the app closed the window — keeps every answer given in both files,
//      and the log's `end` row says `stopped` in its answer column (docs/CHANGES.md, issue 32).
// Threads: one front-end thread (the app's message thread, the CLI's main thread); only the
// player's onPacket runs on the control side.
#include "Access/AdaptivePlan.h"
#include "Access/ReaderProfile.h"
#include "Access/TactilePlayer.h"
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::procedures {

/// The app's settings for the training (the CLI's `--trials --stages --method --level`).
struct AdaptiveChoices {
    int trials = 20;                        ///< 1..10000
    std::string stages = "letters,words";   ///< comma list of letters, words, signs, contractions
    std::string method = "rows";            ///< rows, whole, columns, dots
    int level = 8;                          ///< 1..15
    /// "" when every choice is usable, else why not (naming the choice).
    std::string problem() const;
};

class AdaptiveTraining {
public:
    struct Options {
        std::string profilePath;                 ///< the reader profile (created if it does not exist)
        std::string logPath;                     ///< the session log ("" = none)
        int trials = 20;                         ///< 1..10000
        std::vector<std::string> stages {"letters", "words"};
        std::string method = "rows";             ///< rows, whole, columns, dots
        float level = 8.0f;                      ///< level of the cells (1..15)
        std::int64_t seed = -1;                  ///< the plan's seed; < 0: the session's number
        std::vector<std::string> signWords;      ///< the words/signs stages' words ("" = the built-in list)
        double stillnessSeconds = 2.0;           ///< s of stillness after a trial's feedback
    };

    explicit AdaptiveTraining(access::TactilePlayer& player) : player_(player) {}

    enum class State { Idle, Drawing, Answering, Done };
    State state() const noexcept { return state_; }

    /// Loads (or starts) the reader profile and draws the first trial. Throws UsageError for a bad
    /// option, InputError for a bad profile, IoError when the profile or log cannot be written
    /// (both are written now, before the reader answers anything).
    void start(const Options& options);
    /// The app's start: the choices checked, the log next to the profile
    /// ("<profile>-session<N>.csv"). False and why instead of throwing.
    bool begin(const std::string& profilePath, const AdaptiveChoices& choices, std::string& why);

    /// True when the drawing of a trial has just ended: ask the question now.
    bool poll();
    /// The player's sequence that ends the drawing (a blocking presenter waits for it).
    int waitingFor() const noexcept { return waitingFor_; }
    /// Everything queued has been played (feedback and stillness included).
    bool settled() const noexcept { return player_.completed() >= lastQueued_; }

    /// The trial's question ("which letter?", …) while answering, "" otherwise.
    std::string question() const;
    /// "Trial 3 of 20: which letter?" while answering.
    std::string prompt() const;
    /// The answer to the current trial (letters; spaces do not count). Returns the verdict, the
    /// running score and, after the last trial, "Training complete: 14 of 20 right" (and "Not
    /// saved: …" when a file could not be written); lastVerdict() has the verdict alone. The next
    /// trial is drawn after it. "" when not answering.
    std::string answer(const std::string& given, double responseSeconds);
    /// Skips the current trial (scored wrong, recorded "(skipped)"); returns as answer().
    std::string skip(double responseSeconds);
    /// Shows the current trial again, its "next" cue first (while answering).
    void again();

    struct Verdict {
        bool correct = false, skipped = false;
        std::string given, expected;
        std::string text;   ///< "right", "wrong: it was 'e', you said 'i'", "skipped: it was 'e'"
    };
    const Verdict& lastVerdict() const noexcept { return verdict_; }

    enum class Gesture { None, Repeat, Skip };
    /// The arm's twists seen by the player (TactilePlayer::repeats / skips) since the last call.
    /// While answering the newest is returned and logged (noteGesture); the caller runs again()
    /// or skip(). Twists during a drawing are dropped (the reader feels the drawing go on).
    Gesture takeGesture();
    /// Logs a `gesture` row for an "again" or "skip" that came from the arm (a presenter that
    /// detects twists itself); only while answering.
    void noteGesture(Gesture g);

    /// Ends the session early: an `end` row saying `stopped`, the profile and log saved with every
    /// answer given. Idle afterwards. Nothing when idle.
    void stop();

    int right() const noexcept { return right_; }
    int trial() const noexcept { return number_; }        ///< the current trial's number (1-based)
    int trials() const noexcept { return options_.trials; }
    int answered() const noexcept { return answered_; }   ///< trials answered or skipped
    int session() const noexcept { return access_.session; }
    std::size_t answersInProfile() const;
    std::size_t historyAnswers() const noexcept { return history_; }
    /// Why the last save failed ("" = saved).
    const std::string& lastError() const noexcept { return saveError_; }
    const std::string& logPath() const noexcept { return options_.logPath; }
    const std::string& logText() const noexcept { return log_; }
    /// The CLI's summary line: {"session":…,"trials":…,"trials_done":…,"stopped":…,"correct":…,
    /// "answers_in_profile":…,"history":…}.
    std::string summaryJson(bool stopped) const;

private:
    void drawTrial();
    void showTrial();
    int queue(std::vector<access::TactileSegment> segments, double after);
    int draw(const std::string& text, double after);
    std::string finishAnswer(const std::string& given, bool correct, bool skipped, double responseSeconds);
    void save();
    double now() const;   ///< s of session time (the player's clock)

    access::TactilePlayer& player_;
    std::unique_ptr<access::AdaptivePlanner> plan_;
    access::ReaderProfile reader_;
    access::AdaptiveOptions access_;
    Options options_;
    access::PlannedTrial trial_;
    Verdict verdict_;
    std::string log_, saveError_;
    State state_ = State::Idle;
    std::size_t history_ = 0;
    int number_ = 0, right_ = 0, answered_ = 0, waitingFor_ = 0, lastQueued_ = 0, repeatsSeen_ = 0, skipsSeen_ = 0;
    double startClock_ = 0.0, queuedUntil_ = 0.0;
};

} // namespace armadillo::procedures
