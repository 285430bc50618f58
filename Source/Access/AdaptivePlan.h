#pragma once
// Training that adapts and remembers (issue 26). The plan is made one trial at a time from the
// reader's whole history (ReaderProfile, across sessions) and this session's answers:
//
//   weight(item) = 0.2 + 4·e² + 0.5·min(age / N, 1.5)
//     e   = (wrong + 1) / (shown + 2) over the item's last 5 presentations (Laplace: an unseen
//           item counts as 0.5), so a letter the reader keeps confusing comes back far more
//           often than one they know (e → 1: weight ≈ 4.2; known: ≈ 0.2–0.9);
//     age = answers since the item was last shown (spaced repetition: what has not been seen
//           for a while comes back), N = the number of items in the stage.
//   The item just shown is not drawn again at once. Draws use the seed (std::mt19937_64 with
//   `%`-free arithmetic: the same seed gives the same plan on every platform).
// Confused pairs side by side: every 6th trial, when the reader has mixed up two items at least
// twice (either way round), the pair is shown one after the other and the answer is both, in
// order ("pairs" stage). After a wrong answer the front end shows the right cell and, when the
// answer was another item, that item's cell next to it.
// From letters to words: once letters are steady — every letter answered at least twice, the
// last 20 letter answers ≥ 90 % right and no letter with e > 0.5 — the plan moves on to the
// next stage of `stages` (default: letters then words).
#include "Access/ReaderProfile.h"
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace armadillo::access {

struct AdaptiveOptions {
    std::vector<std::string> stages {"letters", "words"};   ///< in order; also signs, contractions
    std::vector<std::string> words;                         ///< items of "words" (lower case)
    std::vector<std::pair<std::string, std::string>> signs; ///< (shorthand, word) for "signs"
    std::vector<std::string> contractions;                  ///< items of "contractions"
    std::uint64_t seed = 1;
    int session = 1;                                        ///< the session's number in the profile
    std::string method = "rows";
};

struct PlannedTrial {
    std::string stage;       ///< letters, words, signs, contractions, pairs
    std::string expected;    ///< the right answer (lower case; a pair: both letters, no space)
    std::string shown;       ///< the text the display shows (a sign's shorthand; a pair "e i")
    std::string prompt;      ///< "which letter?", …
};

class AdaptivePlanner {
public:
    AdaptivePlanner(const ReaderProfile& history, const AdaptiveOptions& options);
    /// The next trial.
    PlannedTrial next();
    /// Records the answer to the trial next() gave (also appended to answers()).
    void record(const PlannedTrial& trial, const std::string& answer, bool correct, double rt, double t = -1.0);
    /// Every answer so far: the history's, then this session's.
    const std::vector<ReaderAnswer>& answers() const noexcept { return answers_; }
    const std::string& stage() const noexcept { return stages_[stage_]; }
    /// The current weight of an item of the current stage (for tests and the report).
    double weight(const std::string& item) const;

private:
    std::vector<std::string> items(const std::string& stage) const;
    bool steady(const std::string& stage) const;
    std::string pick(const std::vector<std::string>& items);
    AdaptiveOptions options_;
    std::vector<std::string> stages_;
    std::size_t stage_ = 0;
    std::vector<ReaderAnswer> answers_;
    std::mt19937_64 rng_;
    std::string last_;
    int trial_ = 0;
};

} // namespace armadillo::access
