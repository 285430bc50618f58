// Packet codec against hand-computed byte vectors (thesis Table 2-2, ARMADILLO.md §2 decisions).
#include "Link/Packets.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;

TEST_CASE("sensor packet: MSB-first 12-bit samples ax..mz then end nibble 0x0", "[device][packets]")
{
    // Nibbles 1 2 3 | 4 5 6 | 7 8 9 | A B C | D E F | 0 1 2 | 3 4 5 | 6 7 8 | 9 A B | end 0.
    const SensorCounts counts {0x123, 0x456, 0x789, 0xABC, 0xDEF, 0x012, 0x345, 0x678, 0x9AB};
    const SensorPacketBytes expected {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xF0, 0x12, 0x34, 0x56, 0x78, 0x9A, 0xB0};
    CHECK(encodeSensorPacket(counts) == expected);
    SensorCounts back {};
    CHECK(decodeSensorPacket(expected.data(), back));
    CHECK(back == counts);
}

TEST_CASE("sensor packet: extremes and single bits land where the bit order says", "[device][packets]")
{
    SensorCounts full;
    full.fill(4095);
    SensorPacketBytes allOnes;
    allOnes.fill(0xFF);
    allOnes[13] = 0xF0;
    CHECK(encodeSensorPacket(full) == allOnes);

    SensorCounts zero {};
    SensorPacketBytes zeros {};
    CHECK(encodeSensorPacket(zero) == zeros);

    // ax's most significant bit is the first bit of the stream; mz's least significant bit is bit 4 of byte 13.
    SensorCounts ax {};
    ax[kAx] = 0x800;
    CHECK(encodeSensorPacket(ax)[0] == 0x80);
    SensorCounts mz {};
    mz[kMz] = 0x001;
    const auto b = encodeSensorPacket(mz);
    CHECK(b[12] == 0x00);
    CHECK(b[13] == 0x10);
    // gx starts on a byte boundary (byte 4.5 → 36 bits = byte 4, low nibble).
    SensorCounts gx {};
    gx[kGx] = 0xFFF;
    const auto g = encodeSensorPacket(gx);
    CHECK(g[4] == 0x0F);
    CHECK(g[5] == 0xFF);
    CHECK(g[3] == 0x00);
    CHECK(g[6] == 0x00);
}

TEST_CASE("sensor packet: counts above 12 bits are masked, bad end nibble is reported", "[device][packets]")
{
    SensorCounts c {};
    c[kAx] = 0xF123;
    CHECK(encodeSensorPacket(c)[0] == 0x12);
    SensorPacketBytes p = encodeSensorPacket(SensorCounts {1, 2, 3, 4, 5, 6, 7, 8, 9});
    SensorCounts out {};
    REQUIRE(decodeSensorPacket(p.data(), out));
    for (std::uint8_t nib = 1; nib < 16; ++nib) {
        p[13] = static_cast<std::uint8_t>((p[13] & 0xF0) | nib);
        CHECK_FALSE(decodeSensorPacket(p.data(), out));
    }
}

TEST_CASE("motor packet: motor 1 in the high nibble of byte 0, motor 9 then 0x8", "[device][packets]")
{
    ProtocolLevels levels {1, 2, 3, 4, 5, 6, 7, 8, 9};
    const MotorPacketBytes expected {0x12, 0x34, 0x56, 0x78, 0x98};
    CHECK(encodeMotorPacket(levels) == expected);
    ProtocolLevels back {};
    CHECK(decodeMotorPacket(expected.data(), back));
    CHECK(back == levels);

    MotorLevels all {};
    all.fill(15);
    CHECK(encodeMotorPacket(all) == MotorPacketBytes {0xFF, 0xFF, 0xFF, 0xFF, 0xF8});
    CHECK(encodeMotorPacket(MotorLevels {}) == MotorPacketBytes {0x00, 0x00, 0x00, 0x00, 0x08});

    // Out-of-range levels clamp to 15 instead of wrapping into a weak level; motors 10+ are not sent.
    MotorLevels wild {};
    wild[0] = 20;
    wild[9] = 15;
    CHECK(encodeMotorPacket(wild) == MotorPacketBytes {0xF0, 0x00, 0x00, 0x00, 0x08});

    MotorPacketBytes bad = expected;
    bad[4] = 0x90;
    CHECK_FALSE(decodeMotorPacket(bad.data(), back));
}

TEST_CASE("packets round-trip for random contents", "[device][packets]")
{
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> count(0, 4095), level(0, 15);
    for (int i = 0; i < 100000; ++i) {
        SensorCounts c;
        for (auto& v : c) v = static_cast<std::uint16_t>(count(rng));
        SensorCounts d {};
        REQUIRE(decodeSensorPacket(encodeSensorPacket(c).data(), d));
        REQUIRE(d == c);
        ProtocolLevels l;
        for (auto& v : l) v = static_cast<std::uint8_t>(level(rng));
        ProtocolLevels m {};
        REQUIRE(decodeMotorPacket(encodeMotorPacket(l).data(), m));
        REQUIRE(m == l);
    }
}

TEST_CASE("lock-step theoretical rate at 57600 baud is about 303 updates/s", "[device][packets]")
{
    CHECK(lockStepRate(57600.0) == Approx(57600.0 / 190.0));
    CHECK(lockStepRate(57600.0) == Approx(303.16).epsilon(1e-3));
}
