#pragma once
// Audio files through libsndfile: the offline renderer's and `play --out`'s WAV files, and the
// instruments' user-supplied audio (any format libsndfile reads: WAV, AIFF, FLAC, Ogg, 8–32-bit
// PCM, float). Written WAVs start as RF64 and are downgraded to a plain RIFF/WAVE on close when
// they stay under 4 GiB, so a six-hour recording is still one valid file; float WAVs carry the
// `fact` chunk. Every file is written under a temporary name and renamed in when complete,
// except a live recording (WavWriteMode::Recording), which is readable under its own name while
// it grows.
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::core {

struct AudioBuffer {
    double sampleRate = 48000.0;                ///< Hz
    std::vector<std::vector<float>> channels;   ///< channels[c][i], nominally −1..1
    std::size_t frames() const noexcept { return channels.empty() ? 0 : channels[0].size(); }
};

/// 16-bit PCM (rounded, clipped to ±1) or 32-bit float; written whole or not at all.
/// Non-finite samples are written as 0. IoError when it cannot be written.
void writeWav(const std::string& path, const AudioBuffer& audio, bool float32 = false);
/// Reads any audio file libsndfile knows (despite the name: WAV, AIFF, FLAC, Ogg...). IoError
/// when it cannot be opened for reading, InputError naming the file when it is not audio.
AudioBuffer readWav(const std::string& path);
/// Stems (audio-touch, docs/INSTRUMENTS.md "Stems felt apart"): each file read with readWav and
/// mixed down to one mono channel (the mean of its channels), in the given order; shorter ones
/// padded with silence to the longest. InputError naming the file when the sample rates differ
/// or a file holds no audio.
AudioBuffer readWavStems(const std::vector<std::string>& paths);

/// The sample rates the engine runs at, in Hz.
constexpr double kMinEngineSampleRate = 8000.0;
constexpr double kMaxEngineSampleRate = 384000.0;
/// `rate` (Hz) when the engine can run at it; otherwise an InputError naming `source`: the file
/// whose rate the engine was to take (a recording), or the option that set it.
double engineSampleRate(double rate, const std::string& source);

/// How a WavStreamWriter puts its file in place.
enum class WavWriteMode {
    /// A temporary file renamed over the target by finish(); destroyed without finish(), it
    /// leaves nothing behind (the renderer's one-shot files).
    Atomic,
    /// A live session's recording (core::openRecording): written under its own name, an existing
    /// file kept aside as NAME.1 …; the header's sizes are rewritten and the data synced to disk
    /// once a second of audio, so a crash or a power cut leaves a valid WAV of all but the last
    /// second. Destroyed without finish(), it keeps what was written (or, with no audio at all,
    /// is removed and the file kept aside put back).
    Recording,
};

/// A WAV written as audio arrives. Not real-time itself: call it from a writer thread, not an
/// audio callback. Samples go to a temporary file; finish() closes it and renames it in place
/// (WavWriteMode::Atomic), or to the file itself (WavWriteMode::Recording).
class WavStreamWriter {
public:
    WavStreamWriter(std::string path, double sampleRate, int channels, bool float32,
                    WavWriteMode mode = WavWriteMode::Atomic);   ///< IoError
    ~WavStreamWriter();
    WavStreamWriter(const WavStreamWriter&) = delete;
    WavStreamWriter& operator=(const WavStreamWriter&) = delete;

    /// `frames` interleaved frames; false (and finish() throws) once a write failed.
    bool write(const float* interleaved, std::size_t frames);
    /// Closes and renames; IoError naming the path if anything failed on the way.
    void finish();
    /// Closes and removes what was written (a recording: the file kept aside is put back).
    void discard() noexcept;
    std::uint64_t frames() const noexcept { return frames_; }
    /// Recording: where a file already at the path was kept aside ("" when there was none).
    const std::string& keptAs() const noexcept { return keptAs_; }

private:
    std::string path_, tmp_, keptAs_;
    int channels_;
    int fd_ = -1;                     // the descriptor libsndfile writes (it closes it)
    std::uint64_t headerEvery_ = 0;   // Recording: frames between header rewrites (one second)
    std::uint64_t headerAt_ = 0;      // Recording: frames_ at which the header is rewritten next
    void* file_ = nullptr;   // SNDFILE*
    std::uint64_t frames_ = 0;
    bool failed_ = false;
    std::string error_;
    std::vector<float> clean_;
};

} // namespace armadillo::core
