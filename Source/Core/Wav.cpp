#include "Core/Wav.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace armadillo {
namespace {
void put16(std::string& s, std::uint16_t v) { s += char(v & 0xFF); s += char(v >> 8); }
void put32(std::string& s, std::uint32_t v) { for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xFF); }
std::uint32_t get32(const unsigned char* p) { return p[0] | (p[1] << 8) | (p[2] << 16) | (std::uint32_t(p[3]) << 24); }
std::uint16_t get16(const unsigned char* p) { return std::uint16_t(p[0] | (p[1] << 8)); }
} // namespace

void writeWav(const std::string& path, const AudioBuffer& audio, bool float32)
{
    const std::uint16_t channels = static_cast<std::uint16_t>(std::max<std::size_t>(1, audio.channels.size()));
    const std::size_t frames = audio.frames();
    const std::uint16_t bytesPerSample = float32 ? 4 : 2;
    const std::uint32_t dataBytes = static_cast<std::uint32_t>(frames * channels * bytesPerSample);
    const auto rate = static_cast<std::uint32_t>(std::lround(audio.sampleRate));
    std::string s;
    s.reserve(44 + dataBytes);
    s += "RIFF";
    put32(s, 36 + dataBytes);
    s += "WAVEfmt ";
    put32(s, 16);
    put16(s, float32 ? 3 : 1);
    put16(s, channels);
    put32(s, rate);
    put32(s, rate * channels * bytesPerSample);
    put16(s, static_cast<std::uint16_t>(channels * bytesPerSample));
    put16(s, static_cast<std::uint16_t>(bytesPerSample * 8));
    s += "data";
    put32(s, dataBytes);
    for (std::size_t i = 0; i < frames; ++i)
        for (std::size_t c = 0; c < channels; ++c) {
            const float x = c < audio.channels.size() ? audio.channels[c][i] : 0.0f;
            if (float32) {
                std::uint32_t bits;
                std::memcpy(&bits, &x, 4);
                put32(s, bits);
            } else {
                const float clipped = std::isfinite(x) ? std::clamp(x, -1.0f, 1.0f) : 0.0f;
                put16(s, static_cast<std::uint16_t>(static_cast<std::int16_t>(std::lround(clipped * 32767.0f))));
            }
        }
    writeFileAtomically(path, s);
}

AudioBuffer readWav(const std::string& path)
{
    const std::string bytes = readWholeFile(path);
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::size_t n = bytes.size();
    if (n < 12 || std::memcmp(p, "RIFF", 4) != 0 || std::memcmp(p + 8, "WAVE", 4) != 0)
        throw InputError(path, 0, "", "not a RIFF/WAVE file");
    std::uint16_t format = 0, channels = 0, bits = 0;
    std::uint32_t rate = 0;
    const unsigned char* data = nullptr;
    std::size_t dataLen = 0;
    for (std::size_t pos = 12; pos + 8 <= n;) {
        const std::uint32_t len = get32(p + pos + 4);
        const unsigned char* body = p + pos + 8;
        const std::size_t avail = n - (pos + 8);
        if (std::memcmp(p + pos, "fmt ", 4) == 0) {
            if (len < 16 || avail < 16) throw InputError(path, 0, "", "truncated fmt chunk");
            format = get16(body);
            channels = get16(body + 2);
            rate = get32(body + 4);
            bits = get16(body + 14);
            if (format == 0xFFFE && len >= 26) format = get16(body + 24);   // WAVE_FORMAT_EXTENSIBLE
        } else if (std::memcmp(p + pos, "data", 4) == 0) {
            data = body;
            dataLen = std::min<std::size_t>(len, avail);
        }
        pos += 8 + len + (len & 1);
    }
    if (!data || channels == 0 || rate == 0) throw InputError(path, 0, "", "missing fmt or data chunk");
    const bool pcm = format == 1 && (bits == 16 || bits == 24 || bits == 32);
    const bool flt = format == 3 && (bits == 32 || bits == 64);
    if (!pcm && !flt) throw InputError(path, 0, "", "unsupported sample format (PCM 16/24/32 or float 32/64 only)");
    const std::size_t bytesPer = bits / 8, frames = dataLen / (bytesPer * channels);
    AudioBuffer out;
    out.sampleRate = rate;
    out.channels.assign(channels, std::vector<float>(frames));
    for (std::size_t i = 0; i < frames; ++i)
        for (std::size_t c = 0; c < channels; ++c) {
            const unsigned char* s = data + (i * channels + c) * bytesPer;
            float v = 0.0f;
            if (flt && bits == 32) std::memcpy(&v, s, 4);
            else if (flt) { double d; std::memcpy(&d, s, 8); v = static_cast<float>(d); }
            else if (bits == 16) v = static_cast<std::int16_t>(get16(s)) / 32768.0f;
            else if (bits == 24) v = static_cast<float>(static_cast<std::int32_t>((s[0] << 8) | (s[1] << 16) | (std::uint32_t(s[2]) << 24)) / 2147483648.0);
            else v = static_cast<float>(static_cast<std::int32_t>(get32(s)) / 2147483648.0);
            out.channels[c][i] = std::isfinite(v) ? v : 0.0f;
        }
    return out;
}

} // namespace armadillo
