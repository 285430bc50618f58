#include "Live/SessionWriters.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unistd.h>

namespace armadillo::live {

namespace {

std::string tempNameFor(const std::string& path)
{
    return path + ".tmp-" + std::to_string(::getpid()) + "-" +
           std::to_string(std::chrono::steady_clock::now().time_since_epoch().count() % 1000000007);
}

std::FILE* openTemp(const std::string& path, const std::string& tmp)
{
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw core::IoError("cannot write " + path + ": " + std::strerror(errno));
    return f;
}

void commit(std::FILE*& f, const std::string& path, const std::string& tmp, bool failed)
{
    bool ok = !failed && std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
    const int e = errno;
    ok = std::fclose(f) == 0 && ok;
    f = nullptr;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e2 = ok ? errno : e;
        std::remove(tmp.c_str());
        throw core::IoError("cannot write " + path + ": " + std::strerror(e2 ? e2 : EIO));
    }
}

} // namespace

// --- CSV ---------------------------------------------------------------------------------------

StreamingCsvWriter::StreamingCsvWriter(std::string path, const std::vector<std::string>& header, int precision)
    : path_(std::move(path)), tmp_(tempNameFor(path_)), columns_(static_cast<int>(header.size())), precision_(precision)
{
    if (columns_ < 1 || columns_ > kMaxLogColumns) throw core::IoError("CSV writer for " + path_ + ": bad column count");
    file_ = openTemp(path_, tmp_);
    std::string h;
    for (std::size_t i = 0; i < header.size(); ++i) h += (i ? "," : "") + header[i];
    h += '\n';
    if (std::fwrite(h.data(), 1, h.size(), file_) != h.size()) failed_.store(true);
    thread_ = std::thread([this] { run(); });
}

StreamingCsvWriter::~StreamingCsvWriter()
{
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    if (file_) {
        std::fclose(file_);
        std::remove(tmp_.c_str());
    }
}

bool StreamingCsvWriter::push(const LogRow& row) noexcept
{
    if (queue_.push(row)) return true;
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
}

void StreamingCsvWriter::drain()
{
    LogRow row;
    text_.clear();
    while (queue_.pop(row)) {
        for (int i = 0; i < columns_; ++i) {
            if (i) text_ += ',';
            core::appendNumber(text_, i < row.count ? row.v[static_cast<std::size_t>(i)] : core::kNaN, precision_);
        }
        text_ += '\n';
        written_.fetch_add(1, std::memory_order_relaxed);
        if (text_.size() > 1 << 16) break;
    }
    if (!text_.empty() && std::fwrite(text_.data(), 1, text_.size(), file_) != text_.size()) failed_.store(true);
}

void StreamingCsvWriter::run()
{
    while (!stop_.load(std::memory_order_acquire)) {
        drain();
        if (queue_.size() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    while (queue_.size() > 0) drain();
}

void StreamingCsvWriter::finish()
{
    if (!file_) return;
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    commit(file_, path_, tmp_, failed_.load());
}

// --- WAV ---------------------------------------------------------------------------------------

StreamingWavWriter::StreamingWavWriter(std::string path, double sampleRate, bool float32)
    : out_(std::move(path), sampleRate, 2, float32)
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
