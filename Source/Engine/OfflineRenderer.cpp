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
    const double t0 = source.time(0);
    const double tail = std::max(0.0, settings.tailSeconds);
    const double maxSeconds = settings.audioSink ? settings.maxSeconds : std::min(settings.maxSeconds, kMaxCollectedRenderSeconds);
    checkRenderSpan(motion, source.size(), [&](std::size_t i) { return source.time(i); }, tail, maxSeconds);

    fusion::ArmTracker tracker;
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
    std::vector<core::MidiNoteEvent> midiBlock(settings.midiIn ? settings.midiIn->size() : 0);
    std::size_t nextMidi = 0;
    const int block = std::clamp(settings.blockSize, 1, 8192);
    std::vector<const float*> inputChannels(input ? input->channels.size() : 0, nullptr);
    std::vector<std::vector<float>> inputScratch(inputChannels.size(), std::vector<float>(static_cast<std::size_t>(block), 0.0f));

    RenderResult result;
    const bool twoArms = settings.leftMotion != nullptr;
    MotionRows leftSource;
    fusion::ArmTracker leftTracker;
    std::size_t leftRow = 0;
    core::ArmState leftArm;
    if (twoArms) {
        leftSource = MotionRows::load(*settings.leftMotion, settings.leftMount, "--mount-left");
        if (leftSource.size() == 0) throw core::InputError(settings.leftMotion->source(), 0, "--motion-left", "the left arm's motion file has no rows");
    }
    const double tEnd = source.time(source.size() - 1) + tail;
    const auto totalFrames = static_cast<std::size_t>(std::llround((tEnd - t0) * sampleRate)) + 1;
    result.audio.sampleRate = sampleRate;
    if (!settings.audioSink) result.audio.channels.assign(2, std::vector<float>(totalFrames, 0.0f));   // bounded by maxSeconds
    result.tactile.reserve(source.size() + 1);

    std::vector<float> left(static_cast<std::size_t>(block)), right(static_cast<std::size_t>(block));
    std::size_t frame = 0;
    const auto renderUntil = [&](double t) {
        const auto target = std::min(totalFrames, static_cast<std::size_t>(std::llround((t - t0) * sampleRate)));
        while (frame < target) {
            const int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(block), target - frame));
            if (settings.midiIn) {   // the block's MIDI notes, before its audio (Scene::processMidi)
                int count = 0;
                const auto& notes = *settings.midiIn;
                while (nextMidi < notes.size()) {
                    const auto at = static_cast<std::size_t>(std::max(0.0, std::round(notes[nextMidi].t * sampleRate)));
                    if (at >= frame + static_cast<std::size_t>(n)) break;
                    const TimedMidiNote& m = notes[nextMidi++];
                    core::MidiNoteEvent& e = midiBlock[static_cast<std::size_t>(count++)];
                    e.offset = at > frame ? static_cast<int>(at - frame) : 0;
                    e.note = static_cast<std::uint8_t>(std::clamp(m.note, 0, 127));
                    e.velocity = static_cast<std::uint8_t>(std::clamp(m.velocity, 0, 127));
                    e.channel = static_cast<std::uint8_t>(std::clamp(m.channel, 0, 15));
                }
                if (count > 0) engine.processMidi(midiBlock.data(), count);
            }
            if (input) {   // past the recording's end silence still comes in (the input stays connected)
                for (std::size_t c = 0; c < inputChannels.size(); ++c) {
                    if (frame + static_cast<std::size_t>(n) <= input->frames()) {
                        inputChannels[c] = input->channels[c].data() + frame;
                        continue;
                    }
                    auto& scratch = inputScratch[c];
                    for (int i = 0; i < n; ++i) {
                        const std::size_t at = frame + static_cast<std::size_t>(i);
                        scratch[static_cast<std::size_t>(i)] = at < input->frames() ? input->channels[c][at] : 0.0f;
                    }
                    inputChannels[c] = scratch.data();
                }
                engine.processInput(inputChannels.data(), static_cast<int>(inputChannels.size()), n);
            }
            std::fill(left.begin(), left.begin() + n, 0.0f);
            std::fill(right.begin(), right.begin() + n, 0.0f);
            engine.renderAudio(left.data(), right.data(), n);
            for (int i = 0; i < n; ++i)
                result.scenePeak = std::max({result.scenePeak, std::fabs(left[static_cast<std::size_t>(i)]), std::fabs(right[static_cast<std::size_t>(i)])});
            if (input && settings.mixAudioIn) {   // the recording as the listener hears it, under the scene's sound
                const float* first = inputChannels[0];
                const float* second = inputChannels[inputChannels.size() > 1 ? 1 : 0];
                for (int i = 0; i < n; ++i) {
                    left[static_cast<std::size_t>(i)] = std::clamp(left[static_cast<std::size_t>(i)] + first[i], -1.0f, 1.0f);
                    right[static_cast<std::size_t>(i)] = std::clamp(right[static_cast<std::size_t>(i)] + second[i], -1.0f, 1.0f);
                }
            }
            for (int i = 0; i < n; ++i)
                result.peak = std::max({result.peak, std::fabs(left[static_cast<std::size_t>(i)]), std::fabs(right[static_cast<std::size_t>(i)])});
            if (settings.audioSink) {
                settings.audioSink(left.data(), right.data(), n);
            } else {
                std::copy(left.begin(), left.begin() + n, result.audio.channels[0].begin() + static_cast<std::ptrdiff_t>(frame));
                std::copy(right.begin(), right.begin() + n, result.audio.channels[1].begin() + static_cast<std::ptrdiff_t>(frame));
            }
            frame += static_cast<std::size_t>(n);
        }
    };

    if (input) engine.processInput(inputChannels.data(), static_cast<int>(inputChannels.size()), 0);   // the recording itself, from sample 0
    double previous = t0;
    bool anyPose = false;
    for (std::size_t i = 0; i < source.size(); ++i) {
        const double t = source.time(i);
        renderUntil(t);
        engine.beforeRow(t - t0);
        const core::ArmState arm = source.apply(tracker, i);
        if (twoArms)   // the left arm's rows up to this time
            while (leftRow < leftSource.size() && leftSource.time(leftRow) <= t + 1e-9) leftArm = leftSource.apply(leftTracker, leftRow++);
        core::Transport transport;
        transport.valid = true;
        transport.playing = true;
        transport.seconds = t - t0;
        transport.bpm = settings.bpm;
        transport.ppq = transport.seconds * settings.bpm / 60.0;
        core::MotorLevels levels {};
        if (arm.valid) {
            levels = engine.control(arm, twoArms ? &leftArm : nullptr, transport, t - previous);
            const core::Pose& p = arm.features.pose;
            if (std::isfinite(p.elevationDeg) && std::isfinite(p.azimuthDeg)) {
                result.minElevation = anyPose ? std::min(result.minElevation, p.elevationDeg) : p.elevationDeg;
                result.maxElevation = anyPose ? std::max(result.maxElevation, p.elevationDeg) : p.elevationDeg;
                result.minAzimuth = anyPose ? std::min(result.minAzimuth, p.azimuthDeg) : p.azimuthDeg;
                result.maxAzimuth = anyPose ? std::max(result.maxAzimuth, p.azimuthDeg) : p.azimuthDeg;
                anyPose = true;
            }
        } else {
            engine.allOff();
            ++result.invalidRows;
        }
        if (Engine& sounding = engine.sounding(); sounding.failed())
            throw std::runtime_error("scene '" + sounding.config().scene + "' failed at t = " + std::to_string(t)
                                     + " s (motors off): " + sounding.failure());
        previous = t;
        result.tactile.push_back({t, levels});
        if (twoArms) {
            result.leftTactile.push_back({t, engine.leftLevels()});
            result.rightOrientation.push_back({t, arm.valid ? arm.q : Eigen::Quaterniond::Identity()});
            result.leftOrientation.push_back({t, leftArm.valid ? leftArm.q : Eigen::Quaterniond::Identity()});
        }
        ++result.controlUpdates;
        const std::size_t firstGesture = result.gestures.size();
        engine.popGestures(result.gestures);
        if (settings.onControl)
            settings.onControl(t, arm, twoArms ? &leftArm : nullptr, result.gestures.data() + firstGesture, result.gestures.size() - firstGesture,
                               engine.sounding());
    }
    renderUntil(tEnd + 1.0 / sampleRate);
    // The render ends as a session does: every motor off, in one last packet (the tactile file's
    // last row), at the end of the audio.
    engine.allOff();
    result.tactile.push_back({tEnd, core::MotorLevels {}});
    result.frames = frame;
    return result;
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
