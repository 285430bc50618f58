#pragma once
// The Arm Braille scene (thesis §4.2–4.4): SceneConfig::text is read by rolling the arm
// (active), drawn without movement (passive) or used in the training protocol (§4.4.1).
// SceneConfig::text is the text itself, or "@PATH" for a file (.brf = Braille ASCII).
// With SceneConfig::messagesOnly the scene has no text of its own: it shows only the messages
// handed to it (`armadillo read`, docs/MQTT.md) and keeps the arm still between them.
#include "Braille/Reading.h"
#include "Core/Scene.h"
#include <cstdint>
#include <memory>
#include <string>

namespace armadillo::braille {

std::unique_ptr<core::Scene> makeBrailleScene();   ///< "braille"

/// Indices into the braille scene's parameters() (ids "braille.<name>").
enum BrailleParam : int {
    kParamMode = 0,        ///< choice: active, passive, training
    kParamMethod,          ///< choice: rows, whole, columns, dots (DisplayMethod)
    kParamGrade,           ///< choice: 1, 2 (the default tables; prepare() translates both)
    kParamLevel,           ///< level of a dot's vibration, 1..15
    kParamPulse,           ///< s a step vibrates in active reading
    kParamStep,            ///< deg of roll per advance
    kParamDeadTime,        ///< s after an advance with no further advance
    kParamHoldRepeat,      ///< s between repeats of the step the reader holds on; 0 = never
    kParamPassiveOn,       ///< s a step vibrates in passive drawing
    kParamPassiveGap,      ///< s between steps of one character in passive drawing
    kParamPassiveLetterGap,///< s between characters in passive drawing
    kParamPassiveWordGap,  ///< s of a word gap in passive drawing
    kParamPassiveRepeat,   ///< s before a passive message starts again; 0 = once
    kParamCount
};

enum class BrailleMode : int { Active = 0, Passive = 1, Training = 2 };

/// A message for the arm (issue 35, docs/MQTT.md), laid out off the control thread by
/// prepareArmMessage() and handed to the scene with BrailleSceneControls::showMessage().
struct ArmMessage {
    std::uint64_t id = 0;
    bool timed = false;       ///< drawn with the passive timings, framed; false = read by roll
    bool urgent = false;      ///< interrupts the message being shown
    ReadingCursor cursor;     ///< the message's cells, word gaps, in the reader's grade and method
};

/// Translates and lays out a message (liblouis: not real-time). Throws InputError naming
/// `source` when the text cannot be shown (a character the table lacks, nothing to read).
std::unique_ptr<ArmMessage> prepareArmMessage(const std::string& text, const std::string& source, int grade, DisplayMethod method,
                                              bool timed, bool urgent, std::uint64_t id);

/// What the app's UI (or a test) can do with the braille scene beyond the Scene API:
/// `dynamic_cast<braille::BrailleSceneControls*>(scene)`.
class BrailleSceneControls {
public:
    virtual ~BrailleSceneControls() = default;
    /// A training answer ("left", a letter, a word, "here"); any thread, lock-free; false when
    /// too many answers are waiting.
    virtual bool submitAnswer(const std::string& answer) noexcept = 0;
    /// The training log so far (CSV). Any thread but the control thread, while control() runs
    /// or not: control() queues fixed-size records, this turns them into text.
    virtual std::string trainingLogCsv() const = 0;
    /// Moves queued log records into the text log (any thread but the control thread). Long live
    /// sessions call it regularly (the feeder's poll, the app's timer) so the queue never fills.
    virtual void collectTrainingLog() {}
    /// Training progress for a UI that asks and listens (any thread, lock-free): the trial now
    /// shown (trainingTrialCount() once all are answered), and how many answers were right.
    virtual int trainingTrial() const noexcept = 0;
    virtual int trainingCorrect() const noexcept = 0;
    /// The plan, fixed at prepare(): how many trials, and what the teacher says for trial i
    /// ("left, right or both?", "stop on row 2", …). Any thread while prepare() is not running.
    virtual int trainingTrialCount() const noexcept = 0;
    virtual std::string trainingPrompt(int trial) const = 0;
    virtual std::string trainingExpected(int trial) const = 0;   ///< the right answer, lower case
    /// The trial's stage name ("sides", "hold", "letters", …; Braille/Training.h); "" unknown.
    virtual std::string trainingStage(int) const { return {}; }
    /// Starts the current trial again from its first row (any thread, lock-free; taken at the
    /// next control update). The app's arm feedback asks for it once the feedback has played,
    /// so rows the reader rolled past while the motors gave feedback are shown again.
    virtual void restartTrainingTrial() noexcept {}
    /// "Here" answered by the arm (the hold stage's push, Braille/ArmPush.h): how many so far,
    /// and the last one's trial and score. Any thread, lock-free; the scene publishes these
    /// before the trial that follows (read trainingTrial() first, as for the score).
    virtual int trainingArmAnswers() const noexcept { return 0; }
    virtual int trainingLastArmTrial() const noexcept { return -1; }
    virtual bool trainingLastArmRight() const noexcept { return false; }

    /// Messages (issue 35). The scene shows one message at a time, in any mode: first the
    /// "message waiting" cue (kMessageWaitingCue), then the sweep (kSweepCue); a timed message
    /// is then drawn with the passive timings (braille.passive*) and ends with the double tap; a
    /// message read by roll replaces the text under the roll reader until the reader reaches its
    /// end (the double tap), then the scene's own text comes back where it was. An urgent message
    /// ends the one being shown and starts at once; others wait in the scene (at most 4), and
    /// while a training runs (mode training, not finished) they wait for its end.
    /// One producer thread, lock-free; the message stays the caller's and must live until its
    /// id comes back from takeFinishedMessage(). False (nothing taken) when 4 are waiting.
    virtual bool showMessage(ArmMessage*) noexcept { return false; }
    /// The id of a message the scene is done with: shown to its end, or `interrupted` (by an
    /// urgent one, or a reset of the scene); false when none.
    virtual bool takeFinishedMessage(std::uint64_t& /*id*/, bool& /*interrupted*/) noexcept { return false; }
    /// A message is being shown or waits in the scene (any thread, lock-free).
    virtual bool messageBusy() const noexcept { return false; }
};

/// Default text when SceneConfig::text is empty (the plugin's scene choice starts with it).
inline constexpr const char* kDefaultText = "exit";

} // namespace armadillo::braille
