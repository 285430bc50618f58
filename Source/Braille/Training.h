#pragma once
// The training protocol of thesis §4.4.1, in its order, with a log a researcher can analyse:
//   sides     — a left, right or both-sides column; answer "left", "right" or "both"
//   hold      — a series of full cells; stop on the asked row and answer "here"
//   one-dot   — letters with exactly one dot in every row (l, s, …); answer the letter
//   gaps      — letters with an empty middle row (k, m, u, x); answer the letter
//   alphabet  — the whole alphabet as one string; answer it
//   letters   — random letters; answer the letter
//   words     — random words from the 50 sign words (Resources/Braille/signwords.txt)
// Every movement (roll change ≥ 1° or posture change), every displayed step and every answer
// is a row of the log, with its time.
#include "Braille/Reading.h"
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::braille {

enum class TrainingStage : std::uint8_t { Sides, Hold, OneDotPerRow, Gaps, Alphabet, Letters, Words };
inline constexpr int kTrainingStageCount = 7;
const char* trainingStageName(TrainingStage s) noexcept;   ///< "sides", "hold", "one-dot", …
bool parseTrainingStage(const std::string& name, TrainingStage& out) noexcept;

struct TrainingOptions {
    std::vector<TrainingStage> stages {TrainingStage::Sides, TrainingStage::Hold, TrainingStage::OneDotPerRow,
                                       TrainingStage::Gaps, TrainingStage::Alphabet, TrainingStage::Letters,
                                       TrainingStage::Words};
    int trialsPerStage = 10;         ///< the alphabet stage always has one trial
    std::uint64_t seed = 1;
    std::vector<std::string> signWords;   ///< the words stage draws from these (upper or lower case)
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
/// Resources/Braille/signwords.txt of the source tree this library was built from.
std::string defaultSignWordsPath();
/// Reads a word list (one word a line, '#' comments); InputError for an empty or bad list.
std::vector<std::string> readWordList(const std::string& path);

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
    /// Returns whether it was right. Ignored (false) once finished.
    bool answer(double t, const std::string& answer);

    RollReader& roll() noexcept { return reading_.roll(); }
    int correctCount() const noexcept { return correct_; }
    int answeredCount() const noexcept { return answered_; }

    /// The log as CSV text; header: t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct
    std::string logCsv() const;
    void saveLog(const std::string& path) const;   ///< atomic (whole or nothing)

private:
    void beginTrial(double t);
    void log(double t, const char* event, const std::string& posture, double rollDeg, int unit, int step,
             const std::string& motors, const std::string& answer, int correct);

    std::vector<TrainingTrial> trials_;
    int index_ = 0;
    ReadingCursor cursor_;
    ActiveReading reading_;
    ReadingStep shown_ {};
    bool started_ = false;
    ReadingPosture loggedPosture_ = ReadingPosture::Invalid;
    double loggedRoll_ = 0.0;
    int correct_ = 0, answered_ = 0;
    std::string log_;
};

} // namespace armadillo::braille
