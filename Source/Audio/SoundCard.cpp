#include "Audio/SoundCard.h"
#include "Core/Errors.h"
#include "Core/ThreadPriority.h"
#include <alsa/asoundlib.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstring>
#include <mutex>
#include <vector>

namespace armadillo::audio {

namespace {
// ALSA prints its own diagnostics on stderr by default ("ALSA lib pcm.c:…: Unknown PCM default"
// on every machine without a card); the caller reports the failure once, in its own words.
void quietAlsa(const char*, int, const char*, int, const char*, ...) {}

std::string reason(const std::string& device, const std::string& what, int err)
{
    return "sound card '" + device + "': " + what + ": " + snd_strerror(err);
}
} // namespace

struct SoundCard::Pcm {
    snd_pcm_t* handle = nullptr;
    bool isFloat = true;
    ~Pcm()
    {
        if (handle) snd_pcm_close(handle);
    }
};

SoundCard::SoundCard(const std::string& device, double sampleRate, double latencySeconds)
    : SoundCard(device, sampleRate, latencySeconds, 2)
{
}

SoundCard::SoundCard(const std::string& device, double sampleRate, double latencySeconds, int channels)
    : pcm_(std::make_unique<Pcm>())
{
    static std::once_flag quiet;
    std::call_once(quiet, [] { snd_lib_error_set_handler(quietAlsa); });
    if (!(sampleRate >= 8000.0 && sampleRate <= 384000.0))
        throw core::IoError("sound card '" + device + "': unsupported sample rate " + std::to_string(sampleRate));
    // Non-blocking: the thread waits in snd_pcm_wait() with a timeout instead of inside a write,
    // so stop() is never stuck behind a stalled sound server.
    int err = snd_pcm_open(&pcm_->handle, device.c_str(), SND_PCM_STREAM_PLAYBACK, SND_PCM_NONBLOCK);
    if (err < 0) {
        pcm_->handle = nullptr;
        throw core::IoError(reason(device, "cannot open", err));
    }
    if (channels < 1 || channels > 32) throw core::IoError("sound card '" + device + "': 1..32 channels, not " + std::to_string(channels));
    {
        // A device that has fewer outputs than asked is named as such (ALSA's own reason, "Invalid
        // argument", says nothing); plug devices ("default", "plughw:") take any count.
        snd_pcm_hw_params_t* hw = nullptr;
        snd_pcm_hw_params_malloc(&hw);
        unsigned most = 0;
        const bool known = hw && snd_pcm_hw_params_any(pcm_->handle, hw) >= 0 && snd_pcm_hw_params_get_channels_max(hw, &most) >= 0;
        if (hw) snd_pcm_hw_params_free(hw);
        if (known && most < static_cast<unsigned>(channels))
            throw core::IoError("sound card '" + device + "': " + std::to_string(most) + " output channels, " + std::to_string(channels) + " needed");
    }
    const auto rate = static_cast<unsigned>(std::lround(sampleRate));
    const auto latencyUs = static_cast<unsigned>(std::clamp(latencySeconds, 0.002, 1.0) * 1e6);
    // Float first (no conversion on the way), 16-bit for cards opened directly ("hw:N") that
    // have no float format; soft resampling on, so a 44.1 kHz card still plays at our rate.
    err = snd_pcm_set_params(pcm_->handle, SND_PCM_FORMAT_FLOAT_LE, SND_PCM_ACCESS_RW_INTERLEAVED, static_cast<unsigned>(channels), rate, 1, latencyUs);
    if (err < 0) {
        pcm_->isFloat = false;
        err = snd_pcm_set_params(pcm_->handle, SND_PCM_FORMAT_S16_LE, SND_PCM_ACCESS_RW_INTERLEAVED, static_cast<unsigned>(channels), rate, 1, latencyUs);
    }
    if (err < 0) throw core::IoError(reason(device, "no " + std::to_string(channels) + "-channel float or 16-bit format at " + std::to_string(rate) + " Hz", err));
    snd_pcm_uframes_t buffer = 0, period = 0;
    err = snd_pcm_get_params(pcm_->handle, &buffer, &period);
    if (err < 0 || period == 0) throw core::IoError(reason(device, "cannot read buffer sizes", err < 0 ? err : -EINVAL));
    info_.device = device;
    info_.sampleRate = static_cast<double>(rate);
    info_.periodFrames = static_cast<int>(std::min<snd_pcm_uframes_t>(period, 8192));
    info_.bufferFrames = static_cast<int>(buffer);
    info_.format = pcm_->isFloat ? "FLOAT_LE" : "S16_LE";
    info_.channels = channels;
}

SoundCard::~SoundCard() { stop(); }

void SoundCard::start(Render render, int realtimePriority)
{
    if (running_.exchange(true)) return;
    if (thread_.joinable()) thread_.join();   // a thread that ended on its own (card gone)
    render_ = std::move(render);
    renderChannels_ = nullptr;
    failed_.store(false, std::memory_order_relaxed);
    thread_ = std::thread([this, realtimePriority] { loop(realtimePriority); });
}

void SoundCard::start(RenderChannels render, int realtimePriority)
{
    if (running_.exchange(true)) return;
    if (thread_.joinable()) thread_.join();
    renderChannels_ = std::move(render);
    render_ = nullptr;
    failed_.store(false, std::memory_order_relaxed);
    thread_ = std::thread([this, realtimePriority] { loop(realtimePriority); });
}

void SoundCard::stop()
{
    running_.store(false, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    if (pcm_ && pcm_->handle) snd_pcm_drop(pcm_->handle);
}

std::string SoundCard::lastError() const
{
    return failed_.load(std::memory_order_acquire) ? error_ : std::string();
}

void SoundCard::loop(int realtimePriority)
{
    if (realtimePriority > 0) core::requestRealtimePriority(realtimePriority);
    const int n = info_.periodFrames;
    const int channels = info_.channels;
    const auto nc = static_cast<std::size_t>(channels);
    // Everything the loop touches is allocated here, before the first period.
    std::vector<std::vector<float>> buffers(nc, std::vector<float>(static_cast<std::size_t>(n)));
    std::vector<float*> pointers(nc);
    for (std::size_t c = 0; c < nc; ++c) pointers[c] = buffers[c].data();
    std::vector<float> interleavedF(pcm_->isFloat ? nc * static_cast<std::size_t>(n) : 0);
    std::vector<std::int16_t> interleavedS(pcm_->isFloat ? 0 : nc * static_cast<std::size_t>(n));
    const double bufferSeconds = info_.bufferFrames / info_.sampleRate;
    // Pacing reference: re-anchored whenever the device makes the loop wait (a real card, whose
    // clock is the one that counts, even when it runs a little fast against the system's).
    auto anchor = std::chrono::steady_clock::now();
    std::uint64_t anchorFrames = 0, written = 0;
    snd_pcm_prepare(pcm_->handle);

    while (running_.load(std::memory_order_acquire)) {
        for (auto& b : buffers) std::fill(b.begin(), b.end(), 0.0f);
        snd_pcm_sframes_t delay = 0;
        queued_.store(snd_pcm_delay(pcm_->handle, &delay) == 0 && delay > 0 ? static_cast<int>(delay) : 0, std::memory_order_relaxed);
        if (renderChannels_) renderChannels_(pointers.data(), channels, n);
        else render_(pointers[0], pointers[std::min<std::size_t>(1, nc - 1)], n);
        const void* data;
        if (pcm_->isFloat) {
            for (int i = 0; i < n; ++i)
                for (std::size_t c = 0; c < nc; ++c) {
                    const float x = buffers[c][static_cast<std::size_t>(i)];
                    interleavedF[nc * static_cast<std::size_t>(i) + c] = std::isfinite(x) ? x : 0.0f;
                }
            data = interleavedF.data();
        } else {
            const auto toS16 = [](float x) {
                const float c = std::isfinite(x) ? std::clamp(x, -1.0f, 1.0f) : 0.0f;
                return static_cast<std::int16_t>(std::lround(c * 32767.0f));
            };
            for (int i = 0; i < n; ++i)
                for (std::size_t c = 0; c < nc; ++c) interleavedS[nc * static_cast<std::size_t>(i) + c] = toS16(buffers[c][static_cast<std::size_t>(i)]);
            data = interleavedS.data();
        }
        const std::size_t frameBytes = pcm_->isFloat ? nc * sizeof(float) : nc * sizeof(std::int16_t);
        int done = 0;
        bool waited = false;
        while (done < n && running_.load(std::memory_order_acquire)) {
            const auto* p = static_cast<const char*>(data) + static_cast<std::size_t>(done) * frameBytes;
            snd_pcm_sframes_t w = snd_pcm_writei(pcm_->handle, p, static_cast<snd_pcm_uframes_t>(n - done));
            if (w == -EAGAIN) {   // buffer full: wait for room (at most 100 ms, then look at running_)
                waited = true;
                const int r = snd_pcm_wait(pcm_->handle, 100);
                if (r >= 0) continue;
                w = r;   // an xrun or a vanished device reported by the wait
            }
            if (w < 0) {
                if (w == -EPIPE) underruns_.fetch_add(1, std::memory_order_relaxed);
                const int r = snd_pcm_recover(pcm_->handle, static_cast<int>(w), 1);
                if (r < 0) {
                    error_ = reason(info_.device, "playback stopped", r);
                    failed_.store(true, std::memory_order_release);
                    running_.store(false, std::memory_order_release);
                    return;
                }
                continue;
            }
            done += static_cast<int>(w);
        }
        written += static_cast<std::uint64_t>(done);
        frames_.fetch_add(static_cast<std::uint64_t>(done), std::memory_order_relaxed);
        // A card makes the loop wait once its buffer is full; a device that never does (ALSA's
        // null/file plugins) is held to at most one buffer ahead of the wall clock instead.
        const auto now = std::chrono::steady_clock::now();
        if (waited) {
            anchor = now;
            anchorFrames = written;
            continue;
        }
        const double elapsed = std::chrono::duration<double>(now - anchor).count();
        const double ahead = static_cast<double>(written - anchorFrames) / info_.sampleRate - elapsed - bufferSeconds;
        if (ahead > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
    }
}

} // namespace armadillo::audio
