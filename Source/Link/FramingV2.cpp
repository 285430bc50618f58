#include "Link/FramingV2.h"
#include <algorithm>
#include <cstring>

namespace armadillo::link {

std::uint16_t crc16Ccitt(const std::uint8_t* data, std::size_t n, std::uint16_t crc) noexcept
{
    for (std::size_t i = 0; i < n; ++i) {
        crc = static_cast<std::uint16_t>(crc ^ (static_cast<unsigned>(data[i]) << 8));
        for (int b = 0; b < 8; ++b)
            crc = (crc & 0x8000u) ? static_cast<std::uint16_t>((crc << 1) ^ 0x1021u) : static_cast<std::uint16_t>(crc << 1);
    }
    return crc;
}

namespace {
void putCrc(std::uint8_t* frame, std::size_t n) noexcept
{
    const std::uint16_t c = crc16Ccitt(frame, n);
    frame[n] = static_cast<std::uint8_t>(c >> 8);
    frame[n + 1] = static_cast<std::uint8_t>(c & 0xFF);
}
bool crcOk(const std::uint8_t* frame, std::size_t n) noexcept
{
    return crc16Ccitt(frame, n) == ((static_cast<unsigned>(frame[n]) << 8) | frame[n + 1]);
}
} // namespace

std::array<std::uint8_t, kV2OfferSize> encodeOfferV2(const OfferV2& offer) noexcept
{
    std::array<std::uint8_t, kV2OfferSize> out {};
    std::copy(std::begin(kV2Query), std::end(kV2Query), out.begin());
    out[5] = offer.version;
    out[6] = offer.motors;
    out[7] = static_cast<std::uint8_t>(offer.sensorRateHz >> 8);
    out[8] = static_cast<std::uint8_t>(offer.sensorRateHz & 0xFF);
    putCrc(out.data(), 11);
    out[13] = kV2OfferEnd;
    return out;
}

bool decodeOfferV2(const std::uint8_t* bytes, OfferV2& offer) noexcept
{
    if (std::memcmp(bytes, kV2Query, sizeof kV2Query) != 0 || bytes[13] != kV2OfferEnd || !crcOk(bytes, 11)) return false;
    if (bytes[5] < 2) return false;
    offer.version = bytes[5];
    offer.motors = bytes[6];
    offer.sensorRateHz = static_cast<std::uint16_t>((bytes[7] << 8) | bytes[8]);
    return true;
}

std::array<std::uint8_t, kV2SensorFrameSize> encodeSensorFrameV2(const SensorFrameV2& f) noexcept
{
    std::array<std::uint8_t, kV2SensorFrameSize> out {};
    out[0] = kV2SensorSync;
    out[1] = f.seq;
    out[2] = static_cast<std::uint8_t>((f.rawTimeUs >> 16) & 0xFF);
    out[3] = static_cast<std::uint8_t>((f.rawTimeUs >> 8) & 0xFF);
    out[4] = static_cast<std::uint8_t>(f.rawTimeUs & 0xFF);
    // The 14 sample bytes are the v1 packing; the last nibble carries the status instead of 0x0.
    const SensorPacketBytes p = encodeSensorPacket(f.counts);
    std::copy(p.begin(), p.end(), out.begin() + 5);
    out[18] = static_cast<std::uint8_t>((out[18] & 0xF0) | (f.status & 0x0F));
    putCrc(out.data(), 19);
    return out;
}

bool decodeSensorFrameV2(const std::uint8_t* bytes, SensorFrameV2& f) noexcept
{
    if (bytes[0] != kV2SensorSync || !crcOk(bytes, 19)) return false;
    f.seq = bytes[1];
    f.rawTimeUs = (static_cast<std::uint32_t>(bytes[2]) << 16) | (static_cast<std::uint32_t>(bytes[3]) << 8) | bytes[4];
    f.deviceTimeUs = f.rawTimeUs;
    decodeSensorPacket(bytes + 5, f.counts);   // its "end nibble" is the status: not checked
    f.status = static_cast<std::uint8_t>(bytes[18] & 0x0F);
    return true;
}

std::array<std::uint8_t, kV2MotorFrameSize> encodeMotorFrameV2(std::uint8_t seq, const ProtocolLevels& levels,
                                                               std::uint8_t flags) noexcept
{
    auto lv = [&](int i) { return static_cast<unsigned>(std::min<unsigned>(levels[static_cast<std::size_t>(i)], 15u)); };
    std::array<std::uint8_t, kV2MotorFrameSize> out {};
    out[0] = kV2MotorSync;
    out[1] = seq;
    for (int i = 0; i < 4; ++i) out[static_cast<std::size_t>(2 + i)] = static_cast<std::uint8_t>((lv(2 * i) << 4) | lv(2 * i + 1));
    out[6] = static_cast<std::uint8_t>((lv(8) << 4) | (flags & 0x0F));
    putCrc(out.data(), 7);
    return out;
}

bool decodeMotorFrameV2(const std::uint8_t* bytes, std::uint8_t& seq, ProtocolLevels& levels, std::uint8_t& flags) noexcept
{
    if (bytes[0] != kV2MotorSync || !crcOk(bytes, 7)) return false;
    seq = bytes[1];
    for (int i = 0; i < 4; ++i) {
        levels[static_cast<std::size_t>(2 * i)] = static_cast<std::uint8_t>(bytes[2 + i] >> 4);
        levels[static_cast<std::size_t>(2 * i + 1)] = static_cast<std::uint8_t>(bytes[2 + i] & 0x0F);
    }
    levels[8] = static_cast<std::uint8_t>(bytes[6] >> 4);
    flags = static_cast<std::uint8_t>(bytes[6] & 0x0F);
    return true;
}

void FramingV2Host::startNegotiation(std::vector<std::uint8_t>& out)
{
    out.insert(out.end(), std::begin(kV2Query), std::end(kV2Query));
    const std::uint8_t burst[5] = {0x00, 0x00, 0x00, 0x00, kMotorEndNibble};   // the v1 resync, as any host sends it
    out.insert(out.end(), std::begin(burst), std::end(burst));
    mode_ = Mode::Negotiating;
    fill_ = 0;
    hasV1Answer_ = false;
    haveSeq_ = false;
}

void FramingV2Host::fallBackToV1() noexcept
{
    mode_ = Mode::V1;
    fill_ = 0;
}

void FramingV2Host::receive(std::uint8_t byte, std::vector<SensorFrameV2>& frames)
{
    switch (mode_) {
    case Mode::V1:
        return;
    case Mode::Negotiating:
        buf_[fill_++] = byte;
        if (fill_ < kV2OfferSize) return;
        fill_ = 0;
        if (decodeOfferV2(buf_, offer_)) {
            mode_ = Mode::V2;
            haveSeq_ = false;
            return;
        }
        // Not an offer: a v1 board answered the resync (or garbage, which v1's checks will handle).
        std::copy(buf_, buf_ + kSensorPacketSize, v1Answer_.begin());
        hasV1Answer_ = sensorPacketEndOk(buf_[kSensorPacketSize - 1]);
        mode_ = Mode::V1;
        return;
    case Mode::V2:
        break;
    }
    if (fill_ == 0 && byte != kV2SensorSync) {
        ++stats_.discardedBytes;
        return;
    }
    buf_[fill_++] = byte;
    if (fill_ < kV2SensorFrameSize) return;
    SensorFrameV2 f;
    if (!decodeSensorFrameV2(buf_, f)) {
        ++stats_.crcFailures;
        // The real frame may start at a later sync byte inside this one.
        std::size_t next = 1;
        while (next < kV2SensorFrameSize && buf_[next] != kV2SensorSync) ++next;
        stats_.discardedBytes += next;
        std::memmove(buf_, buf_ + next, kV2SensorFrameSize - next);
        fill_ = kV2SensorFrameSize - next;
        return;
    }
    fill_ = 0;
    if (haveSeq_) {
        stats_.seqGaps += static_cast<std::uint8_t>(f.seq - lastSeq_ - 1);
        time_ += (f.rawTimeUs - lastRawTime_) & 0xFFFFFFu;   // 24-bit clock, wraps every 16.8 s
    } else {
        time_ = f.rawTimeUs;
    }
    haveSeq_ = true;
    lastSeq_ = f.seq;
    lastRawTime_ = f.rawTimeUs;
    f.deviceTimeUs = time_;
    ++stats_.frames;
    frames.push_back(f);
}

void FramingV2Host::encodeMotor(const ProtocolLevels& levels, std::vector<std::uint8_t>& out, std::uint8_t flags)
{
    const auto f = encodeMotorFrameV2(motorSeq_++, levels, flags);
    out.insert(out.end(), f.begin(), f.end());
}

} // namespace armadillo::link
