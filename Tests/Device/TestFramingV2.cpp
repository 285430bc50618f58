// The host side of the v2 framing (FramingV2.h): codecs, negotiation outcomes, sync hunting,
// sequence gaps, clock unwrapping, and a fuzz run of the framer. The firmware side and the
// interplay with the real firmware are in Tests/Firmware.
#include "Device/FramingV2.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo::device;

TEST_CASE("FramingV2 codecs round-trip and refuse every corrupted byte", "[device][v2]")
{
    CHECK(crc16Ccitt(reinterpret_cast<const std::uint8_t*>("123456789"), 9) == 0x29B1);
    OfferV2 o {2, 9, 1000};
    auto ob = encodeOfferV2(o);
    OfferV2 back {};
    REQUIRE(decodeOfferV2(ob.data(), back));
    CHECK(back.sensorRateHz == 1000);
    CHECK_FALSE(sensorPacketEndOk(ob[13]));   // a v1 framer rejects an offer
    for (std::size_t i = 0; i < ob.size(); ++i) {
        auto bad = ob;
        bad[i] ^= 0x10;
        CHECK_FALSE(decodeOfferV2(bad.data(), back));
    }
    SensorFrameV2 f;
    f.seq = 200;
    f.rawTimeUs = 0xABCDEF;
    f.counts = {1, 2, 3, 4095, 5, 6, 7, 8, 2048};
    f.status = kV2StatusHeatLimit;
    auto fb = encodeSensorFrameV2(f);
    SensorFrameV2 g;
    REQUIRE(decodeSensorFrameV2(fb.data(), g));
    CHECK(g.seq == 200);
    CHECK(g.rawTimeUs == 0xABCDEF);
    CHECK(g.counts == f.counts);
    CHECK(g.status == kV2StatusHeatLimit);
    for (std::size_t i = 0; i < fb.size(); ++i)
        for (int bit = 0; bit < 8; ++bit) {
            auto bad = fb;
            bad[i] ^= static_cast<std::uint8_t>(1 << bit);
            CHECK_FALSE(decodeSensorFrameV2(bad.data(), g));
        }
    std::uint8_t seq = 0, flags = 0;
    ProtocolLevels lv {};
    auto mb = encodeMotorFrameV2(9, ProtocolLevels {1, 2, 3, 4, 5, 6, 7, 8, 99}, kV2FlagLeave);
    REQUIRE(decodeMotorFrameV2(mb.data(), seq, lv, flags));
    CHECK(seq == 9);
    CHECK(lv[8] == 15);   // clamped, never wrapped
    CHECK(flags == kV2FlagLeave);
}

TEST_CASE("FramingV2Host: negotiation outcomes, sync hunting, gaps and the 24-bit clock", "[device][v2]")
{
    std::vector<SensorFrameV2> frames;
    SECTION("a v1 board answers: fall back, keep its packet")
    {
        FramingV2Host h;
        std::vector<std::uint8_t> out;
        h.startNegotiation(out);
        REQUIRE(out.size() == 10);
        CHECK(out.back() == 0x08);
        for (auto b : encodeSensorPacket(SensorCounts {9, 8, 7, 6, 5, 4, 3, 2, 1})) h.receive(b, frames);
        CHECK(h.mode() == FramingV2Host::Mode::V1);
        CHECK(h.hasV1Answer());
    }
    SECTION("garbage answers: fall back without a v1 packet")
    {
        FramingV2Host h;
        std::vector<std::uint8_t> out;
        h.startNegotiation(out);
        for (int i = 0; i < 14; ++i) h.receive(0x5F, frames);
        CHECK(h.mode() == FramingV2Host::Mode::V1);
        CHECK_FALSE(h.hasV1Answer());
    }
    SECTION("v2: garbage before a frame is skipped, gaps counted, the clock unwrapped")
    {
        FramingV2Host h;
        std::vector<std::uint8_t> out;
        h.startNegotiation(out);
        for (auto b : encodeOfferV2(OfferV2 {2, 9, 1000})) h.receive(b, frames);
        REQUIRE(h.mode() == FramingV2Host::Mode::V2);
        for (std::uint8_t b : {0x00, 0x3C, 0x11, 0x22}) h.receive(b, frames);   // a false sync included
        SensorFrameV2 f;
        const std::uint8_t seqs[4] = {10, 11, 13, 14};
        const std::uint32_t times[4] = {0xFFFF00, 0xFFFFF0, 0x000010, 0x000100};   // wraps
        for (int i = 0; i < 4; ++i) {
            f.seq = seqs[i];
            f.rawTimeUs = times[i];
            for (auto b : encodeSensorFrameV2(f)) h.receive(b, frames);
        }
        REQUIRE(frames.size() == 4);
        CHECK(h.stats().seqGaps == 1);
        CHECK(h.stats().crcFailures >= 1);   // the false sync's frame
        CHECK(frames[3].deviceTimeUs - frames[0].deviceTimeUs == 0x1000100u - 0xFFFF00u);
    }
}

TEST_CASE("FramingV2Host survives 10^6 random bytes in every mode", "[device][v2][fuzz]")
{
    std::mt19937 rng(99);
    FramingV2Host h;
    std::vector<SensorFrameV2> frames;
    std::vector<std::uint8_t> out;
    for (int i = 0; i < 1000000; ++i) {
        if (i % 100000 == 0) {
            out.clear();
            h.startNegotiation(out);
            for (auto b : encodeOfferV2(OfferV2 {2, 9, 500})) h.receive(b, frames);
        }
        h.receive(static_cast<std::uint8_t>(rng()), frames);
        if (frames.size() > 1000) frames.clear();
    }
    CHECK(h.mode() == FramingV2Host::Mode::V2);
    CHECK(h.stats().discardedBytes > 0);
}
