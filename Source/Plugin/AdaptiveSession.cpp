#include "Plugin/AdaptiveSession.h"
#include "Access/Feedback.h"
#include "Braille/Reading.h"
#include "Braille/Training.h"
#include <algorithm>
#include <cctype>
#include <ctime>

namespace armadillo::plugin {

namespace {
// docs/BRAILLE.md "Passive drawing" (the CLI's Timing): s.
constexpr double kOn = 0.4, kGap = 0.2, kLetterGap = 0.5, kWordGap = 1.2;

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
} // namespace

bool AdaptiveSession::begin(const std::string& path, int trials, std::string& why)
{
    try {
        reader_ = access::loadReaderProfile(path);   // a file that does not exist yet: a new reader
        options_ = access::AdaptiveOptions {};
        options_.session = reader_.nextSession();
        options_.seed = static_cast<std::uint64_t>(options_.session);
        for (const std::string& w : braille::defaultSignWords()) options_.words.push_back(normalised(w));
        options_.signs = braille::signShorthand(braille::defaultSignWords());
        options_.contractions = braille::contractionWords();
        plan_ = std::make_unique<access::AdaptivePlanner>(reader_, options_);
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
    path_ = path;
    trials_ = std::max(1, trials);
    number_ = 0;
    right_ = 0;
    saveError_.clear();
    startClock_ = player_.clock();
    save();   // an unwritable profile is refused now, not after the reader has answered
    if (! saveError_.empty()) {
        why = saveError_;
        state_ = State::Idle;
        return false;
    }
    drawTrial(true);
    return true;
}

int AdaptiveSession::draw(const std::string& text, double after)
{
    braille::TranslationOptions o;
    o.grade = trial_.stage == "contractions" ? 2 : 1;
    const auto units = braille::layoutDocument(braille::translateText(text, o), braille::DisplayMethod::Rows);
    std::vector<access::TactileSegment> segs;
    double at = 0.0;
    for (const auto& unit : units) {
        if (segs.size() + unit.steps.size() + 1 > 120) break;   // the player takes 127 at a time; trials are short
        if (unit.kind != braille::UnitKind::Cell) {
            segs.push_back({at, 0.15, access::kUndersideMotors, kLevel * 0.6f, true, false});
            at += kWordGap;
            continue;
        }
        for (std::size_t s = 0; s < unit.steps.size(); ++s) {
            if (unit.steps[s] != 0) segs.push_back({at, kOn, unit.steps[s], kLevel, false, false});
            at += kOn + (s + 1 < unit.steps.size() ? kGap : kLetterGap);
        }
    }
    double length = 0.0;
    for (const auto& seg : segs) length = std::max(length, seg.at + seg.duration);
    return player_.play(std::move(segs), std::max(0.0, at - length) + after);
}

void AdaptiveSession::drawTrial(bool)
{
    trial_ = plan_->next();
    ++number_;
    // The "next" cue (the underside line swept wrist → elbow), then the cells, then "your turn"
    // (the underside line tapped twice), as the CLI.
    player_.play({{0.0, 0.1, braille::motorBit(0, 1), kLevel * 0.8f, true, false},
                  {0.1, 0.1, braille::motorBit(1, 1), kLevel * 0.8f, true, false},
                  {0.2, 0.1, braille::motorBit(2, 1), kLevel * 0.8f, true, false}},
                 0.5);
    draw(trial_.shown, 0.0);
    waitingFor_ = player_.play({{0.0, 0.12, access::kUndersideMotors, kLevel * 0.8f, false, false},
                                {0.22, 0.12, access::kUndersideMotors, kLevel * 0.8f, false, false}});
    state_ = State::Drawing;
}

void AdaptiveSession::again()
{
    if (state_ != State::Answering) return;
    draw(trial_.shown, 0.0);
    waitingFor_ = player_.play({{0.0, 0.12, access::kUndersideMotors, kLevel * 0.8f, false, false},
                                {0.22, 0.12, access::kUndersideMotors, kLevel * 0.8f, false, false}});
    state_ = State::Drawing;
}

bool AdaptiveSession::poll()
{
    if (state_ != State::Drawing || player_.completed() < waitingFor_) return false;
    state_ = State::Answering;
    return true;
}

std::string AdaptiveSession::prompt() const
{
    if (state_ != State::Answering) return {};
    return "Trial " + std::to_string(number_) + " of " + std::to_string(trials_) + ": " + trial_.prompt;
}

std::string AdaptiveSession::answer(const std::string& given, double responseSeconds)
{
    if (state_ != State::Answering) return {};
    const std::string g = normalised(given);
    const bool correct = ! g.empty() && g == normalised(trial_.expected);
    right_ += correct;
    plan_->record(trial_, g, correct, responseSeconds, player_.clock() - startClock_);
    std::string feedback = correct ? "right" : "wrong: it was '" + trial_.expected + "', you said '" + g + "'";
    player_.play(access::feedbackSensation(correct, kLevel), access::feedbackPause(correct));
    if (! correct) {
        // The right cell again; when the answer was another letter, that one next to it.
        std::string again = trial_.shown;
        if (trial_.stage == "letters" && g.size() == 1 && g[0] >= 'a' && g[0] <= 'z') again += " " + g;
        draw(again, 1.0);
    }
    save();
    if (! saveError_.empty()) feedback += ". The reader profile was not saved: " + saveError_;
    if (number_ >= trials_) {
        state_ = State::Done;
        feedback += ". Training complete: " + std::to_string(right_) + " of " + std::to_string(trials_) + " right";
        return feedback;
    }
    feedback += ". " + std::to_string(right_) + " of " + std::to_string(number_) + " right";
    drawTrial(true);
    return feedback;
}

void AdaptiveSession::stop()
{
    if (state_ == State::Idle) return;
    save();
    state_ = State::Idle;
}

void AdaptiveSession::save()
{
    try {
        access::ReaderProfile out = reader_;
        if (plan_) out.answers = plan_->answers();
        out.sessions.push_back({options_.session, utcNow(), options_.method, player_.clock() - startClock_});
        access::saveReaderProfile(path_, out);
        saveError_.clear();
    } catch (const std::exception& e) {
        saveError_ = e.what();
    }
}

} // namespace armadillo::plugin
