#pragma once
// SLIP framing (RFC 1055): packets on a byte stream, each ended by END (0xC0), with END and ESC
// (0xDB) inside a packet written as ESC ESC_END (0xDB 0xDC) and ESC ESC_ESC (0xDB 0xDD). The
// NGIMU sends its OSC packets over USB and serial this way (x-io's NGIMU user manual,
// "Communication"; NgimuApi/ConnectionImplementations/SerialConnectionImplementation.cs sizes its
// buffer for "SLIP escaped bytes"), as OSC 1.1 recommends for stream transports. The decoder
// keeps no heap after construction and never trusts the stream: an over-long packet or a bad
// escape drops that packet (counted) and resynchronises on the next END.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace armadillo::osc {

class SlipDecoder {
public:
    static constexpr std::uint8_t kEnd = 0xC0, kEsc = 0xDB, kEscEnd = 0xDC, kEscEsc = 0xDD;
    explicit SlipDecoder(std::size_t maxPacket = 65536) { buffer_.reserve(maxPacket); max_ = maxPacket; }

    /// Feeds bytes; calls sink(context, packet, size) for every complete, non-empty packet.
    template <typename Sink>
    void feed(const std::uint8_t* data, std::size_t size, Sink&& sink)
    {
        for (std::size_t i = 0; i < size; ++i) {
            std::uint8_t b = data[i];
            if (b == kEnd) {
                if (!dropping_ && !escaped_ && !buffer_.empty()) sink(buffer_.data(), buffer_.size());
                else if (escaped_) ++bad_;
                buffer_.clear();
                dropping_ = escaped_ = false;
                continue;
            }
            if (dropping_) continue;
            if (escaped_) {
                escaped_ = false;
                if (b == kEscEnd) b = kEnd;
                else if (b == kEscEsc) b = kEsc;
                else {   // not an escape RFC 1055 defines: the packet is damaged
                    ++bad_;
                    dropping_ = true;
                    continue;
                }
            } else if (b == kEsc) {
                escaped_ = true;
                continue;
            }
            if (buffer_.size() >= max_) {
                ++bad_;
                dropping_ = true;
                continue;
            }
            buffer_.push_back(b);
        }
    }
    std::uint64_t badPackets() const noexcept { return bad_; }

private:
    std::vector<std::uint8_t> buffer_;
    std::size_t max_ = 65536;
    bool escaped_ = false, dropping_ = false;
    std::uint64_t bad_ = 0;
};

/// One packet SLIP-encoded, with an END before (flushes line noise, as RFC 1055 suggests) and after.
inline std::vector<std::uint8_t> slipEncode(const std::uint8_t* data, std::size_t size)
{
    std::vector<std::uint8_t> out;
    out.reserve(size + size / 8 + 2);
    out.push_back(SlipDecoder::kEnd);
    for (std::size_t i = 0; i < size; ++i) {
        if (data[i] == SlipDecoder::kEnd) {
            out.push_back(SlipDecoder::kEsc);
            out.push_back(SlipDecoder::kEscEnd);
        } else if (data[i] == SlipDecoder::kEsc) {
            out.push_back(SlipDecoder::kEsc);
            out.push_back(SlipDecoder::kEscEsc);
        } else {
            out.push_back(data[i]);
        }
    }
    out.push_back(SlipDecoder::kEnd);
    return out;
}

} // namespace armadillo::osc
