#include "Protocol.h"

namespace armfw {

const uint8_t kQuery[kQuerySize] = {0x41, 0x52, 0x4D, 0x76, 0x32};   // "ARMv2"

uint16_t crc16(const uint8_t* data, size_t n, uint16_t crc)
{
    for (size_t i = 0; i < n; ++i) {
        crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(data[i]) << 8));
        for (uint8_t b = 0; b < 8; ++b)
            crc = (crc & 0x8000u) ? static_cast<uint16_t>((crc << 1) ^ 0x1021u) : static_cast<uint16_t>(crc << 1);
    }
    return crc;
}

void packSamples(const uint16_t counts[kChannels], uint8_t lastNibble, uint8_t out[14])
{
    uint16_t c[kChannels];
    for (uint8_t i = 0; i < kChannels; ++i) c[i] = counts[i] > kMaxCount ? kMaxCount : counts[i];
    // Two 12-bit samples fill three bytes; the ninth fills one and a half, then the nibble.
    for (uint8_t pair = 0; pair < 4; ++pair) {
        const uint16_t a = c[2 * pair], b = c[2 * pair + 1];
        out[3 * pair] = static_cast<uint8_t>(a >> 4);
        out[3 * pair + 1] = static_cast<uint8_t>(((a & 0x0Fu) << 4) | (b >> 8));
        out[3 * pair + 2] = static_cast<uint8_t>(b & 0xFFu);
    }
    out[12] = static_cast<uint8_t>(c[8] >> 4);
    out[13] = static_cast<uint8_t>(((c[8] & 0x0Fu) << 4) | (lastNibble & 0x0Fu));
}

void unpackSamples(const uint8_t in[14], uint16_t counts[kChannels])
{
    for (uint8_t pair = 0; pair < 4; ++pair) {
        const uint8_t* p = in + 3 * pair;
        counts[2 * pair] = static_cast<uint16_t>((static_cast<uint16_t>(p[0]) << 4) | (p[1] >> 4));
        counts[2 * pair + 1] = static_cast<uint16_t>((static_cast<uint16_t>(p[1] & 0x0Fu) << 8) | p[2]);
    }
    counts[8] = static_cast<uint16_t>((static_cast<uint16_t>(in[12]) << 4) | (in[13] >> 4));
}

void encodeV1Sensor(const uint16_t counts[kChannels], uint8_t out[kV1SensorSize])
{
    packSamples(counts, 0x0, out);   // end nibble 0x0
}

void encodeOffer(uint16_t sensorRateHz, uint8_t out[kOfferSize])
{
    // "ARMv2" magic, version, motors, the sensor rate the board sustains (Hz, big-endian),
    // two reserved bytes, CRC over bytes 0..10, a pad and the end byte 0x5F (not a v1 end nibble).
    for (uint8_t i = 0; i < kQuerySize; ++i) out[i] = kQuery[i];
    out[5] = kV2Version;
    out[6] = kMotors;
    out[7] = static_cast<uint8_t>(sensorRateHz >> 8);
    out[8] = static_cast<uint8_t>(sensorRateHz & 0xFFu);
    out[9] = 0;
    out[10] = 0;
    const uint16_t crc = crc16(out, 11);
    out[11] = static_cast<uint8_t>(crc >> 8);
    out[12] = static_cast<uint8_t>(crc & 0xFFu);
    out[13] = kOfferEndByte;
}

void encodeV2Sensor(uint8_t seq, uint32_t timeUs, const uint16_t counts[kChannels], uint8_t status,
                    uint8_t out[kV2SensorSize])
{
    out[0] = kV2SensorSync;
    out[1] = seq;
    out[2] = static_cast<uint8_t>((timeUs >> 16) & 0xFFu);
    out[3] = static_cast<uint8_t>((timeUs >> 8) & 0xFFu);
    out[4] = static_cast<uint8_t>(timeUs & 0xFFu);
    packSamples(counts, status, out + 5);
    const uint16_t crc = crc16(out, 19);
    out[19] = static_cast<uint8_t>(crc >> 8);
    out[20] = static_cast<uint8_t>(crc & 0xFFu);
}

void encodeV2Motor(uint8_t seq, const uint8_t levels[kMotors], uint8_t flags, uint8_t out[kV2MotorSize])
{
    auto lv = [&](uint8_t i) { return static_cast<uint8_t>(levels[i] > 15 ? 15 : levels[i]); };
    out[0] = kV2MotorSync;
    out[1] = seq;
    for (uint8_t i = 0; i < 4; ++i) out[2 + i] = static_cast<uint8_t>((lv(2 * i) << 4) | lv(2 * i + 1));
    out[6] = static_cast<uint8_t>((lv(8) << 4) | (flags & 0x0Fu));
    const uint16_t crc = crc16(out, 7);
    out[7] = static_cast<uint8_t>(crc >> 8);
    out[8] = static_cast<uint8_t>(crc & 0xFFu);
}

void DeviceLink::reset()
{
    mode_ = Mode::V1;
    waiting_ = true;
    offerPending_ = false;
    leavePending_ = false;
    replyDue_ = false;
    haveHostSeq_ = false;
    fill_ = 0;
    for (uint8_t i = 0; i < kMotors; ++i) levels_[i] = 0;
    queryMatch_ = 0;
    lastGoodMs_ = 0;
    hostSeq_ = 0;
    seq_ = 0;
}

LinkEvent DeviceLink::onByte(uint8_t byte, uint32_t nowMs)
{
    // The v2 query is recognised in every state: a host that (re)connects asks again.
    queryMatch_ = (byte == kQuery[queryMatch_]) ? static_cast<uint8_t>(queryMatch_ + 1)
                                                 : static_cast<uint8_t>(byte == kQuery[0] ? 1 : 0);
    if (queryMatch_ == kQuerySize) {
        queryMatch_ = 0;
        mode_ = Mode::V1;
        waiting_ = true;          // the resync that follows the query gets the offer
        fill_ = 0;
        offerPending_ = true;
        leavePending_ = false;
        replyDue_ = false;
        ++badPackets_;            // what a v1 device would count: the query spoilt a packet
        return LinkEvent::None;
    }
    const LinkEvent e = mode_ == Mode::V1 ? onV1(byte) : onV2(byte, nowMs);
    if (e == LinkEvent::Motor || e == LinkEvent::Resynced) {
        replyDue_ = true;
        lastGoodMs_ = nowMs;
    }
    return e;
}

LinkEvent DeviceLink::onV1(uint8_t byte)
{
    // The thesis rule: wait for a byte whose low nibble is 0x8, answer it, then read 5-byte packets.
    // The host's resync burst 00 00 00 00 08 reads as "all off" to a device in step; one out of step
    // skips the 0x00 bytes (low nibble 0) and answers the 0x08.
    if (waiting_) {
        if ((byte & 0x0Fu) != kMotorEndNibble) return LinkEvent::None;
        waiting_ = false;
        fill_ = 0;
        return LinkEvent::Resynced;
    }
    buf_[fill_++] = byte;
    if (fill_ < kV1MotorSize) return LinkEvent::None;
    fill_ = 0;
    if ((buf_[4] & 0x0Fu) != kMotorEndNibble) {
        ++badPackets_;
        waiting_ = true;
        return LinkEvent::BadPacket;
    }
    for (uint8_t i = 0; i < 4; ++i) {
        levels_[2 * i] = static_cast<uint8_t>(buf_[i] >> 4);
        levels_[2 * i + 1] = static_cast<uint8_t>(buf_[i] & 0x0Fu);
    }
    levels_[8] = static_cast<uint8_t>(buf_[4] >> 4);
    return LinkEvent::Motor;
}

LinkEvent DeviceLink::onV2(uint8_t byte, uint32_t /*nowMs*/)
{
    if (fill_ == 0 && byte != kV2MotorSync) return LinkEvent::None;   // hunting for the sync byte
    buf_[fill_++] = byte;
    if (fill_ < kV2MotorSize) return LinkEvent::None;
    const uint16_t crc = crc16(buf_, 7);
    if (crc != ((static_cast<uint16_t>(buf_[7]) << 8) | buf_[8])) {
        ++badFrames_;
        // Rescan: the real frame may start at a later sync byte inside this one.
        uint8_t next = 1;
        while (next < kV2MotorSize && buf_[next] != kV2MotorSync) ++next;
        for (uint8_t i = next; i < kV2MotorSize; ++i) buf_[i - next] = buf_[i];
        fill_ = static_cast<uint8_t>(kV2MotorSize - next);
        return LinkEvent::BadFrame;
    }
    fill_ = 0;
    if (haveHostSeq_) seqGaps_ = static_cast<uint16_t>(seqGaps_ + static_cast<uint8_t>(buf_[1] - hostSeq_ - 1));
    haveHostSeq_ = true;
    hostSeq_ = buf_[1];
    for (uint8_t i = 0; i < 4; ++i) {
        levels_[2 * i] = static_cast<uint8_t>(buf_[2 + i] >> 4);
        levels_[2 * i + 1] = static_cast<uint8_t>(buf_[2 + i] & 0x0Fu);
    }
    levels_[8] = static_cast<uint8_t>(buf_[6] >> 4);
    if (buf_[6] & kV2FlagLeave) leavePending_ = true;
    return LinkEvent::Motor;
}

void DeviceLink::tick(uint32_t nowMs)
{
    if (mode_ == Mode::V2 && !replyDue_ && static_cast<uint32_t>(nowMs - lastGoodMs_) > kV2FallbackMs) {
        mode_ = Mode::V1;   // no v2 host any more: speak the thesis protocol again
        waiting_ = true;
        fill_ = 0;
        haveHostSeq_ = false;
    }
}

uint8_t DeviceLink::buildReply(const uint16_t counts[kChannels], uint32_t timeUs, uint8_t status,
                               uint16_t sensorRateHz, uint8_t* out, uint8_t capacity)
{
    if (!replyDue_) return 0;
    if (offerPending_) {
        if (capacity < kOfferSize) return 0;
        replyDue_ = false;
        offerPending_ = false;
        encodeOffer(sensorRateHz, out);
        mode_ = Mode::V2;   // the host answers an offer with v2 frames, or falls back after kV2FallbackMs
        fill_ = 0;
        haveHostSeq_ = false;
        return kOfferSize;
    }
    if (mode_ == Mode::V2) {
        if (capacity < kV2SensorSize) return 0;
        replyDue_ = false;
        encodeV2Sensor(seq_++, timeUs, counts, status, out);
        if (leavePending_) {
            leavePending_ = false;
            mode_ = Mode::V1;
            waiting_ = true;
            fill_ = 0;
        }
        return kV2SensorSize;
    }
    if (capacity < kV1SensorSize) return 0;
    replyDue_ = false;
    encodeV1Sensor(counts, out);
    return kV1SensorSize;
}

} // namespace armfw
