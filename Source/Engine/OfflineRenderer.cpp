#include "Engine/OfflineRenderer.h"
#include <stdexcept>
#include "Core/Errors.h"
#include "Fusion/ArmTracker.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace armadillo::engine {

std::size_t MotionRows::size() const { return kind == core::MotionKind::Imu ? imu.size() : orientations.size(); }
double MotionRows::time(std::size_t i) const { return kind == core::MotionKind::Imu ? imu[i].t : orientations[i].t; }
core::ArmState MotionRows::apply(fusion::ArmTracker& tracker, std::size_t i) const
{
    return kind == core::MotionKind::Imu ? tracker.update(imu[i]) : tracker.updateOrientation(orientations[i].t, orientations[i].q);
}

MotionRows MotionRows::load(const core::CsvTable& table, const Eigen::Quaterniond& mount, const char* mountOption)
{
    MotionRows m;
    m.kind = detectMotionKind(table);
    if (m.kind == core::MotionKind::Imu) m.imu = readImu(table);
    else m.orientations = motionAsQuaternions(table);   // throws for unknown headers
    if (mount.angularDistance(Eigen::Quaterniond::Identity()) == 0.0) return m;
    if (m.kind == core::MotionKind::Pose)
        throw core::InputError(table.source(), 0, mountOption, "a pose file is the forearm's own pose, not a sensor's: a mount applies to IMU and quaternion files");
    const Eigen::Quaterniond r = mount.normalized();
    for (core::ImuSample& s : m.imu) {
        s.gyro = r * s.gyro;
        s.accel = r * s.accel;
        if (s.mag.allFinite()) s.mag = r * s.mag;
    }
    for (core::TimedQuaternion& q : m.orientations) q.q = (q.q * r.conjugate()).normalized();
    return m;
}

void checkRenderSpan(const core::CsvTable& motion, std::size_t rows, const std::function<double(std::size_t)>& timeOf, double tailSeconds,
                     double maxSeconds)
{
    if (rows == 0) return;
    const double t0 = timeOf(0);
    const double tail = std::max(0.0, tailSeconds);
    for (std::size_t i = 0; i < rows; ++i)
        if (timeOf(i) - t0 + tail > maxSeconds) {
            char what[160];
            std::snprintf(what, sizeof what, "the file would render %.6g s from its first row (at most %.6g s): is the time column in seconds?",
                          timeOf(i) - t0 + tail, maxSeconds);
            motion.fail(i, motion.columnIndex("t"), what);
        }
}

namespace {

/// One engine, built from the settings: what `render --scene` plays.
class EnginePerformer final : public OfflinePerformer {
public:
    explicit EnginePerformer(const EngineConfig& config) : engine_(config) {}
    core::MotorLevels control(const core::ArmState& right, const core::ArmState* left, const core::Transport& transport, double dt) override
    {
        return left != nullptr ? engine_.control(right, *left, transport, dt) : engine_.control(right, transport, dt);
    }
    core::MotorLevels leftLevels() override { return engine_.leftLevels(); }
    void allOff() override { engine_.allOff(); }
    Engine& sounding() override { return engine_; }
    void processMidi(const core::MidiNoteEvent* events, int count) override { engine_.processMidi(events, count); }
    void processInput(const float* const* in, int channels, int n) override { engine_.processInput(in, channels, n); }
    void renderAudio(float* left, float* right, int n) override { engine_.renderAudio(left, right, n); }
    void popGestures(std::vector<GestureEvent>& out) override
    {
        GestureEvent g;
        while (engine_.popGesture(g)) out.push_back(g);
    }
    bool listensToAudio(std::string& whyNot) const override
    {
        whyNot = "scene '" + engine_.config().scene + "' does not listen to audio";
        return engine_.listensToAudio();
    }
    bool listensToMidi(std::string& whyNot) const override
    {
        whyNot = "scene '" + engine_.config().scene + "' does not listen to MIDI";
        return engine_.listensToMidi();
    }

private:
    Engine engine_;
};

} // namespace

RenderResult renderOffline(const core::CsvTable& motion, const RenderSettings& settings)
{
    if (settings.leftMotion != nullptr && !settings.engine.twoArms) throw core::InputError("", 0, "--motion-left", "two arms need EngineConfig::twoArms");
    EnginePerformer performer(settings.engine);
    return renderOffline(motion, settings, performer);
}

namespace {

/// The audio input and MIDI notes a render hears, checked against the performer before anything
/// runs (InputError naming the recording, the MIDI file or the option).
void checkRenderInputs(const RenderSettings& settings, OfflinePerformer& engine, double sampleRate)
{
    const std::string audioInName = settings.audioInName.empty() ? std::string("--audio-in") : settings.audioInName;
    const core::AudioBuffer* input = settings.audioIn;
    if (std::string whyNot; input && !engine.listensToAudio(whyNot))
        throw core::InputError(audioInName, 0, "", "--audio-in: " + whyNot + " (score, audio-touch and layered-keyboard do)");
    if (input) {
        if (input->channels.empty() || input->frames() == 0) throw core::InputError(audioInName, 0, "", "--audio-in: the recording holds no audio");
        if (std::fabs(input->sampleRate - sampleRate) > 0.5)
            throw core::InputError(audioInName, 0, "", "--audio-in: the recording's sample rate (" + std::to_string(static_cast<long>(input->sampleRate)) +
                                                      " Hz) differs from the engine's (" + std::to_string(static_cast<long>(sampleRate)) +
                                                      " Hz); give --sample-rate to match it");
    }
    if (std::string whyNot; settings.midiIn && !engine.listensToMidi(whyNot))
        throw core::InputError(settings.midiInName.empty() ? std::string("--midi-in") : settings.midiInName, 0, "",
                         "--midi-in: " + whyNot + " (layered-keyboard does)");
}

/// One offline render: the motion's rows drive the control step (the file's clock), the audio
/// between rows is rendered block by block with the recording and the MIDI notes it hears.
class OfflineRun {
public:
    OfflineRun(const MotionRows& source, const RenderSettings& settings, OfflinePerformer& engine, double sampleRate, double tail)
        : source_(source), settings_(settings), engine_(engine), sampleRate_(sampleRate), input_(settings.audioIn),
          block_(std::clamp(settings.blockSize, 1, 8192)), t0_(source.time(0)), tEnd_(source.time(source.size() - 1) + tail)
    {
        midiBlock_.resize(settings.midiIn ? settings.midiIn->size() : 0);
        inputChannels_.assign(input_ ? input_->channels.size() : 0, nullptr);
        inputScratch_.assign(inputChannels_.size(), std::vector<float>(static_cast<std::size_t>(block_), 0.0f));
        left_.resize(static_cast<std::size_t>(block_));
        right_.resize(static_cast<std::size_t>(block_));
        totalFrames_ = static_cast<std::size_t>(std::llround((tEnd_ - t0_) * sampleRate)) + 1;
        result_.audio.sampleRate = sampleRate;
        if (!settings.audioSink) result_.audio.channels.assign(2, std::vector<float>(totalFrames_, 0.0f));   // bounded by maxSeconds
        result_.tactile.reserve(source.size() + 1);
        previous_ = t0_;
    }

    /// The left arm's rows (two arms).
    void setLeft(const MotionRows* left) { leftSource_ = left; }

    RenderResult run()
    {
        if (input_) engine_.processInput(inputChannels_.data(), static_cast<int>(inputChannels_.size()), 0);   // the recording itself, from sample 0
        for (std::size_t i = 0; i < source_.size(); ++i) {
            renderUntil(source_.time(i));
            controlRow(i);
        }
        renderUntil(tEnd_ + 1.0 / sampleRate_);
        // The render ends as a session does: every motor off, in one last packet (the tactile file's
        // last row), at the end of the audio.
        engine_.allOff();
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
            const TimedMidiNote& m = notes[nextMidi_++];
            core::MidiNoteEvent& e = midiBlock_[static_cast<std::size_t>(count++)];
            e.offset = at > frame_ ? static_cast<int>(at - frame_) : 0;
            e.note = static_cast<std::uint8_t>(std::clamp(m.note, 0, 127));
            e.velocity = static_cast<std::uint8_t>(std::clamp(m.velocity, 0, 127));
            e.channel = static_cast<std::uint8_t>(std::clamp(m.channel, 0, 15));
        }
        if (count > 0) engine_.processMidi(midiBlock_.data(), count);
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
        engine_.processInput(inputChannels_.data(), static_cast<int>(inputChannels_.size()), n);
    }

    void renderBlock(int n)
    {
        std::fill(left_.begin(), left_.begin() + n, 0.0f);
        std::fill(right_.begin(), right_.begin() + n, 0.0f);
        engine_.renderAudio(left_.data(), right_.data(), n);
        for (int i = 0; i < n; ++i)
            result_.scenePeak = std::max({result_.scenePeak, std::fabs(left_[static_cast<std::size_t>(i)]), std::fabs(right_[static_cast<std::size_t>(i)])});
        if (input_ && settings_.mixAudioIn) {   // the recording as the listener hears it, under the scene's sound
            const float* first = inputChannels_[0];
            const float* second = inputChannels_[inputChannels_.size() > 1 ? 1 : 0];
            for (int i = 0; i < n; ++i) {
                left_[static_cast<std::size_t>(i)] = std::clamp(left_[static_cast<std::size_t>(i)] + first[i], -1.0f, 1.0f);
                right_[static_cast<std::size_t>(i)] = std::clamp(right_[static_cast<std::size_t>(i)] + second[i], -1.0f, 1.0f);
            }
        }
        for (int i = 0; i < n; ++i)
            result_.peak = std::max({result_.peak, std::fabs(left_[static_cast<std::size_t>(i)]), std::fabs(right_[static_cast<std::size_t>(i)])});
        if (settings_.audioSink) {
            settings_.audioSink(left_.data(), right_.data(), n);
        } else {
            std::copy(left_.begin(), left_.begin() + n, result_.audio.channels[0].begin() + static_cast<std::ptrdiff_t>(frame_));
            std::copy(right_.begin(), right_.begin() + n, result_.audio.channels[1].begin() + static_cast<std::ptrdiff_t>(frame_));
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

    /// The control step of motion row i: the arm (both arms), the engine, what it felt and did.
    void controlRow(std::size_t i)
    {
        const double t = source_.time(i);
        engine_.beforeRow(t - t0_);
        const core::ArmState arm = source_.apply(tracker_, i);
        const bool twoArms = leftSource_ != nullptr;
        if (twoArms)   // the left arm's rows up to this time
            while (leftRow_ < leftSource_->size() && leftSource_->time(leftRow_) <= t + 1e-9) leftArm_ = leftSource_->apply(leftTracker_, leftRow_++);
        core::Transport transport;
        transport.valid = true;
        transport.playing = true;
        transport.seconds = t - t0_;
        transport.bpm = settings_.bpm;
        transport.ppq = transport.seconds * settings_.bpm / 60.0;
        core::MotorLevels levels {};
        if (arm.valid) {
            levels = engine_.control(arm, twoArms ? &leftArm_ : nullptr, transport, t - previous_);
            notePose(arm.features.pose);
        } else {
            engine_.allOff();
            ++result_.invalidRows;
        }
        if (Engine& sounding = engine_.sounding(); sounding.failed())
            throw std::runtime_error("scene '" + sounding.config().scene + "' failed at t = " + std::to_string(t)
                                     + " s (motors off): " + sounding.failure());
        previous_ = t;
        result_.tactile.push_back({t, levels});
        if (twoArms) {
            result_.leftTactile.push_back({t, engine_.leftLevels()});
            result_.rightOrientation.push_back({t, arm.valid ? arm.q : Eigen::Quaterniond::Identity()});
            result_.leftOrientation.push_back({t, leftArm_.valid ? leftArm_.q : Eigen::Quaterniond::Identity()});
        }
        ++result_.controlUpdates;
        const std::size_t firstGesture = result_.gestures.size();
        engine_.popGestures(result_.gestures);
        if (settings_.onControl)
            settings_.onControl(t, arm, twoArms ? &leftArm_ : nullptr, result_.gestures.data() + firstGesture, result_.gestures.size() - firstGesture,
                                engine_.sounding());
    }

    const MotionRows& source_;
    const RenderSettings& settings_;
    OfflinePerformer& engine_;
    const double sampleRate_;
    const core::AudioBuffer* input_;
    const int block_;
    const double t0_, tEnd_;
    std::size_t totalFrames_ = 0, frame_ = 0, nextMidi_ = 0;
    std::vector<core::MidiNoteEvent> midiBlock_;
    std::vector<const float*> inputChannels_;
    std::vector<std::vector<float>> inputScratch_;
    std::vector<float> left_, right_;
    fusion::ArmTracker tracker_, leftTracker_;
    const MotionRows* leftSource_ = nullptr;
    std::size_t leftRow_ = 0;
    core::ArmState leftArm_ {};
    double previous_ = 0.0;
    bool anyPose_ = false;
    RenderResult result_;
};

} // namespace

RenderResult renderOffline(const core::CsvTable& motion, const RenderSettings& settings, OfflinePerformer& engine)
{
    const MotionRows source = MotionRows::load(motion, settings.mount, "--mount");
    if (source.size() == 0) throw core::InputError(motion.source(), 0, "", "the motion file has no rows");
    // A rate taken from the recording names the recording; any other names the option.
    const bool rateOfInput = settings.audioIn != nullptr && settings.audioIn->sampleRate == settings.engine.sceneConfig.sampleRate;
    const double sampleRate = core::engineSampleRate(settings.engine.sceneConfig.sampleRate,
                                               rateOfInput && !settings.audioInName.empty() ? settings.audioInName : std::string("--sample-rate"));

    // The span is checked before the engine starts or anything is rendered: a time column that
    // jumps to 1e12 s is a bad file, not a request for a year of audio.
    // Collected in memory (no audioSink), the audio is bounded more tightly: an hour of stereo
    // float is 1.4 GB; longer renders stream.
    const double tail = std::max(0.0, settings.tailSeconds);
    const double maxSeconds = settings.audioSink ? settings.maxSeconds : std::min(settings.maxSeconds, kMaxCollectedRenderSeconds);
    checkRenderSpan(motion, source.size(), [&](std::size_t i) { return source.time(i); }, tail, maxSeconds);
    checkRenderInputs(settings, engine, sampleRate);
    MotionRows leftSource;
    if (settings.leftMotion != nullptr) {
        leftSource = MotionRows::load(*settings.leftMotion, settings.leftMount, "--mount-left");
        if (leftSource.size() == 0) throw core::InputError(settings.leftMotion->source(), 0, "--motion-left", "the left arm's motion file has no rows");
    }
    OfflineRun run(source, settings, engine, sampleRate, tail);
    if (settings.leftMotion != nullptr) run.setLeft(&leftSource);
    return run.run();
}

std::string silenceReason(const RenderResult& r, const RenderSettings& settings)
{
    if (r.peak > 0.0f) return "";
    const std::string& scene = settings.engine.scene;
    // Scenes without a sound of their own (docs/INTERFACES.md, scene list).
    if (scene == "monitor") return "the monitor scene makes no sound (it is for recordings and link tests; motors stay off)";
    if (scene == "score" || scene == "audio-touch") {
        if (!settings.audioIn)
            return "the " + scene + " scene makes no sound of its own: it follows a recording (give --audio-in FILE.wav; "
                   "the recording is then mixed into the output)";
        if (!settings.mixAudioIn) return "the " + scene + " scene makes no sound of its own, and --no-audio-in-mix left the recording out";
        return "the recording given with --audio-in is silent, and the " + scene + " scene makes no sound of its own";
    }
    if (scene == "compass" || scene == "braille") return "the " + scene + " scene is felt, not heard: it makes no sound";
    if (r.controlUpdates > 0 && r.invalidRows == r.controlUpdates)
        return "no row of the motion file gave an orientation (the IMU samples never let fusion settle), so the scene never played";
    char range[200];
    std::snprintf(range, sizeof range, "the arm stayed within elevation %.1f..%.1f deg and azimuth %.1f..%.1f deg",
                  r.minElevation, r.maxElevation, r.minAzimuth, r.maxAzimuth);
    std::string why = "scene '" + scene + "' made no sound over this motion: " + range;
    if (scene == "cymbal") why += "; the cymbal sounds on a strike (a fast swing of the forearm)";
    else if (scene == "theremin" || scene == "panel" || scene == "sound-design") why += "; check the scene's range parameters (--param) against this motion";
    return why;
}

} // namespace armadillo::engine
