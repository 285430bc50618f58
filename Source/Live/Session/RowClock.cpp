#include "Live/Session/RowClock.h"
#include "Core/Errors.h"
#include "Live/Session/Instrument.h"
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace armadillo::live {

namespace {

/// What plays, in words for a message: the scene, or the set list.
struct Playing {
    engine::Engine* scene = nullptr;   ///< one scene (null: the cues)
    CuePlayer* cues = nullptr;         ///< a set list (null: one scene)
    std::string listName;

    bool listens(bool audio, std::string& whyNot) const
    {
        const char* what = audio ? "audio" : "MIDI";
        if (scene != nullptr) {
            whyNot = "scene '" + scene->config().scene + "' does not listen to " + what;
            return audio ? scene->listensToAudio() : scene->listensToMidi();
        }
        whyNot = "no cue of " + listName + " listens to " + what;
        for (int c = 0; c < cues->cueCount(); ++c)
            if (audio ? cues->engine(c).listensToAudio() : cues->engine(c).listensToMidi()) return true;
        return false;
    }
};

/// The audio input and MIDI notes a render hears, checked against what plays before anything
/// runs (InputError naming the recording, the MIDI file or the option).
void checkRenderInputs(const engine::RenderSettings& settings, const Playing& playing, double sampleRate)
{
    const std::string audioInName = settings.audioInName.empty() ? std::string("--audio-in") : settings.audioInName;
    const core::AudioBuffer* input = settings.audioIn;
    if (std::string whyNot; input && !playing.listens(true, whyNot))
        throw core::InputError(audioInName, 0, "", "--audio-in: " + whyNot + " (score, audio-touch and layered-keyboard do)");
    if (input) {
        if (input->channels.empty() || input->frames() == 0) throw core::InputError(audioInName, 0, "", "--audio-in: the recording holds no audio");
        if (std::fabs(input->sampleRate - sampleRate) > 0.5)
            throw core::InputError(audioInName, 0, "", "--audio-in: the recording's sample rate (" + std::to_string(static_cast<long>(input->sampleRate)) +
                                                      " Hz) differs from the engine's (" + std::to_string(static_cast<long>(sampleRate)) +
                                                      " Hz); give --sample-rate to match it");
    }
    if (std::string whyNot; settings.midiIn && !playing.listens(false, whyNot))
        throw core::InputError(settings.midiInName.empty() ? std::string("--midi-in") : settings.midiInName, 0, "",
                               "--midi-in: " + whyNot + " (layered-keyboard does)");
}

/// The motion files as rows, the sample rate and the span, checked before the instrument is built:
/// a time column that jumps to 1e12 s is a bad file, not a request for a year of audio.
struct RenderRows {
    engine::MotionRows right, left;
    double sampleRate = 0.0;
    double tail = 0.0;

    RenderRows(const core::CsvTable& motion, const engine::RenderSettings& settings)
    {
        right = engine::MotionRows::load(motion, settings.mount, "--mount");
        if (right.size() == 0) throw core::InputError(motion.source(), 0, "", "the motion file has no rows");
        // A rate taken from the recording names the recording; any other names the option.
        const bool rateOfInput = settings.audioIn != nullptr && settings.audioIn->sampleRate == settings.engine.sceneConfig.sampleRate;
        sampleRate = core::engineSampleRate(settings.engine.sceneConfig.sampleRate,
                                            rateOfInput && !settings.audioInName.empty() ? settings.audioInName : std::string("--sample-rate"));
        // Collected in memory (no audioSink), the audio is bounded more tightly: an hour of stereo
        // float is 1.4 GB; longer renders stream.
        tail = std::max(0.0, settings.tailSeconds);
        const double maxSeconds = settings.audioSink ? settings.maxSeconds : std::min(settings.maxSeconds, engine::kMaxCollectedRenderSeconds);
        engine::checkRenderSpan(motion, right.size(), [&](std::size_t i) { return right.time(i); }, tail, maxSeconds);
    }

    void loadLeft(const engine::RenderSettings& settings)
    {
        if (settings.leftMotion == nullptr) return;
        left = engine::MotionRows::load(*settings.leftMotion, settings.leftMount, "--mount-left");
        if (left.size() == 0) throw core::InputError(settings.leftMotion->source(), 0, "--motion-left", "the left arm's motion file has no rows");
    }
};

/// One offline render: the motion's rows clock the instrument's control step; the audio between
/// rows is rendered block by block with the recording and the MIDI notes it hears.
class RowClock {
public:
    RowClock(const RenderRows& rows, const engine::RenderSettings& settings, Instrument& instrument, std::vector<CueChange> changes)
        : rows_(rows.right), settings_(settings), instrument_(instrument), changes_(std::move(changes)), sampleRate_(rows.sampleRate),
          input_(settings.audioIn), block_(std::clamp(settings.blockSize, 1, 8192)), t0_(rows.right.time(0)),
          tEnd_(rows.right.time(rows.right.size() - 1) + rows.tail)
    {
        if (settings.leftMotion != nullptr) left_ = &rows.left;
        midiBlock_.resize(settings.midiIn ? settings.midiIn->size() : 0);
        inputChannels_.assign(input_ ? input_->channels.size() : 0, nullptr);
        inputScratch_.assign(inputChannels_.size(), std::vector<float>(static_cast<std::size_t>(block_), 0.0f));
        leftOut_.resize(static_cast<std::size_t>(block_));
        rightOut_.resize(static_cast<std::size_t>(block_));
        totalFrames_ = static_cast<std::size_t>(std::llround((tEnd_ - t0_) * sampleRate_)) + 1;
        result_.audio.sampleRate = sampleRate_;
        if (!settings.audioSink) result_.audio.channels.assign(2, std::vector<float>(totalFrames_, 0.0f));   // bounded by maxSeconds
        result_.tactile.reserve(rows_.size() + 1);
        previous_ = t0_;
    }

    engine::RenderResult run()
    {
        instrument_.beginStage();   // the set list (if any) taken before sample 0: it hears the recording from there
        if (input_) instrument_.processInput(inputChannels_.data(), static_cast<int>(inputChannels_.size()), 0);   // the recording itself, from sample 0
        for (std::size_t i = 0; i < rows_.size(); ++i) {
            renderUntil(rows_.time(i));
            controlRow(i);
        }
        renderUntil(tEnd_ + 1.0 / sampleRate_);
        // The render ends as a session does: every motor off, in one last packet (the tactile file's
        // last row), at the end of the audio.
        if (engine::Engine* sounding = instrument_.runner().running(); sounding != nullptr) sounding->allOff();
        result_.tactile.push_back({tEnd_, core::MotorLevels {}});
        result_.frames = frame_;
        return std::move(result_);
    }

private:
    void renderUntil(double t)
    {
        const auto target = std::min(totalFrames_, static_cast<std::size_t>(std::llround((t - t0_) * sampleRate_)));
        while (frame_ < target) {
            const int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(block_), target - frame_));
            if (settings_.midiIn) feedMidi(n);
            if (input_) feedInput(n);
            renderBlock(n);
            frame_ += static_cast<std::size_t>(n);
        }
    }

    /// The block's MIDI notes, before its audio (Scene::processMidi).
    void feedMidi(int n)
    {
        int count = 0;
        const auto& notes = *settings_.midiIn;
        while (nextMidi_ < notes.size()) {
            const auto at = static_cast<std::size_t>(std::max(0.0, std::round(notes[nextMidi_].t * sampleRate_)));
            if (at >= frame_ + static_cast<std::size_t>(n)) break;
            const engine::TimedMidiNote& m = notes[nextMidi_++];
            core::MidiNoteEvent& e = midiBlock_[static_cast<std::size_t>(count++)];
            e.offset = at > frame_ ? static_cast<int>(at - frame_) : 0;
            e.note = static_cast<std::uint8_t>(std::clamp(m.note, 0, 127));
            e.velocity = static_cast<std::uint8_t>(std::clamp(m.velocity, 0, 127));
            e.channel = static_cast<std::uint8_t>(std::clamp(m.channel, 0, 15));
        }
        if (count > 0) instrument_.processMidi(midiBlock_.data(), count);
    }

    /// The block of the recording; past its end silence still comes in (the input stays connected).
    void feedInput(int n)
    {
        for (std::size_t c = 0; c < inputChannels_.size(); ++c) {
            if (frame_ + static_cast<std::size_t>(n) <= input_->frames()) {
                inputChannels_[c] = input_->channels[c].data() + frame_;
                continue;
            }
            auto& scratch = inputScratch_[c];
            for (int i = 0; i < n; ++i) {
                const std::size_t at = frame_ + static_cast<std::size_t>(i);
                scratch[static_cast<std::size_t>(i)] = at < input_->frames() ? input_->channels[c][at] : 0.0f;
            }
            inputChannels_[c] = scratch.data();
        }
        instrument_.processInput(inputChannels_.data(), static_cast<int>(inputChannels_.size()), n);
    }

    void renderBlock(int n)
    {
        std::fill(leftOut_.begin(), leftOut_.begin() + n, 0.0f);
        std::fill(rightOut_.begin(), rightOut_.begin() + n, 0.0f);
        instrument_.render(leftOut_.data(), rightOut_.data(), n);
        for (int i = 0; i < n; ++i)
            result_.scenePeak = std::max({result_.scenePeak, std::fabs(leftOut_[static_cast<std::size_t>(i)]), std::fabs(rightOut_[static_cast<std::size_t>(i)])});
        if (input_ && settings_.mixAudioIn) {   // the recording as the listener hears it, under the scene's sound
            const float* first = inputChannels_[0];
            const float* second = inputChannels_[inputChannels_.size() > 1 ? 1 : 0];
            for (int i = 0; i < n; ++i) {
                leftOut_[static_cast<std::size_t>(i)] = std::clamp(leftOut_[static_cast<std::size_t>(i)] + first[i], -1.0f, 1.0f);
                rightOut_[static_cast<std::size_t>(i)] = std::clamp(rightOut_[static_cast<std::size_t>(i)] + second[i], -1.0f, 1.0f);
            }
        }
        for (int i = 0; i < n; ++i)
            result_.peak = std::max({result_.peak, std::fabs(leftOut_[static_cast<std::size_t>(i)]), std::fabs(rightOut_[static_cast<std::size_t>(i)])});
        if (settings_.audioSink) {
            settings_.audioSink(leftOut_.data(), rightOut_.data(), n);
        } else {
            std::copy(leftOut_.begin(), leftOut_.begin() + n, result_.audio.channels[0].begin() + static_cast<std::ptrdiff_t>(frame_));
            std::copy(rightOut_.begin(), rightOut_.begin() + n, result_.audio.channels[1].begin() + static_cast<std::ptrdiff_t>(frame_));
        }
    }

    void notePose(const core::Pose& p)
    {
        if (!std::isfinite(p.elevationDeg) || !std::isfinite(p.azimuthDeg)) return;
        result_.minElevation = anyPose_ ? std::min(result_.minElevation, p.elevationDeg) : p.elevationDeg;
        result_.maxElevation = anyPose_ ? std::max(result_.maxElevation, p.elevationDeg) : p.elevationDeg;
        result_.minAzimuth = anyPose_ ? std::min(result_.minAzimuth, p.azimuthDeg) : p.azimuthDeg;
        result_.maxAzimuth = anyPose_ ? std::max(result_.maxAzimuth, p.azimuthDeg) : p.azimuthDeg;
        anyPose_ = true;
    }

    /// Row i's step: the cue changes due, the stage, the one control step with the row as the
    /// right arm's sample and the left arm's rows up to its time.
    Instrument::Stepped stepRow(std::size_t i, double t)
    {
        while (nextChange_ < changes_.size() && changes_[nextChange_].t <= t - t0_ + 1e-9) instrument_.stage().cue(changes_[nextChange_++].cue);
        instrument_.beginStage();
        ControlStep step;
        step.source = SourceKind::Device;   // the recording stands in for the forearm
        step.recorded = {&rows_, i, i + 1};
        if (left_ != nullptr) {   // the left arm's rows up to this time
            const std::size_t from = leftRow_;
            while (leftRow_ < left_->size() && left_->time(leftRow_) <= t + 1e-9) ++leftRow_;
            step.recordedLeft = {left_, from, leftRow_};
        }
        step.transport.valid = true;
        step.transport.playing = true;
        step.transport.seconds = t - t0_;
        step.transport.bpm = settings_.bpm;
        step.transport.ppq = step.transport.seconds * settings_.bpm / 60.0;
        step.dt = t - previous_;
        return instrument_.step(step, t, true);
    }

    /// The control step of motion row i: what it felt and did.
    void controlRow(std::size_t i)
    {
        const double t = rows_.time(i);
        const Instrument::Stepped stepped = stepRow(i, t);
        const ControlResult& r = stepped.result;
        if (r.arm.valid) notePose(r.arm.features.pose);
        else ++result_.invalidRows;
        if (engine::Engine* sounding = stepped.engine; sounding != nullptr && sounding->failed())
            throw std::runtime_error("scene '" + sounding->config().scene + "' failed at t = " + std::to_string(t) + " s (motors off): " + sounding->failure());
        previous_ = t;
        result_.tactile.push_back({t, r.levels});
        if (left_ != nullptr) {
            const core::MotorLevels* leftLevels = instrument_.leftLevels();
            result_.leftTactile.push_back({t, leftLevels != nullptr ? *leftLevels : core::MotorLevels {}});
            result_.rightOrientation.push_back({t, r.arm.valid ? r.arm.q : Eigen::Quaterniond::Identity()});
            const bool leftValid = stepped.leftArm != nullptr && stepped.leftArm->valid;
            result_.leftOrientation.push_back({t, leftValid ? stepped.leftArm->q : Eigen::Quaterniond::Identity()});
        }
        ++result_.controlUpdates;
        for (engine::GestureEvent g; instrument_.published().popGesture(g);) result_.gestures.push_back(g);
        if (settings_.onStep && stepped.engine != nullptr) settings_.onStep(instrument_.mappingInput(stepped, t), *stepped.engine);
    }

    const engine::MotionRows& rows_;
    const engine::MotionRows* left_ = nullptr;
    const engine::RenderSettings& settings_;
    Instrument& instrument_;
    const std::vector<CueChange> changes_;
    const double sampleRate_;
    const core::AudioBuffer* input_;
    const int block_;
    const double t0_, tEnd_;
    std::size_t totalFrames_ = 0, frame_ = 0, nextMidi_ = 0, nextChange_ = 0, leftRow_ = 0;
    std::vector<core::MidiNoteEvent> midiBlock_;
    std::vector<const float*> inputChannels_;
    std::vector<std::vector<float>> inputScratch_;
    std::vector<float> leftOut_, rightOut_;
    double previous_ = 0.0;
    bool anyPose_ = false;
    engine::RenderResult result_;
};

/// The instrument's engine: the scene, or a monitor that only tracks the arm under a set list's
/// cues (as `play --setlist` has it).
void installEngine(Instrument& instrument, engine::EngineConfig config)
{
    auto slot = std::make_unique<EngineSlot>();
    slot->engine = std::make_unique<engine::Engine>(config);   // InputError for an unknown scene
    slot->sceneName = config.scene;
    instrument.loop().replace(std::move(slot));
}

} // namespace

engine::RenderResult renderOffline(const core::CsvTable& motion, const engine::RenderSettings& settings)
{
    const bool twoArms = settings.leftMotion != nullptr;
    if (twoArms && !settings.engine.twoArms) throw core::InputError("", 0, "--motion-left", "two arms need EngineConfig::twoArms");
    auto instrument = std::make_unique<Instrument>();
    installEngine(*instrument, settings.engine);
    RenderRows rows(motion, settings);
    checkRenderInputs(settings, Playing {instrument->loop().active()->engine.get(), nullptr, {}}, rows.sampleRate);
    rows.loadLeft(settings);
    instrument->leftArm().setOn(twoArms);
    return RowClock(rows, settings, *instrument, {}).run();
}

engine::RenderResult renderOffline(const core::CsvTable& motion, const engine::RenderSettings& settings, const SetList& list, std::vector<CueChange> changes)
{
    const bool twoArms = settings.leftMotion != nullptr;
    auto player = std::make_unique<CuePlayer>(list, settings.engine.sceneConfig, settings.engine.motorCount, twoArms, settings.engine.motorGain);
    for (const CueChange& c : changes)
        if (c.cue >= player->cueCount())
            throw core::InputError(list.source, 0, "--cue-at", "cue " + std::to_string(c.cue) + " does not exist (the set list has " +
                                                                 std::to_string(player->cueCount()) + " cues, 0.." + std::to_string(player->cueCount() - 1) + ")");
    std::stable_sort(changes.begin(), changes.end(), [](const CueChange& a, const CueChange& b) { return a.t < b.t; });
    RenderRows rows(motion, settings);
    checkRenderInputs(settings, Playing {nullptr, player.get(), list.source}, rows.sampleRate);
    rows.loadLeft(settings);
    auto instrument = std::make_unique<Instrument>();
    engine::EngineConfig monitor = settings.engine;
    monitor.scene = "monitor";
    monitor.parameters.clear();
    monitor.twoArms = false;
    installEngine(*instrument, monitor);
    instrument->stage().replace(std::move(player));   // the stage runs it (Live/Stage/Stage.h)
    instrument->leftArm().setOn(twoArms);
    return RowClock(rows, settings, *instrument, std::move(changes)).run();
}

} // namespace armadillo::live
