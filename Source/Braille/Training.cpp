#include "Braille/Training.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <random>
#include <string_view>

#ifndef ARMADILLO_RESOURCE_DIR
#define ARMADILLO_RESOURCE_DIR "Resources"
#endif

namespace armadillo::braille {

namespace {
constexpr const char* kStageNames[kTrainingStageCount] {"sides", "hold", "one-dot", "gaps", "alphabet", "letters", "words"};

/// The Grade 1 cell of a lower-case letter, from liblouis (the same source as every text).
Dots letterCell(char letter)
{
    const BrailleDocument doc = translateText(std::string(1, letter), {});
    if (doc.messages.size() != 1 || doc.messages[0].symbols.size() != 1 || doc.messages[0].symbols[0].cells.size() != 1)
        throw InputError("text", 0, "", std::string("letter '") + letter + "' is not a single Grade 1 cell");
    return doc.messages[0].symbols[0].cells[0];
}

std::vector<ReadingUnit> unitsOfCells(const std::vector<Dots>& cells)
{
    BrailleDocument doc;
    doc.messages.emplace_back();
    for (Dots c : cells) doc.messages[0].symbols.push_back({dotNumbers(c), {c}});
    return layoutDocument(doc, DisplayMethod::Rows);
}

std::vector<ReadingUnit> unitsOfText(const std::string& text)
{
    return layoutDocument(translateText(text, {}), DisplayMethod::Rows);
}

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}

void appendCsvField(std::string& out, const std::string& field)
{
    if (field.find_first_of(",\"\n\r") == std::string::npos) {
        out += field;
        return;
    }
    out += '"';
    for (char c : field) {
        if (c == '"') out += '"';
        out += c;
    }
    out += '"';
}
} // namespace

const char* trainingStageName(TrainingStage s) noexcept { return kStageNames[static_cast<int>(s)]; }

bool parseTrainingStage(const std::string& name, TrainingStage& out) noexcept
{
    for (int i = 0; i < kTrainingStageCount; ++i)
        if (name == kStageNames[i]) {
            out = static_cast<TrainingStage>(i);
            return true;
        }
    return false;
}

std::vector<char> oneDotPerRowLetters()
{
    std::vector<char> out;
    for (char c = 'a'; c <= 'z'; ++c) {
        const Dots d = letterCell(c);
        bool ok = true;
        for (int r = 0; r < 3; ++r) ok = ok && (((d >> r) & 1) + ((d >> (r + 3)) & 1)) == 1;
        if (ok) out.push_back(c);
    }
    return out;
}

std::vector<char> gapLetters()
{
    std::vector<char> out;
    for (char c = 'a'; c <= 'z'; ++c) {
        const Dots d = letterCell(c);
        if (rowSensation(d, 1) == 0 && rowSensation(d, 2) != 0) out.push_back(c);
    }
    return out;
}

std::string defaultSignWordsPath() { return std::string(ARMADILLO_RESOURCE_DIR) + "/Braille/signwords.txt"; }

std::vector<std::string> readWordList(const std::string& path)
{
    const std::string text = readWholeFile(path);
    std::vector<std::string> words;
    long line = 0;
    std::size_t begin = 0;
    while (begin < text.size()) {
        std::size_t end = text.find('\n', begin);
        if (end == std::string::npos) end = text.size();
        ++line;
        const std::string w = trim(text.substr(begin, end - begin));
        begin = end + 1;
        if (w.empty() || w.front() == '#') continue;
        for (unsigned char c : w)
            if (!std::isalpha(c) && c != ' ' && c != '\'' && c != '-')
                throw InputError(path, line, "", "a sign word may hold letters, spaces, ' and - only: '" + w + "'");
        words.push_back(w);
    }
    if (words.empty()) throw InputError(path, 0, "", "the word list is empty");
    return words;
}

TrainingSession::TrainingSession(const TrainingOptions& options)
{
    // std::mt19937_64 is specified bit-exactly, and we draw with `%` instead of a standard
    // distribution (those differ between libraries), so a seed gives the same session everywhere.
    std::mt19937_64 rng(options.seed);
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
    const int n = std::max(1, options.trialsPerStage);

    for (TrainingStage stage : options.stages) {
        switch (stage) {
        case TrainingStage::Sides: {
            static const char* const kAnswers[3] {"left", "right", "both"};
            const Dots cells[3] {dotsFromNumbers("123"), dotsFromNumbers("456"), dotsFromNumbers("123456")};
            for (int i = 0; i < n; ++i) {
                const std::size_t k = pick(3);
                trials_.push_back({stage, "left, right or both?", kAnswers[k], 0, unitsOfCells({cells[k]})});
            }
            break;
        }
        case TrainingStage::Hold:
            for (int i = 0; i < n; ++i) {
                const int row = static_cast<int>(pick(3)) + 1;
                const Dots full = dotsFromNumbers("123456");
                trials_.push_back({stage, "stop on row " + std::to_string(row) + " and hold it", "here", row,
                                   unitsOfCells({full, full, full, full})});
            }
            break;
        case TrainingStage::OneDotPerRow:
        case TrainingStage::Gaps:
        case TrainingStage::Letters: {
            std::vector<char> set;
            if (stage == TrainingStage::OneDotPerRow) set = oneDotPerRowLetters();
            else if (stage == TrainingStage::Gaps) set = gapLetters();
            else for (char c = 'a'; c <= 'z'; ++c) set.push_back(c);
            for (int i = 0; i < n; ++i) {
                const char c = set[pick(set.size())];
                trials_.push_back({stage, "which letter?", std::string(1, c), 0, unitsOfText(std::string(1, c))});
            }
            break;
        }
        case TrainingStage::Alphabet:
            trials_.push_back({stage, "read the alphabet", "abcdefghijklmnopqrstuvwxyz", 0,
                               unitsOfText("abcdefghijklmnopqrstuvwxyz")});
            break;
        case TrainingStage::Words:
            if (options.signWords.empty()) throw InputError("training", 0, "", "the words stage needs a word list");
            for (int i = 0; i < n; ++i) {
                const std::string w = lower(options.signWords[pick(options.signWords.size())]);
                trials_.push_back({stage, "which word?", w, 0, unitsOfText(w)});
            }
            break;
        }
    }
    log_ = "t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct\n";
}

void TrainingSession::log(double t, const char* event, const std::string& posture, double rollDeg, int unit, int step,
                          const std::string& motors, const std::string& answer, int correct)
{
    std::string row;
    appendNumber(row, t, 9);
    row += ',';
    row += event;
    row += ',';
    if (!finished()) {
        row += trainingStageName(current().stage);
        row += ',' + std::to_string(index_ + 1) + ',';
        appendCsvField(row, current().expected);
        row += ',';
        if (std::string_view(event) == "trial") appendCsvField(row, current().prompt);
    } else {
        row += ",,,";
    }
    row += ',' + posture + ',';
    if (std::isfinite(rollDeg)) appendNumber(row, rollDeg, 6);
    row += ',';
    if (unit >= 0) row += std::to_string(unit + 1);
    row += ',';
    if (unit >= 0) row += std::to_string(step + 1);
    row += ',';
    appendCsvField(row, motors);
    row += ',';
    appendCsvField(row, answer);
    row += ',';
    if (correct >= 0) row += std::to_string(correct);
    log_ += row + '\n';
}

void TrainingSession::beginTrial(double t)
{
    if (finished()) {
        log(t, "end", "", kNaN, -1, 0, "", "", -1);
        return;
    }
    cursor_ = ReadingCursor(current().units);
    reading_.setCursor(&cursor_);
    shown_ = {};
    log(t, "trial", "", kNaN, -1, 0, "", "", -1);
}

void TrainingSession::start(double t)
{
    if (started_) return;
    started_ = true;
    beginTrial(t);
}

ReadEvent TrainingSession::update(double t, const Eigen::Vector3d& axis, const Eigen::Vector3d& normal, bool valid)
{
    if (!started_) start(t);
    if (finished()) return {};
    const ReadEvent e = reading_.update(t, axis, normal, valid);
    const ReadingPosture p = e.roll.posture;
    if (p != loggedPosture_ || (p != ReadingPosture::Invalid && std::abs(wrapDeg180(e.roll.rollDeg - loggedRoll_)) >= 1.0)) {
        log(t, "move", postureName(p), p == ReadingPosture::Invalid ? kNaN : e.roll.rollDeg, -1, 0, "", "", -1);
        loggedPosture_ = p;
        loggedRoll_ = e.roll.rollDeg;
    }
    if (e.roll.directionChanged) log(t, "direction", postureName(p), e.roll.rollDeg, -1, 0, "", "", -1);
    if (e.stepped) {
        shown_ = e.step;
        const char* what = e.step.kind == StepKind::Cell ? "row"
                         : e.step.kind == StepKind::WordGap ? "word-gap"
                         : e.step.kind == StepKind::MessageGap ? "message-gap" : "text-end";
        log(t, what, postureName(p), e.roll.rollDeg, e.step.unit, e.step.step,
            e.step.kind == StepKind::Cell ? motorList(e.step.motors) : "", "", -1);
    }
    return e;
}

bool TrainingSession::answer(double t, const std::string& given)
{
    if (!started_) start(t);
    if (finished()) return false;
    const std::string a = lower(trim(given));
    const TrainingTrial& trial = current();
    bool right = a == trial.expected;
    if (trial.stage == TrainingStage::Hold)
        right = right && shown_.kind == StepKind::Cell && shown_.step + 1 == trial.holdRow;
    ++answered_;
    if (right) ++correct_;
    log(t, "answer", "", kNaN, shown_.kind == StepKind::Cell ? shown_.unit : -1, shown_.step, "", a, right ? 1 : 0);
    ++index_;
    beginTrial(t);
    return right;
}

std::string TrainingSession::logCsv() const { return log_; }

void TrainingSession::saveLog(const std::string& path) const { writeFileAtomically(path, log_); }

} // namespace armadillo::braille
