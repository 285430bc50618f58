#pragma once
// Outputs of a live session that may run for hours: rows and audio are handed over lock-free
// (fixed-size queue, no allocation on the control or audio path) and written by a writer thread
// straight into the file under its own name (core::openRecording: an existing file is kept aside
// as NAME.1 …, never half-replaced), so a session that dies leaves what it recorded
// (INTERFACES.md "Recordings"): CSV rows go to the file whole (one write of whole rows at a time,
// every 20 ms) and are synced to disk once a second; the WAV's header is rewritten once a second
// of audio. Memory stays bounded however long the session runs.
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
    /// Opens the file now (an existing one kept aside: keptAs()) and writes the header; throws
    /// IoError naming the path when it cannot.
    StreamingCsvWriter(std::string path, const std::vector<std::string>& header, int precision = 9);
    /// Without finish(): the rows queued so far are written and the file stays; a file that got
    /// no row at all is removed and the one kept aside put back.
    ~StreamingCsvWriter();
    StreamingCsvWriter(const StreamingCsvWriter&) = delete;
    StreamingCsvWriter& operator=(const StreamingCsvWriter&) = delete;

    bool push(const LogRow& row) noexcept;
    /// Drains, syncs and closes. Throws IoError naming the file on any failure (a failed write
    /// on the way included); the rows written stay in the file.
    void finish();
    /// Stops and removes the file (a session that played nothing); the file kept aside is put back.
    void discard() noexcept;
    std::uint64_t rowsWritten() const noexcept { return written_.load(); }
    std::uint64_t rowsDropped() const noexcept { return dropped_.load(); }
    const std::string& path() const noexcept { return path_; }
    /// Where a file already at path() was kept aside ("" when there was none).
    const std::string& keptAs() const noexcept { return keptAs_; }

private:
    void run();
    void drain();
    void writeAll(const std::string& text);
    std::string path_, keptAs_;
    int columns_;
    int precision_;
    int fd_ = -1;
    int errno_ = 0;   // the first failed write's reason
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
    /// Opens the file under its own name (core::WavWriteMode::Recording).
    StreamingWavWriter(std::string path, double sampleRate, bool float32);
    StreamingWavWriter(const StreamingWavWriter&) = delete;
    StreamingWavWriter& operator=(const StreamingWavWriter&) = delete;

    void write(const float* left, const float* right, int frames);
    void finish();
    void discard() noexcept { out_.discard(); }
    std::uint64_t frames() const noexcept { return out_.frames(); }
    const std::string& keptAs() const noexcept { return out_.keptAs(); }

private:
    core::WavStreamWriter out_;
    std::vector<float> interleaved_;
};

} // namespace armadillo::live
