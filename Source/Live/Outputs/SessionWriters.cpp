#include "Live/Outputs/SessionWriters.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unistd.h>

namespace armadillo::live {

// --- CSV ---------------------------------------------------------------------------------------

StreamingCsvWriter::StreamingCsvWriter(std::string path, const std::vector<std::string>& header, int precision)
    : path_(std::move(path)), columns_(static_cast<int>(header.size())), precision_(precision)
{
    if (columns_ < 1 || columns_ > kMaxLogColumns) throw core::IoError("CSV writer for " + path_ + ": bad column count");
    fd_ = core::openRecording(path_, keptAs_);   // IoError naming the path
    std::string h;
    for (std::size_t i = 0; i < header.size(); ++i) h += (i ? "," : "") + header[i];
    h += '\n';
    writeAll(h);
    thread_ = std::thread([this] { run(); });
}

StreamingCsvWriter::~StreamingCsvWriter()
{
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();   // (the rows queued so far are written)
    if (fd_ >= 0) {
        ::close(fd_);
        if (written_.load() == 0) core::abandonRecording(path_, keptAs_);
    }
}

bool StreamingCsvWriter::push(const LogRow& row) noexcept
{
    if (queue_.push(row)) return true;
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
}

void StreamingCsvWriter::writeAll(const std::string& text)
{
    // Whole rows in one write(): a file on disk never ends inside a row unless the disk is full.
    const char* p = text.data();
    std::size_t left = text.size();
    while (left > 0 && !failed_.load(std::memory_order_relaxed)) {
        const ssize_t n = ::write(fd_, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            errno_ = n < 0 ? errno : ENOSPC;
            failed_.store(true);
            return;
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
}

void StreamingCsvWriter::drain()
{
    LogRow row;
    text_.clear();
    std::uint64_t rows = 0;
    while (queue_.pop(row)) {
        for (int i = 0; i < columns_; ++i) {
            if (i) text_ += ',';
            core::appendNumber(text_, i < row.count ? row.v[static_cast<std::size_t>(i)] : core::kNaN, precision_);
        }
        text_ += '\n';
        ++rows;
        if (text_.size() > 1 << 16) break;
    }
    if (!text_.empty()) writeAll(text_);
    written_.fetch_add(rows, std::memory_order_relaxed);
}

void StreamingCsvWriter::run()
{
    auto syncedAt = std::chrono::steady_clock::now();
    while (!stop_.load(std::memory_order_acquire)) {
        drain();
        // Once a second the rows reach the disk itself (a power cut, a pulled battery).
        if (const auto now = std::chrono::steady_clock::now(); now - syncedAt >= std::chrono::seconds(1)) {
            ::fdatasync(fd_);
            syncedAt = now;
        }
        if (queue_.size() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    while (queue_.size() > 0) drain();
}

void StreamingCsvWriter::finish()
{
    if (fd_ < 0) return;
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    bool ok = !failed_.load();
    int e = errno_;
    if (ok && ::fsync(fd_) != 0) {
        ok = false;
        e = errno;
    }
    if (::close(fd_) != 0 && ok) {
        ok = false;
        e = errno;
    }
    fd_ = -1;
    if (!ok) throw core::IoError("cannot write " + path_ + ": " + std::strerror(e ? e : EIO));
}

void StreamingCsvWriter::discard() noexcept
{
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    if (fd_ < 0) return;
    ::close(fd_);
    fd_ = -1;
    core::abandonRecording(path_, keptAs_);
}

// --- WAV ---------------------------------------------------------------------------------------

StreamingWavWriter::StreamingWavWriter(std::string path, double sampleRate, bool float32)
    : out_(std::move(path), sampleRate, 2, float32, core::WavWriteMode::Recording)
{
}

void StreamingWavWriter::write(const float* left, const float* right, int frames)
{
    if (frames <= 0) return;
    interleaved_.resize(static_cast<std::size_t>(frames) * 2);
    for (int i = 0; i < frames; ++i) {
        interleaved_[2 * static_cast<std::size_t>(i)] = left[i];
        interleaved_[2 * static_cast<std::size_t>(i) + 1] = right[i];
    }
    out_.write(interleaved_.data(), static_cast<std::size_t>(frames));
}

void StreamingWavWriter::finish() { out_.finish(); }

} // namespace armadillo::live
