#include "Live/Outputs/TactorOutput.h"
#include "Audio/JackOutput.h"
#include "Audio/SoundCard.h"
#include "Core/Clock.h"
#include "Core/Errors.h"
#include <cstdio>

namespace armadillo::live {

TactorOutput::TactorOutput(const TactorOutputConfig& config) : config_(config)
{
    if (config_.device.empty()) throw core::IoError("--tactors: no device given (an ALSA PCM such as hw:1, or jack)");
    const int n = config_.map.channels;
    // The renderer's settings first (InputError), so a bad gain file opens no device.
    tactors::validate(config_.params, config_.device == "jack" ? 48000.0 : config_.sampleRate, "--tactor-model");
    if (config_.gains.count > n)
        throw core::InputError(config_.gains.source, 0, "gain",
                         "the file gives " + std::to_string(config_.gains.count) + " gains but the map has " + std::to_string(n) + " channels");
    if (config_.device == "jack") {
        jack_ = std::make_unique<audio::JackOutput>(config_.clientName, n);   // IoError: no server
        sampleRate_ = jack_->sampleRate();
        periodFrames_ = jack_->bufferFrames();
        if (!config_.connect.empty()) jack_->inputPorts(config_.connect);    // IoError now, before anything runs
    } else {
        try {
            card_ = std::make_unique<audio::SoundCard>(config_.device, config_.sampleRate, config_.latencySeconds, n);
        } catch (const core::IoError& e) {
            throw core::IoError(std::string("tactor output: ") + e.what()); // "sound card 'hw:1': 8 output channels, 9 needed"
        }
        sampleRate_ = card_->info().sampleRate;
        periodFrames_ = card_->info().periodFrames;
    }
    renderer_.prepare(config_.params, config_.map, config_.gains, sampleRate_);   // InputError (a carrier above Nyquist)
}

TactorOutput::~TactorOutput()
{
    try {
        stop();
    } catch (...) {
    }
}

void TactorOutput::push(double t, const core::MotorLevels& levels) noexcept
{
    Record r;
    r.t = t;
    r.pushed = core::monotonicSeconds();
    r.levels = levels;
    if (!queue_.push(r)) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void TactorOutput::renderPeriod(float* const* out, int n, double outputDelaySeconds) noexcept
{
    const double now = core::monotonicSeconds();
    Record r;
    bool any = false;
    while (queue_.pop(r)) {
        // dt: the control step's own (source time), as the engine's safety stage saw it, so the
        // guard makes the same decisions (docs/TACTORS.md).
        const double dt = lastT_ < 0.0 || r.t < lastT_ ? 0.0 : r.t - lastT_;
        renderer_.setLevels(r.levels, dt);
        lastT_ = r.t;
        lastPushed_ = r.pushed;
        any = true;
        muted_ = false;
        latency_.push(TactorLatency {now - r.pushed, now - r.pushed + outputDelaySeconds});
    }
    if (!any && !muted_ && lastPushed_ >= 0.0 && now - lastPushed_ > kStaleSeconds) {
        renderer_.mute();   // a stalled source: silence until it speaks again
        muted_ = true;
    }
    if (renderer_.usesSound()) {
        // The scene's sound for this period (what is there of it; the renderer pads silence).
        while (sound_.size() > kSoundBacklog + static_cast<std::size_t>(n)) {
            float drop;
            sound_.pop(drop);   // the sound's clock ran ahead: its oldest samples go
        }
        for (int done = 0; done < n;) {
            const int len = std::min(n - done, static_cast<int>(soundScratch_.size()));
            int got = 0;
            while (got < len && sound_.pop(soundScratch_[static_cast<std::size_t>(got)])) ++got;
            std::array<float*, tactors::kMaxChannels> part {};
            for (int c = 0; c < renderer_.channels(); ++c) part[static_cast<std::size_t>(c)] = out[c] + done;
            renderer_.setSound(soundScratch_.data(), got);
            renderer_.render(part.data(), len);
            done += len;
        }
    } else {
        renderer_.render(out, n);
    }
    frames_.fetch_add(static_cast<std::uint64_t>(n), std::memory_order_relaxed);
    limited_.store(renderer_.limited(), std::memory_order_relaxed);
}

void TactorOutput::pushSound(const float* left, const float* right, int n) noexcept
{
    for (int i = 0; i < n; ++i)
        if (!sound_.push(0.5f * (left[i] + right[i]))) return;   // full: the output is not taking it (stopped)
}

void TactorOutput::start()
{
    if (started_) return;
    started_ = true;
    if (jack_) {
        jack_->start([this](float* const* out, int channels, int n) {
            (void)channels;
            // A period rendered now leaves after JACK's playback latency (connected to hardware),
            // else after one period (the next cycle).
            const int latency = jack_->playbackLatencyFrames();
            renderPeriod(out, n, static_cast<double>(latency > 0 ? latency : periodFrames_) / sampleRate_);
        });
        if (!config_.connect.empty()) {
            try {
                jack_->connect(config_.connect);
            } catch (...) {
                jack_->stop();
                throw;
            }
        }
    } else {
        card_->start([this](float* const* out, int channels, int n) {
            (void)channels;
            renderPeriod(out, n, static_cast<double>(card_->queuedFrames()) / sampleRate_);
        }, config_.realtimePriority);
    }
}

void TactorOutput::stop()
{
    if (card_) card_->stop();   // joins the audio thread; what is queued in the card is dropped
    if (jack_) jack_->stop();
    started_ = false;
}

bool TactorOutput::failed() const noexcept { return (card_ && card_->failed()) || (jack_ && jack_->failed()); }

std::string TactorOutput::describe() const
{
    char buf[256];
    const std::string map = tactors::channelMapText(config_.map);
    if (jack_) {
        std::snprintf(buf, sizeof buf, "JACK client '%s': ports tactor_1..tactor_%d (motors %s), %.0f Hz, %d frames a period, model %s",
                      jack_->clientName().c_str(), channels(), map.c_str(), sampleRate_, periodFrames_, tactors::modelName(config_.params.model));
    } else {
        std::snprintf(buf, sizeof buf, "ALSA '%s': %d channel%s (motors %s), %.0f Hz %s, %d frames a period, model %s", config_.device.c_str(), channels(),
                      channels() == 1 ? "" : "s", map.c_str(), sampleRate_, card_->info().format.c_str(), periodFrames_,
                      tactors::modelName(config_.params.model));
    }
    return buf;
}

} // namespace armadillo::live
