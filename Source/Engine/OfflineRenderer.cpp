#include "Engine/OfflineRenderer.h"
#include <stdexcept>
#include "Core/Errors.h"
#include "Engine/ArmTracker.h"
#include <algorithm>
#include <cmath>

namespace armadillo {

namespace {
/// The motion file as a list of per-row arm updates, whatever its kind.
struct MotionSource {
    MotionKind kind = MotionKind::Unknown;
    std::vector<ImuSample> imu;
    std::vector<TimedQuaternion> orientations;
    std::size_t size() const { return kind == MotionKind::Imu ? imu.size() : orientations.size(); }
    double time(std::size_t i) const { return kind == MotionKind::Imu ? imu[i].t : orientations[i].t; }
    ArmState apply(ArmTracker& tracker, std::size_t i) const
    {
        return kind == MotionKind::Imu ? tracker.update(imu[i]) : tracker.updateOrientation(orientations[i].t, orientations[i].q);
    }
};

MotionSource loadMotion(const CsvTable& table)
{
    MotionSource m;
    m.kind = detectMotionKind(table);
    if (m.kind == MotionKind::Imu) m.imu = readImu(table);
    else m.orientations = motionAsQuaternions(table);   // throws for unknown headers
    return m;
}
} // namespace

RenderResult renderOffline(const CsvTable& motion, const RenderSettings& settings)
{
    const MotionSource source = loadMotion(motion);
    Engine engine(settings.engine);
    ArmTracker tracker;
    const double sampleRate = settings.engine.sceneConfig.sampleRate;
    if (!(sampleRate >= 8000.0 && sampleRate <= 384000.0))
        throw InputError("", 0, "", "sample rate must lie in 8000..384000 Hz");

    const AudioBuffer* input = settings.audioIn;
    if (input) {
        if (!engine.listensToAudio())
            throw InputError("", 0, "--audio-in", "scene '" + settings.engine.scene + "' does not listen to audio (score and audio-touch do)");
        if (input->channels.empty() || input->frames() == 0) throw InputError("", 0, "--audio-in", "the recording holds no audio");
        if (std::fabs(input->sampleRate - sampleRate) > 0.5)
            throw InputError("", 0, "--audio-in", "the recording's sample rate (" + std::to_string(static_cast<long>(input->sampleRate)) +
                                                      " Hz) differs from the engine's (" + std::to_string(static_cast<long>(sampleRate)) +
                                                      " Hz); give --sample-rate to match it");
    }
    std::vector<const float*> inputChannels(input ? input->channels.size() : 0, nullptr);
    std::vector<std::vector<float>> inputScratch(inputChannels.size(), std::vector<float>(static_cast<std::size_t>(std::clamp(settings.blockSize, 1, 8192)), 0.0f));

    RenderResult result;
    const double t0 = source.time(0);
    const double tEnd = source.time(source.size() - 1) + std::max(0.0, settings.tailSeconds);
    const auto totalFrames = static_cast<std::size_t>(std::llround((tEnd - t0) * sampleRate)) + 1;
    result.audio.sampleRate = sampleRate;
    result.audio.channels.assign(2, std::vector<float>(totalFrames, 0.0f));
    result.tactile.reserve(source.size());

    const int block = std::clamp(settings.blockSize, 1, 8192);
    std::size_t frame = 0;
    const auto renderUntil = [&](double t) {
        const auto target = std::min(totalFrames, static_cast<std::size_t>(std::llround((t - t0) * sampleRate)));
        while (frame < target) {
            const int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(block), target - frame));
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
            engine.renderAudio(result.audio.channels[0].data() + frame, result.audio.channels[1].data() + frame, n);
            frame += static_cast<std::size_t>(n);
        }
    };

    if (input) engine.processInput(inputChannels.data(), static_cast<int>(inputChannels.size()), 0);   // the recording itself, from sample 0
    double previous = t0;
    for (std::size_t i = 0; i < source.size(); ++i) {
        const double t = source.time(i);
        renderUntil(t);
        const ArmState arm = source.apply(tracker, i);
        Transport transport;
        transport.valid = true;
        transport.playing = true;
        transport.seconds = t - t0;
        transport.bpm = settings.bpm;
        transport.ppq = transport.seconds * settings.bpm / 60.0;
        MotorLevels levels {};
        if (arm.valid) {
            levels = engine.control(arm, transport, t - previous);
        } else {
            engine.allOff();
            ++result.invalidRows;
        }
        if (engine.failed())
            throw std::runtime_error("scene '" + engine.config().scene + "' failed at t = " + std::to_string(t)
                                     + " s (motors off): " + engine.failure());
        previous = t;
        result.tactile.push_back({t, levels});
        ++result.controlUpdates;
        const std::size_t firstGesture = result.gestures.size();
        GestureEvent g;
        while (engine.popGesture(g)) result.gestures.push_back(g);
        if (settings.onControl)
            settings.onControl(t, arm, result.gestures.data() + firstGesture, result.gestures.size() - firstGesture, engine);
    }
    renderUntil(tEnd + 1.0 / sampleRate);
    return result;
}

} // namespace armadillo
