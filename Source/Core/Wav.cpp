// Audio files through libsndfile (Core/Wav.h). What this file adds: atomic writes (temporary
// name, fsync, rename), RF64 with downgrade for long recordings, and errors that name the file.
#include "Core/Wav.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <sndfile.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace armadillo::core {

namespace {

std::string temporaryNameFor(const std::string& path)
{
    return path + ".tmp-" + std::to_string(::getpid()) + "-" +
           std::to_string(std::chrono::steady_clock::now().time_since_epoch().count() % 1000000007);
}

SNDFILE* handle(void* p) { return static_cast<SNDFILE*>(p); }

} // namespace

WavStreamWriter::WavStreamWriter(std::string path, double sampleRate, int channels, bool float32, WavWriteMode mode)
    : path_(std::move(path)),
      // A device or a pipe (/dev/null) is written as it is: a temporary renamed over it would
      // replace the device itself.
      tmp_(mode == WavWriteMode::Atomic && !isDeviceOrPipe(path_) ? temporaryNameFor(path_) : std::string()),
      channels_(std::max(1, channels))
{
    int fd = -1;
    if (mode == WavWriteMode::Atomic && tmp_.empty()) {
        fd = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd < 0) throw IoError("cannot write " + path_ + ": " + std::strerror(errno));
    } else if (mode == WavWriteMode::Recording) {
        fd = openRecording(path_, keptAs_);   // IoError naming the path
        headerEvery_ = static_cast<std::uint64_t>(std::max(1.0, std::round(sampleRate)));
        headerAt_ = headerEvery_;
    } else {
        fd = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd < 0) throw IoError("cannot write " + path_ + ": " + std::strerror(errno));
    }
    SF_INFO info {};
    info.samplerate = static_cast<int>(std::lround(sampleRate));
    info.channels = channels_;
    // RF64 while writing; on close libsndfile writes a plain RIFF/WAVE header instead when the
    // data stayed below 4 GiB (SFC_RF64_AUTO_DOWNGRADE), so short files are ordinary WAVs.
    info.format = SF_FORMAT_RF64 | (float32 ? SF_FORMAT_FLOAT : SF_FORMAT_PCM_16);
    SNDFILE* f = sf_open_fd(fd, SFM_WRITE, &info, SF_TRUE);
    if (f == nullptr) {
        const std::string why = sf_strerror(nullptr);
        ::close(fd);
        if (tmp_.empty()) abandonRecording(path_, keptAs_);
        else std::remove(tmp_.c_str());
        throw IoError("cannot write " + path_ + ": " + why);
    }
    fd_ = fd;
    sf_command(f, SFC_RF64_AUTO_DOWNGRADE, nullptr, SF_TRUE);
    sf_command(f, SFC_SET_ADD_PEAK_CHUNK, nullptr, SF_FALSE);   // plain files: fmt, fact (float), data
    sf_command(f, SFC_SET_CLIPPING, nullptr, SF_TRUE);          // 16-bit: clip instead of wrapping
    file_ = f;
}

WavStreamWriter::~WavStreamWriter()
{
    if (file_ == nullptr) return;
    sf_close(handle(file_));   // a recording's header holds every frame written
    if (!tmp_.empty()) std::remove(tmp_.c_str());
    else if (frames_ == 0) abandonRecording(path_, keptAs_);
}

bool WavStreamWriter::write(const float* interleaved, std::size_t frames)
{
    if (file_ == nullptr || failed_) return false;
    const std::size_t samples = frames * static_cast<std::size_t>(channels_);
    clean_.resize(samples);
    for (std::size_t i = 0; i < samples; ++i) clean_[i] = std::isfinite(interleaved[i]) ? interleaved[i] : 0.0f;
    const auto written = sf_writef_float(handle(file_), clean_.data(), static_cast<sf_count_t>(frames));
    if (written != static_cast<sf_count_t>(frames)) {
        failed_ = true;
        error_ = sf_strerror(handle(file_));
        return false;
    }
    frames_ += frames;
    if (headerEvery_ > 0 && frames_ >= headerAt_) {
        // A recording: the RIFF and data sizes as they are now, and the data on the disk, so a
        // crash leaves a file that reads to within a second of it.
        headerAt_ = frames_ + headerEvery_;
        sf_command(handle(file_), SFC_UPDATE_HEADER_NOW, nullptr, 0);
        ::fdatasync(fd_);
    }
    return true;
}

void WavStreamWriter::finish()
{
    if (file_ == nullptr) return;
    sf_write_sync(handle(file_));
    const int closed = sf_close(handle(file_));
    file_ = nullptr;
    if (failed_ || closed != 0 || (!tmp_.empty() && std::rename(tmp_.c_str(), path_.c_str()) != 0)) {
        const std::string why = failed_ ? error_ : closed != 0 ? sf_error_number(closed) : std::strerror(errno);
        if (!tmp_.empty()) std::remove(tmp_.c_str());   // (a recording keeps what it holds)
        throw IoError("cannot write " + path_ + ": " + why);
    }
}

void WavStreamWriter::discard() noexcept
{
    if (file_ == nullptr) return;
    sf_close(handle(file_));
    file_ = nullptr;
    if (!tmp_.empty()) std::remove(tmp_.c_str());
    else abandonRecording(path_, keptAs_);
}

void writeWav(const std::string& path, const AudioBuffer& audio, bool float32)
{
    const int channels = static_cast<int>(std::max<std::size_t>(1, audio.channels.size()));
    WavStreamWriter out(path, audio.sampleRate, channels, float32);
    constexpr std::size_t kChunk = 4096;
    std::vector<float> interleaved(kChunk * static_cast<std::size_t>(channels));
    const std::size_t frames = audio.frames();
    for (std::size_t start = 0; start < frames; start += kChunk) {
        const std::size_t n = std::min(kChunk, frames - start);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t c = 0; c < static_cast<std::size_t>(channels); ++c) {
                const bool present = c < audio.channels.size() && start + i < audio.channels[c].size();
                interleaved[i * static_cast<std::size_t>(channels) + c] = present ? audio.channels[c][start + i] : 0.0f;
            }
        out.write(interleaved.data(), n);
    }
    out.finish();
}

AudioBuffer readWavStems(const std::vector<std::string>& paths)
{
    AudioBuffer out;
    for (const std::string& path : paths) {
        const AudioBuffer stem = readWav(path);
        if (stem.channels.empty() || stem.frames() == 0) throw InputError(path, 0, "", "the stem holds no audio");
        if (out.channels.empty()) out.sampleRate = stem.sampleRate;
        else if (stem.sampleRate != out.sampleRate)
            throw InputError(path, 0, "", "the stems must share one sample rate (" + std::to_string(static_cast<long>(stem.sampleRate)) + " Hz here, " +
                                              std::to_string(static_cast<long>(out.sampleRate)) + " Hz in " + paths.front() + ")");
        std::vector<float> mono(stem.frames(), 0.0f);
        for (const auto& c : stem.channels)
            for (std::size_t i = 0; i < mono.size(); ++i) mono[i] += c[i] / static_cast<float>(stem.channels.size());
        out.channels.push_back(std::move(mono));
    }
    std::size_t longest = 0;
    for (const auto& c : out.channels) longest = std::max(longest, c.size());
    for (auto& c : out.channels) c.resize(longest, 0.0f);
    return out;
}

double engineSampleRate(double rate, const std::string& source)
{
    if (rate >= kMinEngineSampleRate && rate <= kMaxEngineSampleRate) return rate;
    char what[160];
    std::snprintf(what, sizeof what, "sample rate %.6g Hz: the engine runs at 8000..384000 Hz (resample the file, or give --sample-rate)", rate);
    throw InputError(source.empty() ? std::string("--sample-rate") : source, 0, "", what);
}

AudioBuffer readWav(const std::string& path)
{
    if (::access(path.c_str(), R_OK) != 0) throw IoError("cannot read " + path + ": " + std::strerror(errno));
    SF_INFO info {};
    SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
    if (f == nullptr) throw InputError(path, 0, "", std::string("not an audio file libsndfile can read (") + sf_strerror(nullptr) + ")");
    struct Closer {
        SNDFILE* f;
        ~Closer() { sf_close(f); }
    } closer {f};
    // About 3 hours of 8 channels at 96 kHz: more is surely a broken header, not a cymbal sample.
    constexpr sf_count_t kMaxSamples = sf_count_t(1) << 32;
    if (info.channels < 1 || info.samplerate < 1 || info.frames < 0 || info.frames > kMaxSamples / info.channels)
        throw InputError(path, 0, "", "implausible audio header (channels, rate or length)");
    AudioBuffer out;
    out.sampleRate = info.samplerate;
    const auto channels = static_cast<std::size_t>(info.channels);
    out.channels.assign(channels, {});
    for (auto& ch : out.channels) ch.reserve(static_cast<std::size_t>(info.frames));
    constexpr sf_count_t kChunk = 4096;
    std::vector<float> buffer(static_cast<std::size_t>(kChunk) * channels);
    for (sf_count_t got; (got = sf_readf_float(f, buffer.data(), kChunk)) > 0;)
        for (sf_count_t i = 0; i < got; ++i)
            for (std::size_t c = 0; c < channels; ++c) {
                const float v = buffer[static_cast<std::size_t>(i) * channels + c];
                out.channels[c].push_back(std::isfinite(v) ? v : 0.0f);
            }
    if (sf_error(f) != SF_ERR_NO_ERROR) throw InputError(path, 0, "", std::string("cannot decode: ") + sf_strerror(f));
    return out;
}

} // namespace armadillo::core
