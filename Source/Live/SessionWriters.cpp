#include "Live/SessionWriters.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unistd.h>

namespace armadillo::device {

namespace {

std::string tempNameFor(const std::string& path)
{
    return path + ".tmp-" + std::to_string(::getpid()) + "-" +
           std::to_string(std::chrono::steady_clock::now().time_since_epoch().count() % 1000000007);
}

std::FILE* openTemp(const std::string& path, const std::string& tmp)
{
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw IoError("cannot write " + path + ": " + std::strerror(errno));
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
        throw IoError("cannot write " + path + ": " + std::strerror(e2 ? e2 : EIO));
    }
}

} // namespace

// --- CSV ---------------------------------------------------------------------------------------

StreamingCsvWriter::StreamingCsvWriter(std::string path, const std::vector<std::string>& header, int precision)
    : path_(std::move(path)), tmp_(tempNameFor(path_)), columns_(static_cast<int>(header.size())), precision_(precision)
{
    if (columns_ < 1 || columns_ > kMaxLogColumns) throw IoError("CSV writer for " + path_ + ": bad column count");
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
            appendNumber(text_, i < row.count ? row.v[static_cast<std::size_t>(i)] : kNaN, precision_);
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

namespace {
void put16(unsigned char* p, unsigned v) { p[0] = static_cast<unsigned char>(v); p[1] = static_cast<unsigned char>(v >> 8); }
void put32(unsigned char* p, std::uint32_t v)
{
    for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
} // namespace

StreamingWavWriter::StreamingWavWriter(std::string path, double sampleRate, bool float32)
    : path_(std::move(path)), tmp_(tempNameFor(path_)), sampleRate_(sampleRate), float32_(float32)
{
    file_ = openTemp(path_, tmp_);
    unsigned char header[44] {};   // sizes patched by finish()
    if (std::fwrite(header, 1, sizeof header, file_) != sizeof header) failed_ = true;
}

StreamingWavWriter::~StreamingWavWriter()
{
    if (file_) {
        std::fclose(file_);
        std::remove(tmp_.c_str());
    }
}

void StreamingWavWriter::write(const float* left, const float* right, int frames)
{
    if (!file_ || frames <= 0) return;
    const std::size_t bytesPerSample = float32_ ? 4 : 2;
    buffer_.resize(static_cast<std::size_t>(frames) * 2 * bytesPerSample);
    unsigned char* p = buffer_.data();
    for (int i = 0; i < frames; ++i) {
        for (const float s : {left[i], right[i]}) {
            if (float32_) {
                float v = std::isfinite(s) ? s : 0.0f;
                std::uint32_t bits;
                std::memcpy(&bits, &v, 4);
                put32(p, bits);
                p += 4;
            } else {
                const float c = std::isfinite(s) ? std::clamp(s, -1.0f, 1.0f) : 0.0f;
                const long v = std::lround(static_cast<double>(c) * 32767.0);
                put16(p, static_cast<unsigned>(static_cast<std::uint16_t>(static_cast<std::int16_t>(v))));
                p += 2;
            }
        }
    }
    if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) failed_ = true;
    frames_ += static_cast<std::uint64_t>(frames);
}

void StreamingWavWriter::finish()
{
    if (!file_) return;
    const std::uint32_t bytesPerSample = float32_ ? 4 : 2;
    const std::uint64_t dataBytes = frames_ * 2 * bytesPerSample;
    if (dataBytes > 0xFFFFFFF0ull - 36) failed_ = true;   // RIFF's 4 GiB limit
    unsigned char h[44];
    std::memcpy(h, "RIFF", 4);
    put32(h + 4, static_cast<std::uint32_t>(36 + dataBytes));
    std::memcpy(h + 8, "WAVEfmt ", 8);
    put32(h + 16, 16);
    put16(h + 20, float32_ ? 3 : 1);
    put16(h + 22, 2);
    put32(h + 24, static_cast<std::uint32_t>(std::lround(sampleRate_)));
    put32(h + 28, static_cast<std::uint32_t>(std::lround(sampleRate_)) * 2 * bytesPerSample);
    put16(h + 32, 2 * bytesPerSample);
    put16(h + 34, 8 * bytesPerSample);
    std::memcpy(h + 36, "data", 4);
    put32(h + 40, static_cast<std::uint32_t>(dataBytes));
    if (std::fseek(file_, 0, SEEK_SET) != 0 || std::fwrite(h, 1, sizeof h, file_) != sizeof h) failed_ = true;
    commit(file_, path_, tmp_, failed_);
}

} // namespace armadillo::device
