// The Arm Braille scene: reading by roll (§4.3), passive drawing (§4.2.1) and training (§4.4.1).
// Everything that allocates (liblouis, layouts, the training plan) happens in prepare(); control()
// only moves cursors, schedules short vibration bursts and states motor targets on the canvas.
#include "Braille/BrailleScene.h"
#include "Braille/ArmPush.h"
#include "Braille/Cells.h"
#include "Braille/Reading.h"
#include "Braille/Training.h"
#include "Core/Errors.h"
#include "Core/SpscQueue.h"
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>


namespace armadillo::braille {
namespace {

/// Short vibrations scheduled on the scene's clock; the level of a motor is the highest of the
/// bursts covering it now. Fixed capacity: no allocation during control.
class BurstPlayer {
public:
    void clear() noexcept { count_ = 0; }
    void add(double start, double duration, MotorSet motors, float level) noexcept
    {
        if (motors == 0 || duration <= 0.0 || level <= 0.0f) return;
        if (count_ == bursts_.size()) {   // full: the oldest burst gives way
            std::move(bursts_.begin() + 1, bursts_.end(), bursts_.begin());
            --count_;
        }
        bursts_[count_++] = {start, start + duration, motors, level};
    }
    void levels(double t, std::array<float, core::kGridMotors>& out) noexcept
    {
        out.fill(0.0f);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < count_; ++i) {
            const Burst& b = bursts_[i];
            if (b.end <= t) continue;   // finished
            bursts_[kept++] = b;
            if (b.start > t) continue;  // not yet
            for (int m = 0; m < core::kGridMotors; ++m)
                if (b.motors & (1u << m)) out[static_cast<std::size_t>(m)] = std::max(out[static_cast<std::size_t>(m)], b.level);
        }
        count_ = kept;
    }

private:
    struct Burst {
        double start = 0.0, end = 0.0;
        MotorSet motors = 0;
        float level = 0.0f;
    };
    std::array<Burst, 32> bursts_ {};
    std::size_t count_ = 0;
};

constexpr MotorSet kCentreColumn = kUndersideLine;
/// s between repeats of the held row in the training's hold stage when braille.holdRepeat is 0.
constexpr double kHoldStageRepeat = 0.8;

struct AnswerText {
    std::array<char, 64> text {};
};

class ArmBrailleScene final : public core::Scene, public BrailleSceneControls {
public:
    ArmBrailleScene()
    {
        const auto specs = parameterSpecs();
        for (std::size_t i = 0; i < specs.size(); ++i) params_[i].store(specs[i].defaultValue);
    }

    std::string_view name() const override { return "braille"; }
    std::vector<core::ParamSpec> parameters() const override { return parameterSpecs(); }

    static std::vector<core::ParamSpec> parameterSpecs()
    {
        return {
            {"braille.mode", "Mode", 0, 2, 0, "", {"active", "passive", "training"}},
            {"braille.method", "Method", 0, 3, 0, "", {"rows", "whole", "columns", "dots"}},
            {"braille.grade", "Grade", 0, 1, 0, "", {"1", "2"}},
            {"braille.level", "Level", 1, 15, 5, "", {}},
            {"braille.pulse", "Step pulse", 0.05f, 2.0f, 0.25f, "s", {}},
            {"braille.step", "Roll per step", 5, 45, 15, "deg", {}},
            {"braille.deadTime", "Dead time", 0, 0.5f, 0.12f, "s", {}},
            {"braille.holdRepeat", "Repeat held step", 0, 5, 0, "s", {}},
            {"braille.passiveOn", "Passive step", 0.05f, 2.0f, 0.4f, "s", {}},
            {"braille.passiveGap", "Passive gap", 0.0f, 2.0f, 0.2f, "s", {}},
            {"braille.passiveLetterGap", "Passive letter gap", 0.0f, 3.0f, 0.5f, "s", {}},
            {"braille.passiveWordGap", "Passive word gap", 0.1f, 5.0f, 1.2f, "s", {}},
            {"braille.passiveRepeat", "Passive repeat", 0.0f, 30.0f, 4.0f, "s", {}},
        };
    }

    void prepare(const core::SceneConfig& config) override
    {
        config_ = config;
        const std::string text = config.text.empty() ? std::string(kDefaultText) : config.text;
        for (int g = 0; g < 2; ++g) {
            TranslationOptions o;
            o.grade = g + 1;
            const BrailleDocument doc = loadDocument(text, o);
            if (doc.cellCount() == 0)
                throw core::InputError(text.front() == '@' ? text.substr(1) : std::string("text"), 0, "", "nothing to read: the braille text is blank");
            for (int m = 0; m < kDisplayMethodCount; ++m)
                cursors_[static_cast<std::size_t>(g * kDisplayMethodCount + m)] =
                    ReadingCursor(layoutDocument(doc, static_cast<DisplayMethod>(m)));
        }
        TrainingOptions training;
        training.seed = config.seed;
        try {
            training.signWords = defaultSignWords(config.resourceDir);
        } catch (const std::exception&) {
            // Reading and passive drawing need no resources: without the word list the training
            // protocol simply stops before its last stage.
            training.stages.pop_back();
        }
        training_ = std::make_unique<TrainingSession>(training);
        trialShown_.store(0, std::memory_order_release);
        trialsRight_.store(0, std::memory_order_release);
        prepared_ = true;
        applied_ = -1;
        reset();
    }

    void setParameter(int index, float value) noexcept override
    {
        if (index < 0 || index >= kParamCount) return;
        params_[static_cast<std::size_t>(index)].store(value);
    }

    void reset() override
    {
        for (auto& c : cursors_) c.rewind();
        reading_.reset();
        player_.clear();
        shown_ = {};
        push_.reset();
        nextPassiveAt_ = t_;
        passiveDone_ = false;
        clearPending_ = true;
        if (message_) finishMessage(true);
    }

    /// Training answers come from another thread (the app's UI); they cross a lock-free queue.
    bool submitAnswer(const std::string& answer) noexcept override
    {
        AnswerText a;
        std::strncpy(a.text.data(), answer.c_str(), a.text.size() - 1);
        return answers_.push(a);
    }

    bool showMessage(ArmMessage* message) noexcept override
    {
        if (!message) return false;
        busy_.store(true, std::memory_order_release);
        return message->urgent ? urgentIn_.push(message) : normalIn_.push(message);
    }
    bool takeFinishedMessage(std::uint64_t& id, bool& interrupted) noexcept override
    {
        FinishedMessage f;
        if (!finished_.pop(f)) return false;
        id = f.id;
        interrupted = f.interrupted;
        return true;
    }
    bool messageBusy() const noexcept override
    {
        return busy_.load(std::memory_order_acquire) || urgentIn_.size() > 0 || normalIn_.size() > 0;
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        if (!prepared_) return;
        t_ += std::clamp(in.dt, 0.0, 1.0);
        applyParameters();
        if (clearPending_) {
            out.motors.clearLevels();
            sent_.fill(0.0f);
            clearPending_ = false;
        }

        const Eigen::Quaterniond q = in.arm.q.normalized();
        const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitX();
        const Eigen::Vector3d normal = q * Eigen::Vector3d::UnitY();
        const bool valid = in.arm.valid && std::isfinite(q.w());

        takeMessages(out);
        if (message_ || config_.messagesOnly) {   // messages only: between them the arm is still
            if (message_) messageTick(axis, normal, valid, out);
            emitLevels(out);
            return;
        }

        switch (mode_) {
        case BrailleMode::Active:
            handle(reading_.update(t_, axis, normal, valid), out);
            break;
        case BrailleMode::Passive:
            passiveTick(out);
            break;
        case BrailleMode::Training: {
            AnswerText a;
            while (answers_.pop(a)) {
                const bool right = training_->answer(t_, a.text.data());
                out.events.emit("answer", right ? 1.0f : 0.0f);
                if (training_->finished()) out.events.emit("training-done", static_cast<float>(training_->correctCount()));
            }
            if (restartTrial_.exchange(false, std::memory_order_acq_rel)) {
                training_->restartTrial();
                shown_ = {};
            }
            // The hold stage's "here" by the arm: a push along the forearm (ArmPush.h). The
            // detector follows every sample so its gravity baseline is ready when a hold comes.
            if (push_.update(t_, in.arm.valid ? in.arm.accel.x() : core::kNaN, in.arm.gyro.norm()) && !training_->finished() &&
                training_->trials()[static_cast<std::size_t>(training_->trialIndex())].stage == TrainingStage::Hold) {
                const int trial = training_->trialIndex();
                const bool right = training_->answerHere(t_, push_.startedAt());
                out.events.emit("answer", right ? 1.0f : 0.0f);
                if (training_->finished()) out.events.emit("training-done", static_cast<float>(training_->correctCount()));
                lastArmTrial_.store(trial, std::memory_order_relaxed);
                lastArmRight_.store(right, std::memory_order_relaxed);
                armAnswers_.fetch_add(1, std::memory_order_release);
            }
            handle(training_->update(t_, axis, normal, valid), out);
            // Score first, then the trial: a reader that sees the new trial sees its score too.
            trialsRight_.store(training_->correctCount(), std::memory_order_release);
            trialShown_.store(training_->trialIndex(), std::memory_order_release);
            break;
        }
        }

        // The training's "hold a row" exercise (thesis §4.4.1: stop on a row and hold the
        // character there) needs the held row to stay felt: a single 0.25 s pulse would leave
        // the reader holding nothing. In that stage a held row repeats every
        // braille.holdRepeat s, or every kHoldStageRepeat s when that is off.
        double holdRepeat = param(kParamHoldRepeat);
        if (mode_ == BrailleMode::Training && training_ && !training_->finished() &&
            training_->trials()[static_cast<std::size_t>(training_->trialIndex())].stage == TrainingStage::Hold &&
            !(holdRepeat > 0.0))
            holdRepeat = kHoldStageRepeat;
        if (mode_ != BrailleMode::Passive && holdRepeat > 0.0 && shown_.kind == StepKind::Cell && shown_.motors != 0 &&
            t_ - shownAt_ >= holdRepeat) {
            player_.add(t_, pulse_, shown_.motors, level_);
            shownAt_ = t_;
        }
        emitLevels(out);
    }

    void emitLevels(core::SceneOutput& out)
    {
        std::array<float, core::kGridMotors> levels {};
        player_.levels(t_, levels);
        for (int m = 0; m < core::kGridMotors; ++m) {
            const auto i = static_cast<std::size_t>(m);
            if (levels[i] != sent_[i]) {
                out.motors.setLevel(m, levels[i]);
                sent_[i] = levels[i];
            }
        }
    }

    std::string trainingLogCsv() const override { return training_ ? training_->logCsv() : std::string(); }
    void collectTrainingLog() override
    {
        if (training_) training_->drainLog();
    }
    int trainingTrial() const noexcept override { return trialShown_.load(std::memory_order_acquire); }
    int trainingCorrect() const noexcept override { return trialsRight_.load(std::memory_order_acquire); }
    int trainingTrialCount() const noexcept override
    {
        return training_ ? static_cast<int>(training_->trials().size()) : 0;
    }
    std::string trainingPrompt(int trial) const override
    {
        if (!training_ || trial < 0 || trial >= trainingTrialCount()) return {};
        return training_->trials()[static_cast<std::size_t>(trial)].prompt;
    }
    std::string trainingExpected(int trial) const override
    {
        if (!training_ || trial < 0 || trial >= trainingTrialCount()) return {};
        return training_->trials()[static_cast<std::size_t>(trial)].expected;
    }

    std::string trainingStage(int trial) const override
    {
        if (!training_ || trial < 0 || trial >= trainingTrialCount()) return {};
        return trainingStageName(training_->trials()[static_cast<std::size_t>(trial)].stage);
    }
    void restartTrainingTrial() noexcept override { restartTrial_.store(true, std::memory_order_release); }
    int trainingArmAnswers() const noexcept override { return armAnswers_.load(std::memory_order_acquire); }
    int trainingLastArmTrial() const noexcept override { return lastArmTrial_.load(std::memory_order_relaxed); }
    bool trainingLastArmRight() const noexcept override { return lastArmRight_.load(std::memory_order_relaxed); }

private:
    double param(int i) const noexcept { return static_cast<double>(params_[static_cast<std::size_t>(i)].load()); }
    int choice(int i, int count) const noexcept
    {
        return std::clamp(static_cast<int>(std::lround(param(i))), 0, count - 1);
    }

    void applyParameters()
    {
        const int mode = choice(kParamMode, 3), method = choice(kParamMethod, kDisplayMethodCount), grade = choice(kParamGrade, 2);
        const int key = (mode * 2 + grade) * kDisplayMethodCount + method;
        if (key != applied_) {
            applied_ = key;
            mode_ = static_cast<BrailleMode>(mode);
            active_ = &cursors_[static_cast<std::size_t>(grade * kDisplayMethodCount + method)];
            reset();
            reading_.setCursor(active_);
        }
        level_ = static_cast<float>(std::clamp(param(kParamLevel), 0.0, 15.0));
        pulse_ = std::clamp(param(kParamPulse), 0.01, 5.0);
        RollReaderParams rp = reading_.roll().params();
        rp.stepDeg = std::clamp(param(kParamStep), 1.0, 90.0);
        rp.deadTime = std::clamp(param(kParamDeadTime), 0.0, 2.0);
        reading_.roll().setParams(rp);
        if (training_) training_->roll().setParams(rp);
    }

    void handle(const ReadEvent& e, core::SceneOutput& out)
    {
        if (e.roll.directionChanged) {
            const bool forward = e.roll.posture == ReadingPosture::Forward;
            directionCue(forward);
            out.events.emit("direction", forward ? 1.0f : -1.0f);
        }
        if (e.stepped) {
            out.events.emit("advance", e.roll.posture == ReadingPosture::Forward ? 1.0f : -1.0f);
            show(e.step, pulse_, out);
        }
    }

    void show(const ReadingStep& s, double duration, core::SceneOutput& out)
    {
        shown_ = s;
        shownAt_ = t_;
        switch (s.kind) {
        case StepKind::Cell:
            player_.add(t_, duration, s.motors, level_);   // an empty row adds nothing: a pause
            break;
        case StepKind::WordGap:
            // A line along the underside: no letter row has the centre column alone.
            cue(std::array<CueBurst, 1> {kWordGapCue}, t_);
            out.events.emit("word", static_cast<float>(s.unit));
            break;
        case StepKind::MessageGap:
        case StepKind::TextEnd:
            // Two taps of that line: the end of a message (and of the text).
            cue(kDoubleTapCue, t_);
            out.events.emit(s.kind == StepKind::TextEnd ? "end" : "message", static_cast<float>(s.unit));
            break;
        }
    }

    /// §4.3.2: "a simple passive tactile sensation ... when the direction is changed": the
    /// underside line swept elbow → wrist for forward, wrist → elbow for backward.
    void directionCue(bool forward)
    {
        for (int k = 0; k < 3; ++k) {
            const int row = forward ? 2 - k : k;
            player_.add(t_ + 0.1 * k, 0.1, motorBit(row, 1), level_ * 0.8f);
        }
    }

    template <std::size_t N>
    void cue(const std::array<CueBurst, N>& bursts, double at) noexcept
    {
        for (const auto& b : bursts) player_.add(at + b.at, b.duration, b.motors, level_ * b.gain);
    }

    /// One step of passive drawing (§4.2.1) of `cursor`: shows it, and sets `nextAt` to when the
    /// next step is due (the end of the text waits one step on time).
    ReadingStep drawStep(ReadingCursor& cursor, core::SceneOutput& out, double& nextAt)
    {
        const ReadingStep s = cursor.advance(true);
        const double on = param(kParamPassiveOn);
        show(s, on, out);
        double wait = on;
        switch (s.kind) {
        case StepKind::Cell: {
            const auto& unit = cursor.units()[static_cast<std::size_t>(s.unit)];
            const bool last = s.step + 1 >= static_cast<int>(unit.steps.size());
            wait += last ? param(kParamPassiveLetterGap) : param(kParamPassiveGap);
            break;
        }
        case StepKind::WordGap: wait = param(kParamPassiveWordGap); break;
        case StepKind::MessageGap: wait = 2.0 * param(kParamPassiveWordGap); break;
        case StepKind::TextEnd: break;
        }
        nextAt = t_ + std::max(wait, 0.01);
        return s;
    }

    void passiveTick(core::SceneOutput& out)
    {
        if (passiveDone_ || t_ < nextPassiveAt_ || !active_) return;
        const ReadingStep s = drawStep(*active_, out, nextPassiveAt_);
        if (s.kind == StepKind::TextEnd) {
            const double repeat = param(kParamPassiveRepeat);
            if (repeat > 0.0) {
                active_->rewind();
                nextPassiveAt_ = t_ + 0.5 + repeat;
            } else {
                passiveDone_ = true;
            }
        }
    }

    // --- Messages (issue 35) -------------------------------------------------------------------
    enum class MessagePhase { Announce, Body, After };
    static constexpr double kAnnounceToSweep = 0.8;   ///< s from the "message waiting" cue to the sweep
    static constexpr double kSweepToBody = 0.8;       ///< s from the sweep's start to the first cell
    static constexpr double kAfterEnd = 0.8;          ///< s after the double tap before the message is done

    void takeMessages(core::SceneOutput& out)
    {
        ArmMessage* m = nullptr;
        if (urgentIn_.pop(m)) {
            if (message_) finishMessage(true);
            startMessage(m, out);
        } else if (!message_ && !trainingRunning() && normalIn_.pop(m)) {
            // A message that is not urgent waits while a training runs (its trials must not be
            // cut into); it starts once the training is over or the scene leaves training.
            startMessage(m, out);
        }
        if (!message_ && urgentIn_.size() == 0 && normalIn_.size() == 0) busy_.store(false, std::memory_order_release);
    }

    bool trainingRunning() const noexcept { return mode_ == BrailleMode::Training && training_ && !training_->finished(); }

    void startMessage(ArmMessage* m, core::SceneOutput& out)
    {
        message_ = m;
        busy_.store(true, std::memory_order_release);
        player_.clear();   // what was playing stops: the message starts on a still arm
        shown_ = {};
        m->cursor.rewind();
        cue(kMessageWaitingCue, t_);
        cue(kSweepCue, t_ + kAnnounceToSweep);
        messagePhase_ = MessagePhase::Announce;
        messageAt_ = t_ + kAnnounceToSweep + kSweepToBody;
        out.events.emit("message-start", static_cast<float>(m->id));
    }

    void finishMessage(bool interrupted) noexcept
    {
        finished_.push({message_->id, interrupted});   // full only if the front end never collects: then it is not told
        message_ = nullptr;
        player_.clear();
        shown_ = {};
        reading_.setCursor(active_);
        reading_.reset();
    }

    void messageTick(const Eigen::Vector3d& axis, const Eigen::Vector3d& normal, bool valid, core::SceneOutput& out)
    {
        switch (messagePhase_) {
        case MessagePhase::Announce:
            if (t_ < messageAt_) return;
            messagePhase_ = MessagePhase::Body;
            if (!message_->timed) {
                reading_.setCursor(&message_->cursor);
                reading_.reset();
            }
            [[fallthrough]];
        case MessagePhase::Body:
            if (message_->timed) {
                if (t_ < messageAt_) return;
                if (drawStep(message_->cursor, out, messageAt_).kind == StepKind::TextEnd) {
                    messagePhase_ = MessagePhase::After;
                    messageAt_ = t_ + kDoubleTapCue.back().at + kDoubleTapCue.back().duration + kAfterEnd;
                }
            } else {
                const ReadEvent e = reading_.update(t_, axis, normal, valid);
                handle(e, out);
                if (e.stepped && e.step.kind == StepKind::TextEnd && e.roll.posture == ReadingPosture::Forward) {
                    messagePhase_ = MessagePhase::After;
                    messageAt_ = t_ + kDoubleTapCue.back().at + kDoubleTapCue.back().duration + kAfterEnd;
                }
            }
            return;
        case MessagePhase::After:
            if (t_ < messageAt_) return;
            out.events.emit("message-end", static_cast<float>(message_->id));
            finishMessage(false);
            return;
        }
    }

    core::SceneConfig config_ {};
    std::array<std::atomic<float>, kParamCount> params_ {};
    std::array<ReadingCursor, 2 * kDisplayMethodCount> cursors_ {};
    ReadingCursor* active_ = nullptr;
    ActiveReading reading_;
    std::unique_ptr<TrainingSession> training_;
    std::atomic<int> trialShown_ {0}, trialsRight_ {0};   // published by control() for the UI
    std::atomic<int> armAnswers_ {0}, lastArmTrial_ {-1};  // "here" by the arm, published likewise
    std::atomic<bool> lastArmRight_ {false}, restartTrial_ {false};
    PushDetector push_;
    core::SpscQueue<AnswerText, 16> answers_;
    BurstPlayer player_;
    std::array<float, core::kGridMotors> sent_ {};
    BrailleMode mode_ = BrailleMode::Active;
    int applied_ = -1;
    bool prepared_ = false, clearPending_ = true, passiveDone_ = false;
    float level_ = 5.0f;
    double pulse_ = 0.25;
    double t_ = 0.0, shownAt_ = 0.0, nextPassiveAt_ = 0.0;
    ReadingStep shown_ {};
    // Messages: pointers cross in SPSC queues (the front end owns the messages), ids come back.
    core::SpscQueue<ArmMessage*, 4> urgentIn_, normalIn_;
    struct FinishedMessage {
        std::uint64_t id = 0;
        bool interrupted = false;
    };
    core::SpscQueue<FinishedMessage, 64> finished_;
    std::atomic<bool> busy_ {false};
    ArmMessage* message_ = nullptr;
    MessagePhase messagePhase_ = MessagePhase::Announce;
    double messageAt_ = 0.0;
};

} // namespace

std::unique_ptr<core::Scene> makeBrailleScene() { return std::make_unique<ArmBrailleScene>(); }

std::unique_ptr<ArmMessage> prepareArmMessage(const std::string& text, const std::string& source, int grade, DisplayMethod method,
                                              bool timed, bool urgent, std::uint64_t id)
{
    TranslationOptions o;
    o.grade = grade;
    BrailleDocument doc;
    try {
        doc = translateText(text, o);
    } catch (const core::InputError& e) {
        throw core::InputError(source, 0, "", e.what());
    }
    if (doc.cellCount() == 0) throw core::InputError(source, 0, "", "nothing to read: the message is blank");
    auto m = std::make_unique<ArmMessage>();
    m->id = id;
    m->timed = timed;
    m->urgent = urgent;
    m->cursor = ReadingCursor(layoutDocument(doc, method));
    return m;
}

} // namespace armadillo::braille
