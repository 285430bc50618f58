#include "Osc/OscStream.h"
#include <algorithm>
#include <cstring>

namespace armadillo::osc {

namespace {
constexpr char kBundle[8] = {'#', 'b', 'u', 'n', 'd', 'l', 'e', '\0'};
std::uint32_t be32(const std::uint8_t* p) noexcept
{
    return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}
bool isSpace(std::uint8_t c) noexcept { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }
} // namespace

OscStreamSplitter::OscStreamSplitter(std::size_t capacity) : buf_(capacity), scratch_(capacity + 16) {}

void OscStreamSplitter::reset() noexcept
{
    size_ = 0;
    haveHeader_ = false;
}

void OscStreamSplitter::consume(std::size_t n) noexcept
{
    n = std::min(n, size_);
    std::memmove(buf_.data(), buf_.data() + n, size_ - n);
    size_ -= n;
}

std::size_t OscStreamSplitter::jsonEnd() const noexcept
{
    int depth = 0;
    bool inString = false, escaped = false;
    for (std::size_t i = 0; i < size_; ++i) {
        const std::uint8_t c = buf_[i];
        if (inString) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') inString = true;
        else if (c == '{' || c == '[') ++depth;
        else if (c == '}' || c == ']') {
            if (--depth == 0) return i + 1;
        }
    }
    return 0;
}

/// Walks size-prefixed elements from `from`; returns where they end: at a following "#bundle"
/// or at the end of the data (complete), or where an element is cut (incomplete, complete=false).
/// 0 when an element size is impossible (not a bundle after all).
std::size_t OscStreamSplitter::bundleEnd(std::size_t from, bool& complete) const noexcept
{
    std::size_t pos = from;
    complete = false;
    while (pos < size_) {
        if (pos > from && size_ - pos >= 8 && std::memcmp(buf_.data() + pos, kBundle, 8) == 0) {
            complete = true;
            return pos;
        }
        if (size_ - pos < 4) return pos;   // a size cut in half: wait
        const std::uint32_t n = be32(buf_.data() + pos);
        if (n == 0 || n % 4 != 0 || n > buf_.size()) return 0;
        if (size_ - pos - 4 < n) return pos;   // an element not all here yet
        pos += 4 + n;
    }
    complete = true;
    return pos;
}

void OscStreamSplitter::feed(const std::uint8_t* data, std::size_t size, Sink sink, void* context)
{
    while (size > 0) {
        const std::size_t take = std::min(size, buf_.size() - size_);
        std::memcpy(buf_.data() + size_, data, take);
        size_ += take;
        data += take;
        size -= take;
        for (;;) {
            std::size_t lead = 0;
            while (lead < size_ && isSpace(buf_[lead])) ++lead;
            consume(lead);
            if (size_ == 0) break;
            const std::uint8_t c = buf_[0];
            if (c == '{') {
                const std::size_t n = jsonEnd();
                if (n == 0) break;
                sink(context, buf_.data(), n);
                consume(n);
                continue;
            }
            if (c == '#') {
                if (size_ < 16) break;
                if (std::memcmp(buf_.data(), kBundle, 8) == 0) {
                    bool complete = false;
                    const std::size_t end = bundleEnd(16, complete);
                    if (end != 0) {
                        if (!complete) break;
                        std::memcpy(header_, buf_.data(), 16);
                        haveHeader_ = true;
                        sink(context, buf_.data(), end);
                        consume(end);
                        continue;
                    }
                }
            } else if (haveHeader_ && c == 0 && size_ >= 4) {
                // Elements after a bundle that ended at a read boundary: they belong to it.
                bool complete = false;
                const std::size_t end = bundleEnd(0, complete);
                if (end != 0) {
                    if (!complete) break;
                    std::memcpy(scratch_.data(), header_, 16);
                    std::memcpy(scratch_.data() + 16, buf_.data(), end);
                    sink(context, scratch_.data(), end + 16);
                    consume(end);
                    continue;
                }
            } else if (c == '/') {
                // A bare message has no length of its own on a stream: what has arrived is it.
                sink(context, buf_.data(), size_);
                consume(size_);
                continue;
            }
            // Neither JSON nor OSC: up to the next byte that could start a unit, as one junk unit.
            std::size_t n = 1;
            while (n < size_ && buf_[n] != '{' && buf_[n] != '#') ++n;
            sink(context, buf_.data(), n);
            consume(n);
        }
        if (size_ == buf_.size()) {   // full without a complete unit
            ++overflows_;
            reset();
        }
    }
}

} // namespace armadillo::osc
