#pragma once
// The training protocol of thesis §4.4.1, in its order, with a log a researcher can analyse:
//   sides     — a left, right or both-sides column; answer "left", "right" or "both"
//   hold      — a series of full cells; stop on the asked row and answer "here"
//   one-dot   — letters with exactly one dot in every row (l, s, …); answer the letter
//   gaps      — letters with an empty middle row (k, m, u, x); answer the letter
//   alphabet  — the whole alphabet as one string; answer it
//   letters   — random letters; answer the letter
//   words     — random words from the 50 sign words (Resources/Braille/signwords.txt)
//   signs     — the §5.3 sign shorthand: a sign word shown as its shortest unique prefix
//               ("ex" = EXIT, "en" = ENTRANCE); answer the whole word
//   contractions — Grade 2 (UEB) words written as one cell ("and", "the", "but" = b …); answer the word
// Every movement (roll change ≥ 1° or posture change), every displayed step and every answer
// is a row of the log, with its time.
//
// Threads: start(), update() and answer() are real-time (the braille scene calls them from
// Scene::control, on the audio thread in the plugin). They write fixed-size log records into an
// SPSC queue; the CSV text is built on the consumer side (drainLog(), logCsv(), saveLog()),
// by one other thread at a time, off the audio thread. A consumer that falls more than
// kLogCapacity records behind loses the newest ones, counted by droppedLogRecords().
#include "Braille/Reading.h"
#include "Core/SpscQueue.h"
#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace armadillo::braille {

enum class TrainingStage : std::uint8_t { Sides, Hold, OneDotPerRow, Gaps, Alphabet, Letters, Words, Signs, Contractions };
inline constexpr int kTrainingStageCount = 9;
const char* trainingStageName(TrainingStage s) noexcept;   ///< "sides", "hold", "one-dot", …
bool parseTrainingStage(const std::string& name, TrainingStage& out) noexcept;

struct TrainingOptions {
    std::vector<TrainingStage> stages {TrainingStage::Sides, TrainingStage::Hold, TrainingStage::OneDotPerRow,
                                       TrainingStage::Gaps, TrainingStage::Alphabet, TrainingStage::Letters,
                                       TrainingStage::Words};
    int trialsPerStage = 10;         ///< the alphabet stage always has one trial
    std::uint64_t seed = 1;
    std::vector<std::string> signWords;   ///< the words and signs stages draw from these (upper or lower case)
    DisplayMethod method = DisplayMethod::Rows;   ///< how cells are shown (`dots`: one dot at a time)
};

struct TrainingTrial {
    TrainingStage stage = TrainingStage::Sides;
    std::string prompt;              ///< what the teacher says ("left, right or both?", "stop on row 2")
    std::string expected;            ///< the right answer, lower case
    int holdRow = 0;                 ///< hold stage: the row (1..3) to stop on
    std::vector<ReadingUnit> units;  ///< what the display shows (Rows method)
};

/// Letters of the Grade 1 alphabet whose every row has exactly one dot.
std::vector<char> oneDotPerRowLetters();
/// Letters of the Grade 1 alphabet with an empty middle row and a dot below it.
std::vector<char> gapLetters();
/// The §5.3 sign shorthand: for each word (lower-cased, letters only) the shortest prefix no other
/// word of the list starts with ("exit" → "ex" next to "entrance" → "en"); the whole word when it
/// is itself the start of another. Pairs (shorthand, word), in the list's order, duplicates dropped.
std::vector<std::pair<std::string, std::string>> signShorthand(const std::vector<std::string>& words);
/// Words Unified English Braille Grade 2 writes as a single cell (liblouis en-ueb-g2.ctb decides
/// from a candidate list of wordsigns: and, for, of, the, with, but, can, do, …).
std::vector<std::string> contractionWords();
/// The shipped sign words, Braille/signwords.txt, from the first resource folder that has it or
/// the copy built in (Core/Resources.h); `resourceDir` is searched first when not empty.
std::vector<std::string> defaultSignWords(const std::string& resourceDir = {});
/// Reads a word list (one word a line, '#' comments); InputError for an empty or bad list.
std::vector<std::string> readWordList(const std::string& path);
/// The same from text already read; `path` names it in errors.
std::vector<std::string> parseWordList(std::string_view text, const std::string& path);

/// What happened, one per log row (the CSV's `event` column).
/// Gesture (since 0.3.x): an answer given by the arm (the `answer` column names the gesture,
/// "push"); the answer row follows it at the same time.
enum class TrainingEvent : std::uint8_t { Trial, Move, Direction, Row, WordGap, MessageGap, TextEnd, Answer, End, Gesture };
const char* trainingEventName(TrainingEvent e) noexcept;   ///< "trial", "move", …, "end", "gesture"

/// One log row as the control thread records it: fixed size, no strings to build.
struct TrainingLogRecord {
    double t = 0.0;                     ///< s
    TrainingEvent event = TrainingEvent::Trial;
    int trial = -1;                     ///< 0-based; −1 once the session is finished
    bool hasPosture = false;
    ReadingPosture posture = ReadingPosture::Invalid;
    double rollDeg = 0.0;               ///< NaN: no roll column
    int unit = -1, step = 0;            ///< unit −1: no unit/step columns
    bool hasMotors = false;
    MotorSet motors = 0;
    int correct = -1;                   ///< −1: no correct column
    std::array<char, 64> answer {};     ///< NUL-terminated, lower case, trimmed
};

class TrainingSession {
public:
    /// Builds every trial now (liblouis runs here, not during control).
    explicit TrainingSession(const TrainingOptions& options);
    TrainingSession(const TrainingSession&) = delete;            // the reader points at our cursor
    TrainingSession& operator=(const TrainingSession&) = delete;

    const std::vector<TrainingTrial>& trials() const noexcept { return trials_; }
    int trialIndex() const noexcept { return index_; }
    bool finished() const noexcept { return index_ >= static_cast<int>(trials_.size()); }
    const TrainingTrial& current() const { return trials_.at(static_cast<std::size_t>(index_)); }

    /// Starts the current trial at time t (logs it); called once before the first update.
    void start(double t);
    /// One control update: reads by roll and logs movement and displayed steps.
    ReadEvent update(double t, const Eigen::Vector3d& axis, const Eigen::Vector3d& normal, bool valid);
    /// Scores an answer to the current trial, logs it and moves to the next trial.
    /// Returns whether it was right. Ignored (false) once finished. Real-time: the answer is
    /// trimmed and lower-cased in a fixed buffer (answers beyond 63 bytes are cut).
    bool answer(double t, std::string_view answer);
    /// The hold stage answered by the arm: the "button pushing" movement (ArmPush.h) that began
    /// at `pushStart` s means "here", scored on the row shown when the push began (the push may
    /// have rolled the arm on by a step). Logs a `gesture` row ("push"), then the answer row.
    /// False (and nothing logged) when the current trial is not a hold trial. Real-time.
    bool answerHere(double t, double pushStart);
    /// Shows the current trial again from its first row (nothing logged: the rows shown next
    /// are). Real-time.
    void restartTrial() noexcept;

    RollReader& roll() noexcept { return reading_.roll(); }
    int correctCount() const noexcept { return correct_; }
    int answeredCount() const noexcept { return answered_; }

    static constexpr std::size_t kLogCapacity = 4096;   ///< records between two drains
    /// Consumer side (never the thread that calls update()/answer()): turns the queued records
    /// into CSV rows. Call it regularly in long live sessions; logCsv() and saveLog() call it too.
    void drainLog();
    /// The log as CSV text; header: t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct
    std::string logCsv();
    void saveLog(const std::string& path);   ///< atomic (whole or nothing)
    /// Records lost because the consumer did not drain in time (any thread).
    std::uint64_t droppedLogRecords() const noexcept { return dropped_.load(std::memory_order_relaxed); }

private:
    void beginTrial(double t);
    bool score(double t, std::string_view answer, const ReadingStep& shown);
    void log(const TrainingLogRecord& record) noexcept;
    TrainingLogRecord record(double t, TrainingEvent event) const noexcept;
    void appendRow(const TrainingLogRecord& r);

    std::vector<TrainingTrial> trials_;
    std::vector<ReadingCursor> cursors_;   ///< one per trial, built with it (no copy during control)
    int index_ = 0;
    ActiveReading reading_;
    ReadingStep shown_ {};
    ReadingStep previous_ {};      ///< the step shown before shown_ (hold answers by the arm)
    double shownSince_ = 0.0;      ///< s: when shown_ was shown
    bool started_ = false;
    ReadingPosture loggedPosture_ = ReadingPosture::Invalid;
    double loggedRoll_ = 0.0;
    int correct_ = 0, answered_ = 0;
    core::SpscQueue<TrainingLogRecord, kLogCapacity> records_; // control thread → consumer
    std::atomic<std::uint64_t> dropped_ {0};
    std::mutex consumer_;                                  // consumers only; never the control thread
    std::string log_;                                      // under consumer_
};

} // namespace armadillo::braille
