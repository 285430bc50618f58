#include "Procedures/AdaptiveTraining.h"
#include "Access/Feedback.h"
#include "Access/SessionLog.h"
#include "Braille/Reading.h"
#include "Braille/Sensations.h"
#include "Braille/Training.h"
#include "Core/AtomicFile.h"
#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace armadillo::procedures {

namespace {
/// Lower case, spaces and tabs removed: how answers and expectations are compared.
std::string normalised(const std::string& s)
{
    std::string out;
    for (unsigned char c : s)
        if (! std::isspace(c)) out += static_cast<char>(std::tolower(c));
    return out;
}

std::string utcNow()
{
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return date;
}

std::vector<std::string> stageList(const std::string& stages)
{
    std::vector<std::string> out;
    std::istringstream in(stages);
    for (std::string n; std::getline(in, n, ',');) {
        n.erase(0, n.find_first_not_of(" \t"));
        n.erase(n.find_last_not_of(" \t") + 1);
        out.push_back(n);
    }
    return out;
}

bool knownStage(const std::string& n) { return n == "letters" || n == "words" || n == "signs" || n == "contractions"; }

// Passive drawing, docs/BRAILLE.md (the timings Access/Feedback.h's drawnText uses too).
constexpr double kOn = 0.4, kGap = 0.2, kLetterGap = 0.5, kWordGap = 1.2;
// A TactilePlayer sequence holds 127 segments: a long text goes in chunks of whole units.
constexpr std::size_t kChunkSegments = 100;
} // namespace

std::string AdaptiveChoices::problem() const
{
    if (trials < 1 || trials > 10000) return "trials must lie in 1..10000 (not " + std::to_string(trials) + ")";
    if (level < 1 || level > 15) return "level must lie in 1..15 (not " + std::to_string(level) + ")";
    braille::DisplayMethod m;
    if (! braille::parseDisplayMethod(method, m)) return "method is one of rows, whole, columns, dots (not '" + method + "')";
    const auto list = stageList(stages);
    if (list.empty()) return "choose at least one stage: letters, words, signs, contractions";
    for (const auto& n : list)
        if (! knownStage(n)) return "the adaptive training trains the stages letters, words, signs, contractions (not '" + n + "')";
    return {};
}

double AdaptiveTraining::now() const { return player_.clock() - startClock_; }

void AdaptiveTraining::start(const Options& options)
{
    if (options.trials < 1 || options.trials > 10000) throw std::invalid_argument("trials must lie in 1..10000");
    if (options.stages.empty()) throw std::invalid_argument("choose at least one stage: letters, words, signs, contractions");
    for (const auto& n : options.stages)
        if (! knownStage(n)) throw std::invalid_argument("the adaptive training trains the stages letters, words, signs, contractions (not '" + n + "')");
    braille::DisplayMethod method;
    if (! braille::parseDisplayMethod(options.method, method)) throw std::invalid_argument("method is one of rows, whole, columns, dots");

    state_ = State::Idle;
    reader_ = access::loadReaderProfile(options.profilePath);   // a file that does not exist yet: a new reader
    access_ = access::AdaptiveOptions {};
    access_.session = reader_.nextSession();
    access_.seed = options.seed < 0 ? static_cast<std::uint64_t>(access_.session) : static_cast<std::uint64_t>(options.seed);
    access_.stages = options.stages;
    access_.method = braille::displayMethodName(method);
    const std::vector<std::string> words = options.signWords.empty() ? braille::defaultSignWords() : options.signWords;
    for (const std::string& w : words) {   // lower case; a phrase keeps its spaces (word gaps on the arm)
        std::string k;
        for (unsigned char c : w) k += static_cast<char>(std::tolower(c));
        access_.words.push_back(k);
    }
    access_.signs = braille::signShorthand(words);
    access_.contractions = braille::contractionWords();
    plan_ = std::make_unique<access::AdaptivePlanner>(reader_, access_);
    history_ = reader_.answers.size();

    options_ = options;
    options_.method = access_.method;
    log_ = access::kSessionLogHeader;
    number_ = right_ = answered_ = 0;
    verdict_ = {};
    saveError_.clear();
    startClock_ = player_.clock();
    queuedUntil_ = 0.0;
    lastQueued_ = player_.completed();
    repeatsSeen_ = player_.repeats();
    skipsSeen_ = player_.skips();
    // An unwritable profile or log is refused now, not after the reader has answered.
    access::ReaderProfile out = reader_;
    out.sessions.push_back({access_.session, utcNow(), access_.method, 0.0});
    access::saveReaderProfile(options_.profilePath, out);
    if (! options_.logPath.empty()) core::writeFileAtomically(options_.logPath, log_);
    drawTrial();
}

bool AdaptiveTraining::begin(const std::string& profilePath, const AdaptiveChoices& choices, std::string& why)
{
    if (const auto p = choices.problem(); ! p.empty()) {
        why = p;
        return false;
    }
    Options o;
    o.profilePath = profilePath;
    o.trials = choices.trials;
    o.stages = stageList(choices.stages);
    o.method = choices.method;
    o.level = static_cast<float>(choices.level);
    try {
        // The log next to the profile, numbered by the session the profile is at.
        const access::ReaderProfile reader = access::loadReaderProfile(profilePath);
        std::filesystem::path log(profilePath);
        log.replace_filename(log.stem().string() + "-session" + std::to_string(reader.nextSession()) + ".csv");
        o.logPath = log.string();
        start(o);
    } catch (const std::exception& e) {
        why = e.what();
        state_ = State::Idle;
        return false;
    }
    return true;
}

int AdaptiveTraining::queue(std::vector<access::TactileSegment> segments, double after)
{
    double length = 0.0;
    for (const auto& s : segments) length = std::max(length, s.at + s.duration);
    queuedUntil_ = std::max(queuedUntil_, now()) + length + after;
    lastQueued_ = player_.play(std::move(segments), after);
    return lastQueued_;
}

int AdaptiveTraining::draw(const std::string& text, double after)
{
    braille::DisplayMethod method = braille::DisplayMethod::Rows;
    braille::parseDisplayMethod(options_.method, method);
    braille::TranslationOptions o;
    o.grade = trial_.stage == "contractions" ? 2 : 1;
    const auto units = braille::layoutDocument(braille::translateText(text, o), method);
    const float level = options_.level;
    std::vector<access::TactileSegment> segs;
    double at = 0.0;                             // s into the current chunk
    double t0 = std::max(queuedUntil_, now());   // rows are logged with the times they will play at
    int sequence = 0;
    auto flush = [&](double extra) {
        double length = 0.0;   // a trailing pause is waited out too
        for (const auto& s : segs) length = std::max(length, s.at + s.duration);
        sequence = queue(std::move(segs), std::max(0.0, at - length) + extra);
        segs.clear();
        at = 0.0;
        t0 = std::max(queuedUntil_, now());
    };
    for (std::size_t u = 0; u < units.size(); ++u) {
        const braille::ReadingUnit& unit = units[u];
        if (segs.size() + unit.steps.size() + 1 > kChunkSegments) flush(0.0);
        if (unit.kind != braille::UnitKind::Cell) {
            const auto& cue = braille::kWordGapCue;
            segs.push_back({at, cue.duration, cue.motors, level * cue.gain, cue.soft, false});
            access::appendSessionLogRow(log_, t0 + at, "word-gap", &trial_, number_, "", static_cast<int>(u), 0, 0, false, "", -1);
            at += kWordGap;
            continue;
        }
        for (std::size_t s = 0; s < unit.steps.size(); ++s) {
            if (unit.steps[s] != 0) segs.push_back({at, kOn, unit.steps[s], level, false, false});
            access::appendSessionLogRow(log_, t0 + at, "row", &trial_, number_, "", static_cast<int>(u), static_cast<int>(s), unit.steps[s], true,
                                        "", -1);
            at += kOn + (s + 1 < unit.steps.size() ? kGap : kLetterGap);
        }
    }
    flush(after);
    return sequence;
}

void AdaptiveTraining::drawTrial()
{
    trial_ = plan_->next();
    ++number_;
    access::appendSessionLogRow(log_, now(), "trial", &trial_, number_, trial_.prompt, -1, 0, 0, false, "", -1);
    showTrial();
}

void AdaptiveTraining::showTrial()
{
    const float level = options_.level;
    access::appendSessionLogRow(log_, std::max(queuedUntil_, now()), "cue", &trial_, number_, "next", -1, 0, access::kUndersideMotors, true, "", -1);
    queue(access::nextCue(level), 0.5);
    draw(trial_.shown, 0.0);
    access::appendSessionLogRow(log_, std::max(queuedUntil_, now()), "cue", &trial_, number_, "your turn", -1, 0, access::kUndersideMotors, true, "",
                                -1);
    waitingFor_ = queue(access::yourTurnCue(level), 0.0);
    state_ = State::Drawing;
}

void AdaptiveTraining::again()
{
    if (state_ == State::Answering) showTrial();
}

bool AdaptiveTraining::poll()
{
    if (state_ != State::Drawing || player_.completed() < waitingFor_) return false;
    state_ = State::Answering;
    return true;
}

AdaptiveTraining::Gesture AdaptiveTraining::takeGesture()
{
    const int repeats = player_.repeats(), skips = player_.skips();
    Gesture g = Gesture::None;
    if (skips > skipsSeen_) g = Gesture::Skip;
    else if (repeats > repeatsSeen_) g = Gesture::Repeat;
    repeatsSeen_ = repeats;
    skipsSeen_ = skips;
    if (state_ != State::Answering || g == Gesture::None) return Gesture::None;
    noteGesture(g);
    return g;
}

void AdaptiveTraining::noteGesture(Gesture g)
{
    if (state_ != State::Answering || g == Gesture::None) return;
    access::appendSessionLogRow(log_, now(), "gesture", &trial_, number_, "", -1, 0, 0, false, g == Gesture::Skip ? "two twists" : "twist", -1);
}

std::string AdaptiveTraining::question() const { return state_ == State::Answering ? trial_.prompt : std::string(); }

std::string AdaptiveTraining::prompt() const
{
    if (state_ != State::Answering) return {};
    return "Trial " + std::to_string(number_) + " of " + std::to_string(options_.trials) + ": " + trial_.prompt;
}

std::string AdaptiveTraining::answer(const std::string& given, double responseSeconds)
{
    if (state_ != State::Answering) return {};
    const std::string g = normalised(given);
    return finishAnswer(g, ! g.empty() && g == normalised(trial_.expected), false, responseSeconds);
}

std::string AdaptiveTraining::skip(double responseSeconds)
{
    if (state_ != State::Answering) return {};
    return finishAnswer("(skipped)", false, true, responseSeconds);
}

std::string AdaptiveTraining::finishAnswer(const std::string& g, bool correct, bool skipped, double responseSeconds)
{
    const float level = options_.level;
    right_ += correct;
    ++answered_;
    plan_->record(trial_, g, correct, responseSeconds, now());
    access::appendSessionLogRow(log_, now(), "answer", &trial_, number_, "", -1, 0, 0, false, g, correct ? 1 : 0);
    verdict_ = {correct, skipped, g, trial_.expected,
                correct   ? std::string("right")
                : skipped ? "skipped: it was '" + trial_.expected + "'"
                          : "wrong: it was '" + trial_.expected + "', you said '" + g + "'"};
    access::appendSessionLogRow(log_, std::max(queuedUntil_, now()), "feedback", &trial_, number_, correct ? "right" : "wrong", -1, 0,
                                correct ? access::kAllNineMotors : access::kOuterMotors, true, "", correct ? 1 : 0);
    queue(access::feedbackSensation(correct, level), access::feedbackPause(correct));
    if (! correct) {
        // The right cell again; when the answer was another letter, that one next to it.
        std::string again = trial_.shown;
        if (trial_.stage == "letters" && g.size() == 1 && g[0] >= 'a' && g[0] <= 'z') again += " " + g;
        draw(again, 0.0);
    }
    // Stillness between trials: the reader tells the next trial from the replay.
    queue({}, options_.stillnessSeconds);
    std::string feedback = verdict_.text;
    if (number_ >= options_.trials) {
        state_ = State::Done;
        access::appendSessionLogRow(log_, now(), "end", nullptr, 0, "", -1, 0, 0, false, "", -1);
        save();
        feedback += ". Training complete: " + std::to_string(right_) + " of " + std::to_string(options_.trials) + " right";
        if (! saveError_.empty()) feedback += ". Not saved: " + saveError_;
        return feedback;
    }
    save();   // nothing lost if the session is cut short
    if (! saveError_.empty()) feedback += ". Not saved: " + saveError_;
    feedback += ". " + std::to_string(right_) + " of " + std::to_string(number_) + " right";
    drawTrial();
    return feedback;
}

void AdaptiveTraining::stop()
{
    if (state_ == State::Idle) return;
    if (state_ != State::Done) access::appendSessionLogRow(log_, now(), "end", nullptr, 0, "", -1, 0, 0, false, "stopped", -1);
    save();
    state_ = State::Idle;
}

std::size_t AdaptiveTraining::answersInProfile() const { return plan_ ? plan_->answers().size() : reader_.answers.size(); }

void AdaptiveTraining::save()
{
    try {
        access::ReaderProfile out = reader_;
        if (plan_) out.answers = plan_->answers();
        out.sessions.push_back({access_.session, utcNow(), access_.method, now()});
        access::saveReaderProfile(options_.profilePath, out);
        if (! options_.logPath.empty()) core::writeFileAtomically(options_.logPath, log_);
        saveError_.clear();
    } catch (const std::exception& e) {
        saveError_ = e.what();
    }
}

std::string AdaptiveTraining::summaryJson(bool stopped) const
{
    return "{\"session\":" + std::to_string(access_.session) + ",\"trials\":" + std::to_string(options_.trials) +
           ",\"trials_done\":" + std::to_string(answered_) + ",\"stopped\":" + (stopped ? "true" : "false") + ",\"correct\":" +
           std::to_string(right_) + ",\"answers_in_profile\":" + std::to_string(answersInProfile()) + ",\"history\":" + std::to_string(history_) + "}";
}

} // namespace armadillo::procedures
