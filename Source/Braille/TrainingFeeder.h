#pragma once
// The reader's side of live braille training (thesis §4.4.1): typed answers are handed to the
// scene one at a time, each only once the previous one is scored, so every "right" / "wrong"
// belongs to the trial it was typed for. Shared by `armadillo play --training-log` (prompts on
// stderr) and the app's Training panel (labels and screen-reader announcements); JUCE-free.
// Not thread-safe: one thread (the CLI's main loop, the app's message thread) owns a feeder and
// is the only producer of the scene's answer queue.
#include "Braille/BrailleScene.h"
#include <cstddef>
#include <deque>
#include <string>
#include <vector>

namespace armadillo::braille {

/// One thing to tell the reader, in the order it should be heard.
struct TrainingNotice {
    enum class Kind { Prompt, Result, Complete };
    Kind kind = Kind::Prompt;
    int trial = 0;           ///< 0-based trial it is about (Complete: the trial count)
    int trialCount = 0;
    int correct = 0;         ///< answers right so far, this one included
    int answered = 0;        ///< answers scored so far, this one included
    std::string prompt;      ///< Prompt: what the teacher says ("left, right or both?")
    std::string answer;      ///< Result: what was handed to the scene (trimmed)
    std::string expected;    ///< Result and Prompt: the right answer
    std::string stage;       ///< Result and Prompt: the trial's stage ("sides", "letters", …)
    bool right = false;      ///< Result
    bool byArm = false;      ///< Result: "here" answered by the arm (a push), not typed
};

/// "correct" or "wrong, it was 'x'" (the wording of the command line and the app; never "right",
/// which is also an answer of the sides stage); an answer by the arm adds " (here, by the arm)".
std::string resultText(const TrainingNotice& result);

class TrainingAnswerFeeder {
public:
    /// The scene carries an answer in a 64-byte slot: longer ones are refused, never cut (a cut
    /// could split a UTF-8 character and would log something the reader did not type).
    static constexpr std::size_t kMaxAnswerBytes = 63;

    enum class Refusal { None, Empty, TooLong, NotUtf8, ControlCharacter, Finished };
    /// Why an answer was refused, in words for the reader ("" for None).
    static std::string refusalText(Refusal r);

    /// Puts an answer in the waiting line (surrounding whitespace removed). Refused answers are
    /// not queued. Refuses everything once the training is complete.
    Refusal add(const std::string& answer);

    /// Follows the scene (its lock-free progress): reports the scored answer, then completion or
    /// the new trial's prompt, then hands over the next waiting answer if none is being scored.
    /// Call it regularly (the CLI every 10 ms, the app from its UI timer).
    std::vector<TrainingNotice> poll(BrailleSceneControls& scene);

    bool finished() const noexcept { return finished_; }
    bool awaitingScore() const noexcept { return awaiting_; }
    std::size_t waiting() const noexcept { return lines_.size(); }
    /// Forgets everything (the scene was rebuilt: its training starts again).
    void reset();

private:
    std::deque<std::string> lines_;
    std::string submitted_;
    bool awaiting_ = false, finished_ = false;
    int announced_ = -1, submittedAt_ = -1, rightBefore_ = 0, armSeen_ = 0;
};

} // namespace armadillo::braille
