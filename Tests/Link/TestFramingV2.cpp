// The host side of the v2 framing (FramingV2.h): codecs, negotiation outcomes, sync hunting,
// sequence gaps, clock unwrapping, and a fuzz run of the framer. The firmware side and the
// interplay with the real firmware are in Tests/Firmware.
#include "Link/FramingV2.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo::link;

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

#include "Link/HostLink.h"

TEST_CASE("HostLink with negotiateV2: an offer switches to v2 frames, gaps and CRC failures are counted, a reset asks again", "[device][v2]")
{
    using namespace armadillo::link;
    using armadillo::core::MotorLevels;
    struct Peer : LinkPeer {
        std::vector<std::vector<std::uint8_t>> writes;
        std::vector<std::uint64_t> deviceTimes;
        MotorLevels onSensorPacket(const SensorCounts&, double) override { return {}; }
        MotorLevels onSensorFrameV2(const SensorFrameV2& f, double) override
        {
            deviceTimes.push_back(f.deviceTimeUs);
            MotorLevels m {};
            m[2] = 7;
            return m;
        }
        void send(const std::uint8_t* b, std::size_t n) override { writes.emplace_back(b, b + n); }
    } peer;
    LinkConfig cfg;
    cfg.negotiateV2 = true;
    HostLink link(cfg);
    link.reset(0.0);
    link.poll(0.0, peer);
    REQUIRE(peer.writes.size() == 1);
    CHECK(peer.writes[0].size() == 10);
    OfferV2 offer;
    offer.version = 2;
    offer.motors = 9;
    offer.sensorRateHz = 1000;
    const auto o = encodeOfferV2(offer);
    link.receive(o.data(), o.size(), 0.004, peer);
    CHECK(link.stats().v2);
    CHECK(link.framingV2().offer().sensorRateHz == 1000);
    link.poll(0.004, peer);   // the first motor frame: all off
    REQUIRE(peer.writes.size() == 2);
    REQUIRE(peer.writes[1].size() == kV2MotorFrameSize);
    std::uint8_t seq = 0, flags = 0;
    ProtocolLevels lv {};
    REQUIRE(decodeMotorFrameV2(peer.writes[1].data(), seq, lv, flags));
    CHECK(lv == ProtocolLevels {});
    auto frame = [](std::uint8_t s, std::uint32_t us) {
        SensorFrameV2 f;
        f.seq = s;
        f.rawTimeUs = us;
        return encodeSensorFrameV2(f);
    };
    auto f0 = frame(0, 0xFFFF00);
    link.receive(f0.data(), f0.size(), 0.008, peer);
    auto f1 = frame(2, 0x000F00);   // seq 1 lost; the 24-bit clock wrapped
    link.receive(f1.data(), f1.size(), 0.013, peer);
    auto bad = frame(3, 0x001F00);
    bad[10] ^= 0x10;
    link.receive(bad.data(), bad.size(), 0.018, peer);
    CHECK(link.stats().packets == 2);
    CHECK(link.stats().seqGaps == 1);
    CHECK(link.stats().crcFailures == 1);
    CHECK(link.stats().badPackets == 1);
    REQUIRE(peer.deviceTimes.size() == 2);
    CHECK(peer.deviceTimes[1] - peer.deviceTimes[0] == 0x1000);
    REQUIRE(peer.writes.size() == 4);   // each good frame answered with the handler's levels
    REQUIRE(decodeMotorFrameV2(peer.writes[3].data(), seq, lv, flags));
    CHECK(lv[2] == 7);
    // A new connection negotiates again.
    link.reset(1.0);
    CHECK_FALSE(link.stats().v2);
    link.poll(1.0, peer);
    REQUIRE(peer.writes.size() == 5);
    CHECK(peer.writes[4].size() == 10);
}
