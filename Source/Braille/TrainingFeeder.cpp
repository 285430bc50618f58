#include "Braille/TrainingFeeder.h"

namespace armadillo::braille {

namespace {
std::string trimmed(const std::string& s)
{
    const char* space = " \t\r\n\f\v";
    const auto b = s.find_first_not_of(space);
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(space) - b + 1);
}

/// Strict UTF-8: no overlong forms, no surrogates, nothing above U+10FFFF.
bool validUtf8(const std::string& s)
{
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        int extra = 0;
        char32_t cp = 0;
        if (c < 0x80) { ++i; continue; }
        if (c >= 0xC2 && c <= 0xDF) { extra = 1; cp = c & 0x1Fu; }
        else if (c >= 0xE0 && c <= 0xEF) { extra = 2; cp = c & 0x0Fu; }
        else if (c >= 0xF0 && c <= 0xF4) { extra = 3; cp = c & 0x07u; }
        else return false;
        if (i + static_cast<std::size_t>(extra) >= s.size()) return false;   // cut short
        for (int k = 1; k <= extra; ++k) {
            const auto cc = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
            if ((cc & 0xC0u) != 0x80u) return false;
            cp = (cp << 6) | (cc & 0x3Fu);
        }
        if ((extra == 2 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) || (extra == 3 && (cp < 0x10000 || cp > 0x10FFFF)))
            return false;
        i += static_cast<std::size_t>(extra) + 1;
    }
    return true;
}
} // namespace

std::string resultText(const TrainingNotice& result)
{
    // "correct", never "right": in the sides stage "right" is also an answer.
    const std::string what = result.right ? std::string("correct") : "wrong, it was '" + result.expected + "'";
    return result.byArm ? what + " (here, by the arm)" : what;
}

std::string TrainingAnswerFeeder::refusalText(Refusal r)
{
    switch (r) {
    case Refusal::None: return {};
    case Refusal::Empty: return "empty answer: type the answer first";
    case Refusal::TooLong:
        return "answer too long: at most " + std::to_string(kMaxAnswerBytes) + " bytes (that many plain letters, fewer accented ones)";
    case Refusal::NotUtf8: return "answer is not valid UTF-8 text";
    case Refusal::ControlCharacter: return "answer contains a tab, line break or other control character";
    case Refusal::Finished: return "the training is complete: no more answers";
    }
    return {};
}

TrainingAnswerFeeder::Refusal TrainingAnswerFeeder::add(const std::string& answer)
{
    if (finished_) return Refusal::Finished;
    std::string a = trimmed(answer);
    if (a.empty()) return Refusal::Empty;
    if (a.size() > kMaxAnswerBytes) return Refusal::TooLong;
    if (!validUtf8(a)) return Refusal::NotUtf8;
    for (const char ch : a)
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F) return Refusal::ControlCharacter;
    lines_.push_back(std::move(a));
    return Refusal::None;
}

std::vector<TrainingNotice> TrainingAnswerFeeder::poll(BrailleSceneControls& scene)
{
    std::vector<TrainingNotice> out;
    scene.collectTrainingLog();   // keeps the scene's log queue short in long sessions
    if (finished_) return out;
    const int count = scene.trainingTrialCount();
    // Trial first (acquire): the scene publishes the score before the trial, so the score read
    // next is at least the one that goes with this trial. Only our one answer is in flight, so
    // it is not newer either.
    const int trial = scene.trainingTrial();
    const int correct = scene.trainingCorrect();
    // "Here" by the arm (published before the trial, so seen with it). A typed answer already
    // on its way then answers the trial after (the scene scores answers in arrival order).
    if (const int arm = scene.trainingArmAnswers(); arm > armSeen_) {
        armSeen_ = arm;
        TrainingNotice n;
        n.kind = TrainingNotice::Kind::Result;
        n.trial = scene.trainingLastArmTrial();
        n.trialCount = count;
        n.correct = correct;
        n.answered = trial;
        n.answer = "here";
        n.expected = scene.trainingExpected(n.trial);
        n.stage = scene.trainingStage(n.trial);
        n.right = scene.trainingLastArmRight();
        n.byArm = true;
        if (awaiting_ && submittedAt_ == n.trial) {
            ++submittedAt_;
            rightBefore_ += n.right ? 1 : 0;
        }
        out.push_back(std::move(n));
    }
    if (awaiting_ && trial > submittedAt_) {
        TrainingNotice n;
        n.kind = TrainingNotice::Kind::Result;
        n.trial = submittedAt_;
        n.trialCount = count;
        n.correct = correct;
        n.answered = trial;
        n.answer = submitted_;
        n.expected = scene.trainingExpected(submittedAt_);
        n.stage = scene.trainingStage(submittedAt_);
        n.right = correct > rightBefore_;
        out.push_back(std::move(n));
        awaiting_ = false;
    }
    if (trial >= count) {
        finished_ = true;
        lines_.clear();   // typed after the last trial: nothing to answer
        TrainingNotice n;
        n.kind = TrainingNotice::Kind::Complete;
        n.trial = count;
        n.trialCount = count;
        n.correct = correct;
        n.answered = count;
        out.push_back(std::move(n));
        return out;
    }
    if (trial != announced_) {
        TrainingNotice n;
        n.kind = TrainingNotice::Kind::Prompt;
        n.trial = trial;
        n.trialCount = count;
        n.correct = correct;
        n.answered = trial;
        n.prompt = scene.trainingPrompt(trial);
        n.expected = scene.trainingExpected(trial);
        n.stage = scene.trainingStage(trial);
        out.push_back(std::move(n));
        announced_ = trial;
    }
    if (!awaiting_ && !lines_.empty()) {
        rightBefore_ = correct;
        if (scene.submitAnswer(lines_.front())) {   // false: the scene's queue is full, try next poll
            submitted_ = std::move(lines_.front());
            lines_.pop_front();
            submittedAt_ = trial;
            awaiting_ = true;
        }
    }
    return out;
}

void TrainingAnswerFeeder::reset()
{
    *this = TrainingAnswerFeeder();
}

} // namespace armadillo::braille
