#pragma once
// A braille reader's history (issue 26): every answer of every guided training session, kept in
// one JSON file across sessions, and the per-item statistics the adaptive plan and the progress
// report are made from. Format (docs/INTERFACES.md "Reader profile"):
//   {"format": "armadillo-reader", "version": 1, "name": "…",
//    "sessions": [{"session": 1, "date": "…", "method": "rows", "seconds": 312.5}, …],
//    "answers": [{"session": 1, "stage": "letters", "method": "rows", "expected": "e",
//                 "answer": "i", "correct": false, "rt": 2.25, "t": 31.5}, …]}
// `rt` is the response time in s from the end of the display to the answer, `t` the time of the
// answer in s since the session started (either null when unknown).
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::access {

struct ReaderAnswer {
    int session = 0;              ///< 1-based
    std::string stage;            ///< "letters", "words", "signs", "contractions", "pairs"
    std::string method;           ///< display method: rows, whole, columns, dots
    std::string expected, answer; ///< lower case
    bool correct = false;
    double rt = -1.0;             ///< s; < 0 = unknown
    double t = -1.0;              ///< s since the session started, at the answer; < 0 = unknown
};

struct ReaderSession {
    int session = 0;
    std::string date;             ///< ISO 8601 (UTC)
    std::string method;
    double seconds = 0.0;         ///< s the session lasted (display and answers)
};

struct ReaderProfile {
    std::string name;
    std::vector<ReaderSession> sessions;
    std::vector<ReaderAnswer> answers;
    int nextSession() const noexcept;
};

/// Parses the JSON above; InputError naming the source, line and key.
ReaderProfile parseReaderProfile(std::string_view json, const std::string& source);
/// Reads a profile; a file that does not exist yet is a new reader (an empty profile).
ReaderProfile loadReaderProfile(const std::string& path);
std::string readerProfileToJson(const ReaderProfile& profile);
void saveReaderProfile(const std::string& path, const ReaderProfile& profile);   ///< atomic

/// What the answers say about one item (a letter, a word).
struct ItemStats {
    int seen = 0, right = 0;
    double medianRt = -1.0;               ///< s; < 0 = no timed answer
    int lastSeen = -1;                    ///< index into the answers (−1 = never)
    std::vector<bool> recent;             ///< right/wrong of the last presentations, oldest first (≤ 5)
    std::map<std::string, int> confusedWith;   ///< answers given instead, and how often
};

/// Statistics of every item answered in `stage` (all stages when empty), from the answers.
std::map<std::string, ItemStats> itemStats(const std::vector<ReaderAnswer>& answers, const std::string& stage = {});

} // namespace armadillo::access
