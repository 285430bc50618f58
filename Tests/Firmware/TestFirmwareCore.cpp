// The firmware's protocol, safety and sensor-scaling code (firmware/core, plain C++) compiled for the
// host: every malformed packet we could think of, the v2 negotiation against the host's own codec
// (Source/Link/FramingV2), the watchdog and the heat limit, and the scaling against the host's
// default calibration.
#include "core/Protocol.h"
#include "core/Safety.h"
#include "core/SensorScale.h"
#include "Link/Calibration.h"
#include "Link/DeviceProtocol.h"
#include "Link/FramingV2.h"
#include "Link/Packets.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

using armfw::DeviceLink;
using armfw::LinkEvent;
namespace dev = armadillo::link;

namespace {
const uint16_t kCounts[9] = {0x123, 0x456, 0x789, 0xABC, 0xDEF, 0x012, 0x345, 0x678, 0x9AB};

std::vector<LinkEvent> feed(DeviceLink& link, std::initializer_list<uint8_t> bytes, uint32_t ms = 0)
{
    std::vector<LinkEvent> out;
    for (uint8_t b : bytes) out.push_back(link.onByte(b, ms));
    return out;
}

/// A link in step: the power-up wait ended by a 0x08, its reply taken.
DeviceLink inStep()
{
    DeviceLink link;
    REQUIRE(link.onByte(0x08, 0) == LinkEvent::Resynced);
    uint8_t out[32];
    REQUIRE(link.buildReply(kCounts, 0, 0, 0, out, sizeof out) == 14);
    return link;
}
} // namespace

TEST_CASE("firmware crc16 is CRC-16/CCITT-FALSE and agrees with the host's", "[firmware]")
{
    const uint8_t s[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    CHECK(armfw::crc16(s, 9) == 0x29B1);
    CHECK(dev::crc16Ccitt(s, 9) == 0x29B1);
    std::mt19937 rng(5);
    for (int i = 0; i < 200; ++i) {
        uint8_t buf[32];
        const size_t n = rng() % 32;
        for (size_t k = 0; k < n; ++k) buf[k] = static_cast<uint8_t>(rng());
        CHECK(armfw::crc16(buf, n) == dev::crc16Ccitt(buf, n));
    }
}

TEST_CASE("firmware v1 sensor packet is byte-identical to the host codec's (thesis Table 2-2)", "[firmware]")
{
    uint8_t out[14];
    armfw::encodeV1Sensor(kCounts, out);
    const uint8_t expect[14] = {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xF0, 0x12, 0x34, 0x56, 0x78, 0x9A, 0xB0};
    for (int i = 0; i < 14; ++i) CHECK(out[i] == expect[i]);
    dev::SensorCounts back {};
    CHECK(dev::decodeSensorPacket(out, back));
    for (int i = 0; i < 9; ++i) CHECK(back[static_cast<size_t>(i)] == kCounts[i]);
    // Out-of-range counts clamp to 4095, never wrap into a small value.
    uint16_t big[9] = {4096, 65535, 0, 0, 0, 0, 0, 0, 5000};
    armfw::encodeV1Sensor(big, out);
    CHECK(dev::decodeSensorPacket(out, back));
    CHECK(back[0] == 4095);
    CHECK(back[1] == 4095);
    CHECK(back[8] == 4095);
}

TEST_CASE("firmware v1: power-up waits for 0x8, good packets set levels, and each malformed packet is refused", "[firmware]")
{
    SECTION("power-up: bytes without low nibble 8 are ignored, no reply, motors off")
    {
        DeviceLink link;
        for (int b = 0; b < 256; ++b) {
            if ((b & 0x0F) == 0x8) continue;
            CHECK(link.onByte(static_cast<uint8_t>(b), 0) == LinkEvent::None);
        }
        CHECK_FALSE(link.replyDue());
        for (int m = 0; m < 9; ++m) CHECK(link.levels()[m] == 0);
        CHECK(link.onByte(0xF8, 0) == LinkEvent::Resynced);   // any byte ending in 8, even F8
        CHECK(link.replyDue());
        for (int m = 0; m < 9; ++m) CHECK(link.levels()[m] == 0);   // the resync byte is not motor data
    }
    SECTION("a good packet: levels 1..9 in thesis nibble order")
    {
        DeviceLink link = inStep();
        const auto ev = feed(link, {0x12, 0x34, 0x56, 0x78, 0x98});
        CHECK(ev.back() == LinkEvent::Motor);
        for (int m = 0; m < 9; ++m) CHECK(link.levels()[m] == m + 1);
        uint8_t out[32];
        CHECK(link.buildReply(kCounts, 0, 0, 0, out, sizeof out) == 14);
        CHECK(link.buildReply(kCounts, 0, 0, 0, out, sizeof out) == 0);   // one reply per packet
    }
    SECTION("wrong end nibble (every value but 8): bad packet, levels kept, waits for 0x8")
    {
        for (int end = 0; end < 16; ++end) {
            if (end == 8) continue;
            DeviceLink link = inStep();
            feed(link, {0x33, 0x33, 0x33, 0x33, 0x38});
            uint8_t out[32];
            REQUIRE(link.buildReply(kCounts, 0, 0, 0, out, sizeof out) == 14);
            const auto ev = feed(link, {0xFF, 0xFF, 0xFF, 0xFF, static_cast<uint8_t>(0xF0 | end)});
            CHECK(ev.back() == LinkEvent::BadPacket);
            CHECK(link.waitingForResync());
            CHECK_FALSE(link.replyDue());
            for (int m = 0; m < 9; ++m) CHECK(link.levels()[m] == 3);
        }
    }
    SECTION("a dropped byte: the next packet's first byte completes a misaligned one")
    {
        DeviceLink link = inStep();
        feed(link, {0x11, 0x11, 0x11, 0x18});              // 4 bytes: one lost
        const auto ev = feed(link, {0x22});                 // low nibble 2 ≠ 8
        CHECK(ev.back() == LinkEvent::BadPacket);
        // The rest of that packet: only its last byte (…8) ends the wait.
        const auto ev2 = feed(link, {0x22, 0x22, 0x22, 0x28});
        CHECK(ev2.back() == LinkEvent::Resynced);
        for (int m = 0; m < 9; ++m) CHECK(link.levels()[m] == 0);   // misaligned data never applied
    }
    SECTION("an inserted byte whose low nibble happens to be 8 shifts the frame: caught at the next end")
    {
        DeviceLink link = inStep();
        const auto ev = feed(link, {0x48, 0x11, 0x11, 0x11, 0x11});
        CHECK(ev.back() == LinkEvent::BadPacket);   // 5th byte 0x11: not an end
    }
    SECTION("the host's resync burst 00 00 00 00 08")
    {
        // In step: it is an all-off motor packet.
        DeviceLink link = inStep();
        feed(link, {0xFF, 0xFF, 0xFF, 0xFF, 0xF8});
        uint8_t out[32];
        link.buildReply(kCounts, 0, 0, 0, out, sizeof out);
        auto ev = feed(link, {0x00, 0x00, 0x00, 0x00, 0x08});
        CHECK(ev.back() == LinkEvent::Motor);
        for (int m = 0; m < 9; ++m) CHECK(link.levels()[m] == 0);
        link.buildReply(kCounts, 0, 0, 0, out, sizeof out);
        // Out of step: the zeros are skipped, the 0x08 answered once.
        feed(link, {0x12, 0x34, 0x56, 0x78, 0x91});        // bad → waiting
        ev = feed(link, {0x00, 0x00, 0x00, 0x00, 0x08});
        CHECK(ev == std::vector<LinkEvent> {LinkEvent::None, LinkEvent::None, LinkEvent::None, LinkEvent::None, LinkEvent::Resynced});
        // Mid-packet (k bytes in): the burst ends a bad packet or is read as a packet; never two replies.
        for (int k = 1; k < 5; ++k) {
            DeviceLink l2 = inStep();
            for (int i = 0; i < k; ++i) l2.onByte(0x55, 0);
            int replies = 0;
            for (uint8_t b : {0x00, 0x00, 0x00, 0x00, 0x08}) {
                const LinkEvent e = l2.onByte(b, 0);
                if (e == LinkEvent::Motor || e == LinkEvent::Resynced) ++replies;
            }
            CHECK(replies == 1);
        }
    }
    SECTION("the old resync stream 08 08 08 08 08 after a bad packet: answered once, then read as a packet")
    {
        DeviceLink link = inStep();
        feed(link, {0x12, 0x34, 0x56, 0x78, 0x91});
        const auto ev = feed(link, {0x08, 0x08, 0x08, 0x08, 0x08});
        CHECK(ev[0] == LinkEvent::Resynced);
    }
}

TEST_CASE("firmware v1 link never crashes and never answers without cause on random bytes (fuzz)", "[firmware]")
{
    std::mt19937 rng(1234);
    DeviceLink link;
    uint8_t out[32];
    uint32_t ms = 0;
    for (int i = 0; i < 200000; ++i) {
        const LinkEvent e = link.onByte(static_cast<uint8_t>(rng()), ms);
        if (e == LinkEvent::Motor || e == LinkEvent::Resynced) CHECK(link.replyDue());
        if (link.replyDue()) {
            const uint8_t n = link.buildReply(kCounts, ms * 1000u, 0, 1000, out, sizeof out);
            CHECK((n == 14 || n == 21));
        }
        for (int m = 0; m < 9; ++m) REQUIRE(link.levels()[m] <= 15);
        link.tick(ms);
        if (i % 10 == 0) ++ms;
    }
    // Too small a buffer: no reply is written and the reply stays due.
    DeviceLink l2;
    l2.onByte(0x08, 0);
    CHECK(l2.buildReply(kCounts, 0, 0, 0, out, 13) == 0);
    CHECK(l2.replyDue());
}

TEST_CASE("firmware v2: negotiation with the host codec, frames, CRC, sequence and fallback to v1", "[firmware]")
{
    DeviceLink board;
    dev::FramingV2Host host;
    std::vector<uint8_t> wire;
    host.startNegotiation(wire);
    int replies = 0;
    uint8_t out[32];
    std::vector<dev::SensorFrameV2> frames;
    for (uint8_t b : wire) {
        board.onByte(b, 10);
        if (board.replyDue()) {
            const uint8_t n = board.buildReply(kCounts, 0, 0, 987, out, sizeof out);
            ++replies;
            REQUIRE(n == armfw::kOfferSize);
            for (uint8_t i = 0; i < n; ++i) host.receive(out[i], frames);
        }
    }
    CHECK(replies == 1);
    REQUIRE(host.mode() == dev::FramingV2Host::Mode::V2);
    CHECK(host.offer().sensorRateHz == 987);
    CHECK(host.offer().motors == 9);
    CHECK(board.mode() == DeviceLink::Mode::V2);

    // A v1 host would never accept the offer: its end nibble is F.
    CHECK_FALSE(dev::sensorPacketEndOk(armfw::kOfferEndByte));

    dev::ProtocolLevels lv {1, 2, 3, 4, 5, 6, 7, 8, 9};
    uint32_t t = 1000;
    for (int i = 0; i < 300; ++i) {
        wire.clear();
        host.encodeMotor(lv, wire);
        for (uint8_t b : wire) board.onByte(b, 20 + static_cast<uint32_t>(i));
        REQUIRE(board.replyDue());
        t += 70000;   // 70 ms per frame here: the 24-bit clock wraps (16.8 s) during the run
        const uint8_t n = board.buildReply(kCounts, t, armfw::kStatusHeatLimit, 987, out, sizeof out);
        REQUIRE(n == armfw::kV2SensorSize);
        for (uint8_t k = 0; k < n; ++k) host.receive(out[k], frames);
    }
    for (int m = 0; m < 9; ++m) CHECK(board.levels()[m] == m + 1);
    REQUIRE(frames.size() == 300);
    CHECK(frames.back().deviceTimeUs - frames.front().deviceTimeUs == 299u * 70000u);
    CHECK(frames.back().status == dev::kV2StatusHeatLimit);
    for (int i = 0; i < 9; ++i) CHECK(frames.back().counts[static_cast<size_t>(i)] == kCounts[i]);
    CHECK(host.stats().seqGaps == 0);
    CHECK(host.stats().crcFailures == 0);
    CHECK(board.seqGaps() == 0);

    SECTION("a corrupted motor frame is refused (every single-bit error) and the next one is taken")
    {
        for (size_t byte = 0; byte < armfw::kV2MotorSize; ++byte)
            for (int bit = 0; bit < 8; ++bit) {
                wire.clear();
                host.encodeMotor(dev::ProtocolLevels {15, 15, 15, 15, 15, 15, 15, 15, 15}, wire);
                wire[byte] ^= static_cast<uint8_t>(1u << bit);
                for (uint8_t b : wire) {
                    const LinkEvent e = board.onByte(b, 50);
                    CHECK(e != LinkEvent::Motor);
                }
                CHECK_FALSE(board.replyDue());
                // Flush whatever partial frame the corruption left, with a good frame.
                wire.clear();
                host.encodeMotor(lv, wire);
                bool got = false;
                for (int rep = 0; rep < 2 && !got; ++rep)
                    for (uint8_t b : wire) got = board.onByte(b, 50) == LinkEvent::Motor || got;
                CHECK(got);
                board.buildReply(kCounts, 0, 0, 0, out, sizeof out);
                for (int m = 0; m < 9; ++m) CHECK(board.levels()[m] == m + 1);
            }
        CHECK(board.badFrames() >= 64);   // 72 flips; the 8 that spoil the sync byte are skipped, not framed
    }
    SECTION("a corrupted sensor frame is refused by the host and counted; the next frame is found")
    {
        const uint64_t before = host.stats().frames;
        wire.clear();
        uint8_t f[21];
        armfw::encodeV2Sensor(77, 5, kCounts, 0, f);
        f[10] ^= 0x40;
        for (uint8_t b : f) host.receive(b, frames);
        armfw::encodeV2Sensor(78, 6, kCounts, 0, f);
        for (uint8_t b : f) host.receive(b, frames);
        CHECK(host.stats().crcFailures == 1);
        CHECK(host.stats().frames == before + 1);
        CHECK(host.stats().seqGaps >= 1);   // the frames jumped from the run's sequence to 78
    }
    SECTION("the v2 host goes silent: after 200 ms the board speaks v1 again")
    {
        board.tick(20 + 299 + 100);
        CHECK(board.mode() == DeviceLink::Mode::V2);
        board.tick(20 + 299 + 201);
        CHECK(board.mode() == DeviceLink::Mode::V1);
        CHECK(board.onByte(0x08, 600) == LinkEvent::Resynced);
        CHECK(board.buildReply(kCounts, 0, 0, 0, out, sizeof out) == 14);
    }
    SECTION("the leave flag: the board answers that frame in v2 and then waits in v1")
    {
        wire.clear();
        host.encodeMotor(lv, wire, dev::kV2FlagLeave);
        for (uint8_t b : wire) board.onByte(b, 400);
        CHECK(board.buildReply(kCounts, 0, 0, 0, out, sizeof out) == 21);
        CHECK(board.mode() == DeviceLink::Mode::V1);
        CHECK(board.waitingForResync());
    }
}

TEST_CASE("firmware v2 query can never appear inside a valid v1 motor stream, and a v1 board survives it", "[firmware]")
{
    // Every fifth byte of a v1 stream ends in 8 and no query byte does.
    for (uint8_t q : armfw::kQuery) CHECK((q & 0x0F) != 0x8);
    // A v1-only device (the host's DeviceProtocol, the thesis rule) fed query + burst at any phase
    // answers exactly once and ends with every level 0 or unchanged — never a level from query bytes.
    for (int k = 0; k < 5; ++k) {
        dev::DeviceProtocol v1;
        v1.onByte(0x08);
        for (uint8_t b : {0x33, 0x33, 0x33, 0x33, 0x38}) v1.onByte(b);
        for (int i = 0; i < k; ++i) v1.onByte(0x33);
        std::vector<uint8_t> wire;
        dev::FramingV2Host host;
        host.startNegotiation(wire);
        int answers = 0;
        for (uint8_t b : wire) {
            const auto e = v1.onByte(b);
            if (e == dev::DeviceProtocol::Event::MotorPacket || e == dev::DeviceProtocol::Event::Resynced) ++answers;
        }
        CHECK(answers == 1);
        for (auto l : v1.levels()) CHECK((l == 3 || l == 0));
    }
    // A host negotiating with a v1 board gets a v1 packet back and falls back.
    dev::FramingV2Host host;
    std::vector<uint8_t> wire;
    host.startNegotiation(wire);
    std::vector<dev::SensorFrameV2> frames;
    const auto pkt = dev::encodeSensorPacket(dev::SensorCounts {1, 2, 3, 4, 5, 6, 7, 8, 9});
    for (uint8_t b : pkt) host.receive(b, frames);
    CHECK(host.mode() == dev::FramingV2Host::Mode::V1);
    CHECK(host.hasV1Answer());
}

TEST_CASE("firmware safety: off at power-on, off 50 ms after the last valid packet, heat limit", "[firmware]")
{
    armfw::MotorSafety s;
    uint8_t out[9];
    s.output(0, out);
    for (uint8_t v : out) CHECK(v == 0);
    const uint8_t req[9] = {3, 4, 5, 6, 7, 8, 9, 10, 20};
    s.onPacket(req, 10);
    s.output(10, out);
    for (int m = 0; m < 8; ++m) CHECK(out[m] == req[m]);
    CHECK(out[8] == 15);   // clamped
    s.output(60, out);     // exactly 50 ms: still alive
    CHECK(out[0] == 3);
    s.output(61, out);     // 51 ms: all off
    for (uint8_t v : out) CHECK(v == 0);
    CHECK((s.takeStatus() & armfw::kStatusWatchdog) != 0);
    CHECK((s.takeStatus() & armfw::kStatusWatchdog) == 0);   // reported once
    s.output(200, out);
    for (uint8_t v : out) CHECK(v == 0);   // stays off without a new packet

    SECTION("heat: 1 s above the rating from cold, then held at the rating until the bucket drains")
    {
        armfw::MotorSafety h;
        const uint8_t full[9] = {15, 5, 0, 0, 0, 0, 0, 0, 0};
        uint32_t t = 0;
        uint32_t limitedAt = 0;
        for (; t <= 1500; ++t) {
            h.onPacket(full, t);
            h.output(t, out);
            CHECK(out[1] == 5);   // at the rating: never limited
            if (out[0] < 15 && !limitedAt) limitedAt = t;
        }
        CHECK(limitedAt >= 1000);
        CHECK(limitedAt <= 1002);
        CHECK(out[0] == 5);       // held at the rating while the bucket drains
        // Held at the rating from ~1 s, the bucket (2000 units) drains 1 unit/ms: 500 gone by 1.5 s,
        // the other 1500 by 3.0 s; only then may the motor go above its rating again.
        const uint8_t off[9] = {};
        uint32_t freedAt = 0;
        for (; t <= 5000; ++t) {
            h.onPacket(off, t);
            h.output(t, out);
            if (!h.heatLimited(0) && !freedAt) freedAt = t;
        }
        CHECK(freedAt > 2950);
        CHECK(freedAt < 3050);
    }
    SECTION("a well-behaved host (0.3 s runs, 30 % of any 2 s) is never limited")
    {
        armfw::MotorSafety h;
        uint8_t lv[9] = {};
        for (uint32_t t = 0; t < 60000; ++t) {
            lv[0] = (t % 1000) < 300 ? 15 : 2;
            h.onPacket(lv, t);
            h.output(t, out);
            REQUIRE(out[0] == lv[0]);
        }
    }
    SECTION("a packet stamped just after the caller read its clock is fresh, not expired")
    {
        armfw::MotorSafety h;
        const uint8_t lv[9] = {4, 4, 4, 4, 4, 4, 4, 4, 4};
        h.onPacket(lv, 100);
        h.onPacket(lv, 103);      // arrived in the interrupt during the main loop's I2C read
        h.output(102, out);       // the main loop's clock, read before that
        CHECK(out[0] == 4);
        CHECK((h.takeStatus() & armfw::kStatusWatchdog) == 0);
    }
    SECTION("the millisecond clock wrapping around is harmless")
    {
        armfw::MotorSafety h;
        const uint32_t start = 0xFFFFFFF0u;
        h.reset(start);
        const uint8_t lv[9] = {7, 0, 0, 0, 0, 0, 0, 0, 0};
        for (uint32_t i = 0; i < 40; ++i) {
            h.onPacket(lv, start + i);
            h.output(start + i, out);
            CHECK(out[0] == 7);
        }
    }
}

TEST_CASE("firmware scaling: MPU-9250/AK8963 LSB through the default calibration read back in SI", "[firmware]")
{
    const dev::Calibration cal = dev::defaultCalibration();
    const uint8_t asa[3] = {176, 171, 128};
    int32_t magQ[3];
    armfw::magScales(asa, magQ);
    // A board lying flat, face up, forearm pointing north: MPU z up (1 g = 4096 LSB at ±8 g).
    armfw::ImuRaw raw {};
    raw.accel[2] = 4096;
    raw.gyro[0] = static_cast<int16_t>(std::lround(100.0 * 32.8));   // 100 °/s about MPU x
    // 50 µT along AK y (= MPU x = device x), the chip reading less by its sensitivity (ASA 171).
    raw.mag[1] = static_cast<int16_t>(std::lround(50.0 / 0.15 / ((171 + 128) / 256.0)));
    uint16_t counts[9];
    armfw::toCounts(raw, magQ, counts);
    dev::SensorCounts c {};
    for (int i = 0; i < 9; ++i) c[static_cast<size_t>(i)] = counts[i];
    const armadillo::core::ImuSample s = cal.apply(0.0, c);
    CHECK(s.accel.y() == Approx(9.80665).epsilon(0.005));       // device y = out of the face = up
    CHECK(std::abs(s.accel.x()) < 0.03);
    CHECK(std::abs(s.accel.z()) < 0.03);
    CHECK(s.gyro.x() == Approx(100.0 * 3.14159265 / 180.0).epsilon(0.005));
    CHECK(s.mag.x() == Approx(1.0).epsilon(0.005));
    CHECK(std::abs(s.mag.y()) < 0.005);
    // Axis map: MPU −y is device z; AK z is device −y; AK x is device −z.
    raw = {};
    raw.accel[1] = -4096;
    raw.mag[2] = 333;
    raw.mag[0] = 333;
    armfw::toCounts(raw, magQ, counts);
    CHECK(counts[2] > 2048 + 400);   // device z positive
    CHECK(counts[7] < 2048);         // device y negative
    CHECK(counts[8] < 2048);         // device z negative (AK x positive)
    // Saturation, never wrap-around.
    raw = {};
    raw.accel[0] = 32767;
    raw.accel[1] = -32768;
    raw.gyro[0] = -32768;
    raw.mag[1] = 32767;
    armfw::toCounts(raw, magQ, counts);
    CHECK(counts[0] == 4095);
    CHECK(counts[2] == 4095);
    CHECK(counts[3] == 0);
    CHECK(counts[6] == 4095);
    CHECK(armfw::scaleToCount(0, 1, 16) == 2048);
    CHECK(armfw::scaleToCount(-1, 32768, 16) == 2047);   // −0.5 rounds away from zero
}
