#include "Plugin/AdaptiveSession.h"
#include "Access/Feedback.h"
#include "Access/SessionLog.h"
#include "Braille/Reading.h"
#include "Braille/Training.h"
#include "Core/AtomicFile.h"
#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <sstream>

namespace armadillo::plugin {

namespace {
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
        if (n != "letters" && n != "words" && n != "signs" && n != "contractions")
            return "the adaptive training trains the stages letters, words, signs, contractions (not '" + n + "')";
    return {};
}

double AdaptiveSession::now() const { return player_.clock() - startClock_; }

bool AdaptiveSession::begin(const std::string& path, const AdaptiveChoices& choices, std::string& why)
{
    if (const auto p = choices.problem(); ! p.empty()) {
        why = p;
        return false;
    }
    try {
        reader_ = access::loadReaderProfile(path);   // a file that does not exist yet: a new reader
        options_ = access::AdaptiveOptions {};
        options_.session = reader_.nextSession();
        options_.seed = static_cast<std::uint64_t>(options_.session);
        options_.stages = stageList(choices.stages);
        options_.method = choices.method;
        for (const std::string& w : braille::defaultSignWords()) options_.words.push_back(normalised(w));
        options_.signs = braille::signShorthand(braille::defaultSignWords());
        options_.contractions = braille::contractionWords();
        plan_ = std::make_unique<access::AdaptivePlanner>(reader_, options_);
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
    choices_ = choices;
    level_ = static_cast<float>(choices.level);
    path_ = path;
    std::filesystem::path log(path);
    log.replace_filename(log.stem().string() + "-session" + std::to_string(options_.session) + ".csv");
    logPath_ = log.string();
    log_ = access::kSessionLogHeader;
    number_ = 0;
    right_ = 0;
    saveError_.clear();
    startClock_ = player_.clock();
    queuedUntil_ = 0.0;
    repeatsSeen_ = player_.repeats();
    skipsSeen_ = player_.skips();
    save();   // an unwritable profile or log is refused now, not after the reader has answered
    if (! saveError_.empty()) {
        why = saveError_;
        state_ = State::Idle;
        return false;
    }
    drawTrial();
    return true;
}

int AdaptiveSession::queue(std::vector<access::TactileSegment> segments, double after)
{
    double length = 0.0;
    for (const auto& s : segments) length = std::max(length, s.at + s.duration);
    queuedUntil_ = std::max(queuedUntil_, now()) + length + after;
    return player_.play(std::move(segments), after);
}

int AdaptiveSession::draw(const std::string& text, double after)
{
    braille::DisplayMethod method = braille::DisplayMethod::Rows;
    braille::parseDisplayMethod(choices_.method, method);
    const int grade = trial_.stage == "contractions" ? 2 : 1;
    double end = 0.0;
    auto segs = access::drawnText(text, grade, method, level_, 0.0, end);
    // Logged with the times they will play at (after what is already queued), as the CLI does.
    const double t0 = std::max(queuedUntil_, now());
    for (const auto& s : segs)
        access::appendSessionLogRow(log_, t0 + s.at, s.motors == access::kUndersideMotors && s.soft ? "word-gap" : "row", &trial_, number_, "",
                                    -1, 0, s.motors, true, "", -1);
    double length = 0.0;
    for (const auto& s : segs) length = std::max(length, s.at + s.duration);
    return queue(std::move(segs), std::max(0.0, end - length) + after);
}

void AdaptiveSession::drawTrial()
{
    trial_ = plan_->next();
    ++number_;
    access::appendSessionLogRow(log_, now(), "trial", &trial_, number_, trial_.prompt, -1, 0, 0, false, "", -1);
    // The "next" cue, the cells, then "your turn", as the CLI.
    access::appendSessionLogRow(log_, std::max(queuedUntil_, now()), "cue", &trial_, number_, "next", -1, 0, access::kUndersideMotors, true, "", -1);
    queue(access::nextCue(level_), 0.5);
    draw(trial_.shown, 0.0);
    access::appendSessionLogRow(log_, std::max(queuedUntil_, now()), "cue", &trial_, number_, "your turn", -1, 0, access::kUndersideMotors, true, "", -1);
    waitingFor_ = queue(access::yourTurnCue(level_), 0.0);
    state_ = State::Drawing;
}

void AdaptiveSession::again()
{
    if (state_ != State::Answering) return;
    draw(trial_.shown, 0.0);
    waitingFor_ = queue(access::yourTurnCue(level_), 0.0);
    state_ = State::Drawing;
}

bool AdaptiveSession::poll()
{
    if (state_ != State::Drawing || player_.completed() < waitingFor_) return false;
    state_ = State::Answering;
    return true;
}

AdaptiveSession::Gesture AdaptiveSession::takeGesture()
{
    const int repeats = player_.repeats(), skips = player_.skips();
    Gesture g = Gesture::None;
    if (skips > skipsSeen_) g = Gesture::Skip;
    else if (repeats > repeatsSeen_) g = Gesture::Repeat;
    repeatsSeen_ = repeats;
    skipsSeen_ = skips;
    if (state_ != State::Answering || g == Gesture::None) return Gesture::None;
    access::appendSessionLogRow(log_, now(), "gesture", &trial_, number_, "", -1, 0, 0, false, g == Gesture::Skip ? "two twists" : "twist", -1);
    return g;
}

std::string AdaptiveSession::prompt() const
{
    if (state_ != State::Answering) return {};
    return "Trial " + std::to_string(number_) + " of " + std::to_string(choices_.trials) + ": " + trial_.prompt;
}

std::string AdaptiveSession::answer(const std::string& given, double responseSeconds)
{
    if (state_ != State::Answering) return {};
    const std::string g = normalised(given);
    return finishAnswer(g, ! g.empty() && g == normalised(trial_.expected), false, responseSeconds);
}

std::string AdaptiveSession::skip(double responseSeconds)
{
    if (state_ != State::Answering) return {};
    return finishAnswer("(skipped)", false, true, responseSeconds);
}

std::string AdaptiveSession::finishAnswer(const std::string& g, bool correct, bool skipped, double responseSeconds)
{
    right_ += correct;
    plan_->record(trial_, g, correct, responseSeconds, now());
    access::appendSessionLogRow(log_, now(), "answer", &trial_, number_, "", -1, 0, 0, false, g, correct ? 1 : 0);
    std::string feedback = correct ? "right" : skipped ? "skipped: it was '" + trial_.expected + "'" : "wrong: it was '" + trial_.expected + "', you said '" + g + "'";
    access::appendSessionLogRow(log_, std::max(queuedUntil_, now()), "feedback", &trial_, number_, correct ? "right" : "wrong", -1, 0,
                                correct ? access::kAllNineMotors : access::kOuterMotors, true, "", correct ? 1 : 0);
    queue(access::feedbackSensation(correct, level_), access::feedbackPause(correct));
    if (! correct) {
        // The right cell again; when the answer was another letter, that one next to it.
        std::string again = trial_.shown;
        if (trial_.stage == "letters" && g.size() == 1 && g[0] >= 'a' && g[0] <= 'z') again += " " + g;
        draw(again, 1.0);
    }
    if (number_ >= choices_.trials) {
        state_ = State::Done;
        access::appendSessionLogRow(log_, now(), "end", nullptr, 0, "", -1, 0, 0, false, "", -1);
        save();
        feedback += ". Training complete: " + std::to_string(right_) + " of " + std::to_string(choices_.trials) + " right";
        if (! saveError_.empty()) feedback += ". Not saved: " + saveError_;
        return feedback;
    }
    save();
    if (! saveError_.empty()) feedback += ". Not saved: " + saveError_;
    feedback += ". " + std::to_string(right_) + " of " + std::to_string(number_) + " right";
    drawTrial();
    return feedback;
}

void AdaptiveSession::stop()
{
    if (state_ == State::Idle) return;
    if (state_ != State::Done) access::appendSessionLogRow(log_, now(), "end", nullptr, 0, "", -1, 0, 0, false, "", -1);
    save();
    state_ = State::Idle;
}

void AdaptiveSession::save()
{
    try {
        access::ReaderProfile out = reader_;
        if (plan_) out.answers = plan_->answers();
        out.sessions.push_back({options_.session, utcNow(), options_.method, now()});
        access::saveReaderProfile(path_, out);
        writeFileAtomically(logPath_, log_);
        saveError_.clear();
    } catch (const std::exception& e) {
        saveError_ = e.what();
    }
}

} // namespace armadillo::plugin
