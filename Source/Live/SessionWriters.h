#pragma once
// Outputs of a live session that may run for hours: rows and audio are handed over lock-free
// (fixed-size queue, no allocation on the control or audio path) and written by a writer thread
// to a temporary file, which is renamed over the target only when the session finishes — whole
// or nothing (INTERFACES.md), with memory bounded however long the session runs.
#include "Core/SpscQueue.h"
#include "Core/Wav.h"
#include <array>
#include <atomic>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace armadillo::live {

inline constexpr int kMaxLogColumns = 32;

struct LogRow {
    std::array<double, kMaxLogColumns> v {};
    int count = 0;
};

/// A CSV file written as the session goes. push() is wait-free; a full queue drops the row and
/// counts it (reported by finish()).
class StreamingCsvWriter {
public:
    /// Opens the temporary file now; throws IoError naming the path when it cannot.
    StreamingCsvWriter(std::string path, const std::vector<std::string>& header, int precision = 9);
    ~StreamingCsvWriter();   ///< without finish(): the temporary is removed, the target untouched
    StreamingCsvWriter(const StreamingCsvWriter&) = delete;
    StreamingCsvWriter& operator=(const StreamingCsvWriter&) = delete;

    bool push(const LogRow& row) noexcept;
    /// Drains, flushes, syncs and renames. Throws IoError on any failure (nothing is left behind).
    void finish();
    std::uint64_t rowsWritten() const noexcept { return written_.load(); }
    std::uint64_t rowsDropped() const noexcept { return dropped_.load(); }
    const std::string& path() const noexcept { return path_; }

private:
    void run();
    void drain();
    std::string path_, tmp_;
    int columns_;
    int precision_;
    std::FILE* file_ = nullptr;
    core::SpscQueue<LogRow, 4096> queue_;
    std::thread thread_;
    std::atomic<bool> stop_ {false};
    std::atomic<bool> failed_ {false};
    std::atomic<std::uint64_t> written_ {0}, dropped_ {0};
    std::string text_;
};

/// A stereo WAV written as audio is rendered (16-bit PCM or 32-bit float), through the core's
/// WavStreamWriter (libsndfile: RF64 above 4 GiB, plain WAV below). Not real-time itself: call
/// it from a writer thread, not an audio callback.
class StreamingWavWriter {
public:
    StreamingWavWriter(std::string path, double sampleRate, bool float32);
    StreamingWavWriter(const StreamingWavWriter&) = delete;
    StreamingWavWriter& operator=(const StreamingWavWriter&) = delete;

    void write(const float* left, const float* right, int frames);
    void finish();
    std::uint64_t frames() const noexcept { return out_.frames(); }

private:
    core::WavStreamWriter out_;
    std::vector<float> interleaved_;
};

} // namespace armadillo::live
