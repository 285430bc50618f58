#include "Braille/Training.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Resources.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <iterator>
#include <random>
#include <string_view>

namespace armadillo::braille {

namespace {
constexpr const char* kStageNames[kTrainingStageCount] {"sides", "hold", "one-dot", "gaps", "alphabet", "letters", "words", "signs",
                                                         "contractions"};

/// The Grade 1 cell of a lower-case letter, from liblouis (the same source as every text).
Dots letterCell(char letter)
{
    const BrailleDocument doc = translateText(std::string(1, letter), {});
    if (doc.messages.size() != 1 || doc.messages[0].symbols.size() != 1 || doc.messages[0].symbols[0].cells.size() != 1)
        throw core::InputError("text", 0, "", std::string("letter '") + letter + "' is not a single Grade 1 cell");
    return doc.messages[0].symbols[0].cells[0];
}

std::vector<ReadingUnit> unitsOfCells(const std::vector<Dots>& cells, DisplayMethod method)
{
    BrailleDocument doc;
    doc.messages.emplace_back();
    for (Dots c : cells) doc.messages[0].symbols.push_back({dotNumbers(c), {c}});
    return layoutDocument(doc, method);
}

std::vector<ReadingUnit> unitsOfText(const std::string& text, DisplayMethod method, int grade = 1)
{
    TranslationOptions o;
    o.grade = grade;
    return layoutDocument(translateText(text, o), method);
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

std::vector<std::pair<std::string, std::string>> signShorthand(const std::vector<std::string>& words)
{
    std::vector<std::string> keys;
    for (const std::string& w : words) {
        std::string k;
        for (unsigned char c : w)
            if (std::isalpha(c)) k += static_cast<char>(std::tolower(c));
        if (!k.empty() && std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    }
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& k : keys) {
        std::string shorthand = k;
        for (std::size_t n = 1; n <= k.size(); ++n) {
            const std::string prefix = k.substr(0, n);
            bool unique = true;
            for (const std::string& other : keys) unique = unique && (other == k || other.compare(0, n, prefix) != 0);
            if (unique) {
                shorthand = prefix;
                break;
            }
        }
        out.emplace_back(shorthand, k);
    }
    return out;
}

std::vector<std::string> contractionWords()
{
    // Candidates: UEB's one-cell wordsigns (the alphabetic wordsigns, the strong wordsigns and
    // the strong contractions standing alone). The table decides which are really one cell.
    static const char* const kCandidates[] {"and", "for", "of", "the", "with", "but", "can", "do", "every", "from", "go",
                                            "have", "just", "knowledge", "like", "more", "not", "people", "quite",
                                            "rather", "so", "that", "us", "very", "will", "it", "you", "as", "child",
                                            "shall", "this", "which", "out", "still", "in", "enough", "were", "his", "was", "be"};
    TranslationOptions o;
    o.grade = 2;
    std::vector<std::string> out;
    for (const char* w : kCandidates) {
        const BrailleDocument doc = translateText(w, o);
        if (doc.cellCount() == 1) out.push_back(w);
    }
    return out;
}

std::vector<std::string> defaultSignWords(const std::string& resourceDir)
{
    const core::ResourceFile file = core::readResource("Braille/signwords.txt", resourceDir);
    return parseWordList(file.bytes, file.origin);
}

std::vector<std::string> readWordList(const std::string& path) { return parseWordList(core::readWholeFile(path), path); }

std::vector<std::string> parseWordList(std::string_view text, const std::string& path)
{
    std::vector<std::string> words;
    long line = 0;
    std::size_t begin = 0;
    while (begin < text.size()) {
        std::size_t end = text.find('\n', begin);
        if (end == std::string::npos) end = text.size();
        ++line;
        const std::string w = trim(std::string(text.substr(begin, end - begin)));
        begin = end + 1;
        if (w.empty() || w.front() == '#') continue;
        for (unsigned char c : w)
            if (!std::isalpha(c) && c != ' ' && c != '\'' && c != '-')
                throw core::InputError(path, line, "", "a sign word may hold letters, spaces, ' and - only: '" + w + "'");
        words.push_back(w);
    }
    if (words.empty()) throw core::InputError(path, 0, "", "the word list is empty");
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
                trials_.push_back({stage, "left, right or both?", kAnswers[k], 0, unitsOfCells({cells[k]}, options.method)});
            }
            break;
        }
        case TrainingStage::Hold:
            for (int i = 0; i < n; ++i) {
                const int row = static_cast<int>(pick(3)) + 1;
                const Dots full = dotsFromNumbers("123456");
                trials_.push_back({stage, "stop on row " + std::to_string(row) + " and hold it", "here", row,
                                   unitsOfCells({full, full, full, full}, options.method)});
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
                trials_.push_back({stage, "which letter?", std::string(1, c), 0, unitsOfText(std::string(1, c), options.method)});
            }
            break;
        }
        case TrainingStage::Alphabet:
            trials_.push_back({stage, "read the alphabet", "abcdefghijklmnopqrstuvwxyz", 0,
                               unitsOfText("abcdefghijklmnopqrstuvwxyz", options.method)});
            break;
        case TrainingStage::Words:
            if (options.signWords.empty()) throw core::InputError("training", 0, "", "the words stage needs a word list");
            for (int i = 0; i < n; ++i) {
                const std::string w = lower(options.signWords[pick(options.signWords.size())]);
                trials_.push_back({stage, "which word?", w, 0, unitsOfText(w, options.method)});
            }
            break;
        case TrainingStage::Signs: {
            if (options.signWords.empty()) throw core::InputError("training", 0, "", "the signs stage needs a word list");
            const auto table = signShorthand(options.signWords);
            for (int i = 0; i < n; ++i) {
                const auto& [shorthand, word] = table[pick(table.size())];
                trials_.push_back({stage, "which sign?", word, 0, unitsOfText(shorthand, options.method)});
            }
            break;
        }
        case TrainingStage::Contractions: {
            const auto words = contractionWords();
            for (int i = 0; i < n; ++i) {
                const std::string& w = words[pick(words.size())];
                trials_.push_back({stage, "which word?", w, 0, unitsOfText(w, options.method, 2)});
            }
            break;
        }
        }
    }
    cursors_.reserve(trials_.size());
    for (const auto& trial : trials_) cursors_.emplace_back(trial.units);
    log_ = "t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct\n";
}

const char* trainingEventName(TrainingEvent e) noexcept
{
    static constexpr const char* kNames[] {"trial", "move", "direction", "row", "word-gap", "message-gap", "text-end", "answer", "end", "gesture"};
    const auto i = static_cast<std::size_t>(e);
    return i < std::size(kNames) ? kNames[i] : "?";
}

TrainingLogRecord TrainingSession::record(double t, TrainingEvent event) const noexcept
{
    TrainingLogRecord r;
    r.t = t;
    r.event = event;
    r.trial = finished() ? -1 : index_;
    r.rollDeg = core::kNaN;
    return r;
}

void TrainingSession::log(const TrainingLogRecord& r) noexcept
{
    if (!records_.push(r)) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void TrainingSession::appendRow(const TrainingLogRecord& r)
{
    std::string row;
    core::appendNumber(row, r.t, 9);
    row += ',';
    row += trainingEventName(r.event);
    row += ',';
    if (r.trial >= 0 && r.trial < static_cast<int>(trials_.size())) {
        const TrainingTrial& trial = trials_[static_cast<std::size_t>(r.trial)];
        row += trainingStageName(trial.stage);
        row += ',' + std::to_string(r.trial + 1) + ',';
        core::appendCsvField(row, trial.expected);
        row += ',';
        if (r.event == TrainingEvent::Trial) core::appendCsvField(row, trial.prompt);
    } else {
        row += ",,,";
    }
    row += ',';
    if (r.hasPosture) row += postureName(r.posture);
    row += ',';
    if (std::isfinite(r.rollDeg)) core::appendNumber(row, r.rollDeg, 6);
    row += ',';
    if (r.unit >= 0) row += std::to_string(r.unit + 1);
    row += ',';
    if (r.unit >= 0) row += std::to_string(r.step + 1);
    row += ',';
    if (r.hasMotors) core::appendCsvField(row, motorList(r.motors));
    row += ',';
    core::appendCsvField(row, std::string(r.answer.data()));
    row += ',';
    if (r.correct >= 0) row += std::to_string(r.correct);
    log_ += row + '\n';
}

void TrainingSession::drainLog()
{
    const std::lock_guard<std::mutex> lock(consumer_);
    TrainingLogRecord r;
    while (records_.pop(r)) appendRow(r);
}

void TrainingSession::beginTrial(double t)
{
    if (finished()) {
        log(record(t, TrainingEvent::End));
        return;
    }
    ReadingCursor& cursor = cursors_[static_cast<std::size_t>(index_)];
    cursor.rewind();
    reading_.setCursor(&cursor);
    shown_ = {};
    previous_ = {};
    log(record(t, TrainingEvent::Trial));
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
    if (p != loggedPosture_ || (p != ReadingPosture::Invalid && std::abs(core::wrapDeg180(e.roll.rollDeg - loggedRoll_)) >= 1.0)) {
        TrainingLogRecord r = record(t, TrainingEvent::Move);
        r.hasPosture = true;
        r.posture = p;
        r.rollDeg = p == ReadingPosture::Invalid ? core::kNaN : e.roll.rollDeg;
        log(r);
        loggedPosture_ = p;
        loggedRoll_ = e.roll.rollDeg;
    }
    if (e.roll.directionChanged) {
        TrainingLogRecord r = record(t, TrainingEvent::Direction);
        r.hasPosture = true;
        r.posture = p;
        r.rollDeg = e.roll.rollDeg;
        log(r);
    }
    if (e.stepped) {
        previous_ = shown_;
        shown_ = e.step;
        shownSince_ = t;
        TrainingLogRecord r = record(t, e.step.kind == StepKind::Cell ? TrainingEvent::Row
                                      : e.step.kind == StepKind::WordGap ? TrainingEvent::WordGap
                                      : e.step.kind == StepKind::MessageGap ? TrainingEvent::MessageGap : TrainingEvent::TextEnd);
        r.hasPosture = true;
        r.posture = p;
        r.rollDeg = e.roll.rollDeg;
        r.unit = e.step.unit;
        r.step = e.step.step;
        r.hasMotors = e.step.kind == StepKind::Cell;
        r.motors = e.step.motors;
        log(r);
    }
    return e;
}

bool TrainingSession::answer(double t, std::string_view given)
{
    if (!started_) start(t);
    if (finished()) return false;
    return score(t, given, shown_);
}

void TrainingSession::restartTrial() noexcept
{
    if (!started_ || finished()) return;
    ReadingCursor& cursor = cursors_[static_cast<std::size_t>(index_)];
    cursor.rewind();
    reading_.setCursor(&cursor);
    shown_ = {};
    previous_ = {};
}

bool TrainingSession::answerHere(double t, double pushStart)
{
    if (!started_) start(t);
    if (finished() || trials_[static_cast<std::size_t>(index_)].stage != TrainingStage::Hold) return false;
    TrainingLogRecord g = record(t, TrainingEvent::Gesture);
    std::memcpy(g.answer.data(), "push", 5);
    log(g);
    // A step shown after the push began was shown by the push itself (it rolled the arm on).
    return score(t, "here", shownSince_ > pushStart ? previous_ : shown_);
}

bool TrainingSession::score(double t, std::string_view given, const ReadingStep& shown)
{
    // Trimmed and lower-cased into the record's fixed buffer: no string is built here.
    const char* space = " \t\r\n";
    const auto b = given.find_first_not_of(space);
    const std::string_view trimmed = b == std::string_view::npos ? std::string_view() : given.substr(b, given.find_last_not_of(space) - b + 1);
    TrainingLogRecord r = record(t, TrainingEvent::Answer);
    const std::size_t n = std::min(trimmed.size(), r.answer.size() - 1);
    for (std::size_t i = 0; i < n; ++i) r.answer[i] = static_cast<char>(std::tolower(static_cast<unsigned char>(trimmed[i])));
    r.answer[n] = '\0';
    const std::string_view a(r.answer.data(), n);
    const TrainingTrial& trial = trials_[static_cast<std::size_t>(index_)];
    bool right = a == std::string_view(trial.expected);
    if (trial.stage == TrainingStage::Hold)
        right = right && shown.kind == StepKind::Cell && shown.step + 1 == trial.holdRow;
    ++answered_;
    if (right) ++correct_;
    r.unit = shown.kind == StepKind::Cell ? shown.unit : -1;
    r.step = shown.step;
    r.correct = right ? 1 : 0;
    log(r);
    ++index_;
    beginTrial(t);
    return right;
}

std::string TrainingSession::logCsv()
{
    drainLog();
    const std::lock_guard<std::mutex> lock(consumer_);
    return log_;
}

void TrainingSession::saveLog(const std::string& path) { core::writeFileAtomically(path, logCsv()); }

} // namespace armadillo::braille
