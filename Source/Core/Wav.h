#pragma once
// RIFF/WAVE files: the offline renderer's output and the instruments' user-supplied audio.
#include <string>
#include <vector>

namespace armadillo {

struct AudioBuffer {
    double sampleRate = 48000.0;                ///< Hz
    std::vector<std::vector<float>> channels;   ///< channels[c][i], nominally −1..1
    std::size_t frames() const noexcept { return channels.empty() ? 0 : channels[0].size(); }
};

/// 16-bit PCM (default, dithered-free rounding with clipping) or 32-bit float; atomic write.
void writeWav(const std::string& path, const AudioBuffer& audio, bool float32 = false);
/// Reads PCM 16/24/32-bit or float 32/64 WAV; throws InputError on anything else or truncation.
AudioBuffer readWav(const std::string& path);

} // namespace armadillo
