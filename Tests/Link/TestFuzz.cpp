// Deterministic random-input fuzzing of every parser on the device path (≥ 10⁶ inputs each for the
// packet parser): the host link state machine fed arbitrary bytes at arbitrary times, the device
// side, the packet decoders, the OSC decoder and the calibration JSON reader. Invariants, not
// just "no crash": only packets with a 0x0 end nibble are delivered, every delivered packet
// re-encodes to the bytes that carried it, buffers stay bounded.
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Link/DeviceProtocol.h"
#include "Link/HostLink.h"
#include "Core/Json.h"
#include "Osc/Osc.h"
#include "Osc/OscIo.h"
#include <catch2/catch.hpp>
#include <deque>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::osc;
using namespace armadillo::link;

namespace {

struct CheckingPeer : LinkPeer {
    std::uint64_t delivered = 0, bytesSent = 0;
    std::deque<std::uint8_t> recent;   // the last 14 bytes fed (to check what was delivered)
    bool mismatch = false;
    bool checking = true;
    MotorLevels onSensorPacket(const SensorCounts& c, double) override
    {
        ++delivered;
        if (!checking) return MotorLevels {};
        const SensorPacketBytes again = encodeSensorPacket(c);
        if (recent.size() < kSensorPacketSize) mismatch = true;
        else
            for (std::size_t i = 0; i < kSensorPacketSize; ++i)
                if (again[i] != recent[recent.size() - kSensorPacketSize + i]) mismatch = true;
        MotorLevels m {};
        m[0] = static_cast<std::uint8_t>(delivered % 16);
        return m;
    }
    void send(const std::uint8_t*, std::size_t n) override { bytesSent += n; }
};

} // namespace

TEST_CASE("fuzz: host link state machine on 10^6 random inputs", "[device][fuzz]")
{
    std::mt19937_64 rng(20051);
    HostLink link;
    CheckingPeer peer;
    link.reset(0.0);
    double t = 0.0;
    std::uniform_int_distribution<int> byte(0, 255), len(1, 40), kind(0, 9);
    std::exponential_distribution<double> gap(1000.0);   // mean 1 ms between chunks
    std::uint64_t inputs = 0, fed = 0;
    SensorCounts c {};
    while (inputs < 1000000) {
        std::uint8_t chunk[64];
        int n = len(rng);
        const int k = kind(rng);
        if (k < 4) {
            // A valid packet, sometimes with the end nibble damaged, sometimes split.
            for (auto& v : c) v = static_cast<std::uint16_t>(rng() & 0xFFF);
            auto p = encodeSensorPacket(c);
            if (k == 0) p[13] ^= static_cast<std::uint8_t>(byte(rng) & 0x0F);
            n = static_cast<int>(kSensorPacketSize);
            std::copy(p.begin(), p.end(), chunk);
        } else {
            for (int i = 0; i < n; ++i) chunk[i] = static_cast<std::uint8_t>(byte(rng));
        }
        t += gap(rng);
        // Feed byte by byte sometimes, whole chunks otherwise (both paths must agree on framing).
        if (k == 9) {
            for (int i = 0; i < n; ++i) {
                peer.recent.push_back(chunk[i]);
                if (peer.recent.size() > 64) peer.recent.pop_front();
                link.receive(chunk + i, 1, t, peer);
            }
        } else {
            // Whole chunk at once: a chunk can hold several packets, so the byte check is off here.
            peer.checking = false;
            link.receive(chunk, static_cast<std::size_t>(n), t, peer);
            peer.checking = true;
            for (int i = 0; i < n; ++i) {
                peer.recent.push_back(chunk[i]);
                if (peer.recent.size() > 64) peer.recent.pop_front();
            }
        }
        fed += static_cast<std::uint64_t>(n);
        if (rng() % 3 == 0) link.poll(t + gap(rng), peer);
        REQUIRE(std::isfinite(link.nextDeadline()));
        ++inputs;
    }
    const LinkStats& s = link.stats();
    CHECK_FALSE(peer.mismatch);
    CHECK(s.packets == peer.delivered);
    CHECK(s.bytesIn == fed);
    // Every byte fed is accounted for: in a delivered packet, a bad frame, discarded, or the
    // (at most 13-byte) frame in progress.
    CHECK(s.packets * kSensorPacketSize + s.discardedBytes <= fed);
    CHECK(fed - (s.packets * kSensorPacketSize + s.discardedBytes) < kSensorPacketSize);
    CHECK(s.packets > 10000);   // garbage between packets costs many (draining waits for quiet)
    CHECK(s.badPackets > 10000);
}

TEST_CASE("fuzz: packet decoders and the device side on 10^6 random inputs", "[device][fuzz]")
{
    std::mt19937_64 rng(77);
    DeviceProtocol device;
    std::uint64_t answers = 0;
    for (int i = 0; i < 1000000; ++i) {
        std::uint8_t bytes[kSensorPacketSize];
        for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
        SensorCounts c {};
        const bool ok = decodeSensorPacket(bytes, c);
        REQUIRE(ok == ((bytes[13] & 0x0F) == 0));
        // The decoded counts carry every payload bit: re-encoding gives the bytes back.
        const auto again = encodeSensorPacket(c);
        for (std::size_t k = 0; k < 13; ++k) REQUIRE(again[k] == bytes[k]);
        REQUIRE((again[13] & 0xF0) == (bytes[13] & 0xF0));
        for (const auto v : c) REQUIRE(v <= kMaxCount);
        ProtocolLevels l {};
        REQUIRE(decodeMotorPacket(bytes, l) == ((bytes[4] & 0x0F) == 0x8));
        for (const auto v : l) REQUIRE(v <= 15);
        const auto e = device.onByte(bytes[0]);
        if (e == DeviceProtocol::Event::MotorPacket || e == DeviceProtocol::Event::Resynced) ++answers;
    }
    CHECK(answers > 10000);
}

TEST_CASE("fuzz: OSC decoder on 10^6 random and mutated datagrams", "[device][fuzz][osc]")
{
    std::mt19937_64 rng(4242);
    const std::vector<std::vector<std::uint8_t>> seeds {
        encodeOscMessage("/armadillo/imu", std::vector<OscArg>(9, OscArg::float32(0.5f))),
        encodeOscMessage("/armadillo/orientation", {OscArg::float32(1), OscArg::float32(0), OscArg::float32(0), OscArg::float32(0)}),
        encodeOscMessage("/x", {OscArg::string("hello"), OscArg::blob("blob!"), OscArg::int32(-3), OscArg::float64(2.5)}),
        encodeOscBundle(1, {encodeOscMessage("/a", {OscArg::int32(1)}),
                            encodeOscBundle(2, {encodeOscMessage("/b", {OscArg::string("s")})})}),
    };
    OscReceiver receiver(0, [](const ImuSample& s) { REQUIRE(s.gyro.allFinite()); }, [](double, const Eigen::Quaterniond& q) {
        REQUIRE(std::abs(q.norm() - 1.0) < 1e-9);
    });
    std::uint64_t decoded = 0, refused = 0;
    std::vector<std::uint8_t> buf;
    for (int i = 0; i < 1000000; ++i) {
        if (rng() % 4 == 0) {
            buf.resize(rng() % 96);
            for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
            if (!buf.empty() && rng() % 2) buf[0] = (rng() % 2) ? '/' : '#';
        } else {
            buf = seeds[rng() % seeds.size()];
            const int edits = 1 + static_cast<int>(rng() % 4);
            for (int e = 0; e < edits && !buf.empty(); ++e) {
                switch (rng() % 4) {
                case 0: buf[rng() % buf.size()] = static_cast<std::uint8_t>(rng()); break;
                case 1: buf.resize(rng() % (buf.size() + 1)); break;
                case 2: buf.insert(buf.begin() + static_cast<long>(rng() % (buf.size() + 1)), static_cast<std::uint8_t>(rng())); break;
                default: buf[rng() % buf.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8)); break;
                }
            }
        }
        std::string error;
        int messages = 0;
        const bool ok = decodeOscPacket(buf.data(), buf.size(), [&](const OscMessage& m) {
            ++messages;
            REQUIRE(!m.address.empty());
            REQUIRE(m.address[0] == '/');
            REQUIRE(m.count <= kOscMaxArgs);
            for (int a = 0; a < m.count; ++a) {
                // Views must lie inside the datagram.
                if (!m.args[a].bytes.empty()) {
                    const auto* p = reinterpret_cast<const std::uint8_t*>(m.args[a].bytes.data());
                    REQUIRE(p >= buf.data());
                    REQUIRE(p + m.args[a].bytes.size() <= buf.data() + buf.size());
                }
            }
        }, &error);
        if (ok) ++decoded;
        else {
            ++refused;
            REQUIRE_FALSE(error.empty());
        }
        receiver.handleDatagram(buf.data(), buf.size(), 0.0);
    }
    CHECK(decoded > 1000);
    CHECK(refused > 100000);
    CHECK(receiver.stats().datagrams == 1000000);
}

TEST_CASE("fuzz: calibration JSON reader refuses mutated files cleanly", "[device][fuzz][calibration]")
{
    std::mt19937_64 rng(9);
    const std::string valid = calibrationToJson(defaultCalibration());
    int accepted = 0, refused = 0;
    for (int i = 0; i < 100000; ++i) {
        std::string s = valid;
        const int edits = 1 + static_cast<int>(rng() % 3);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % (s.size() + 1);
            switch (rng() % 3) {
            case 0: if (at < s.size()) s[at] = static_cast<char>(rng() % 128); break;
            case 1: s.insert(s.begin() + static_cast<long>(at), "{}[],:\"0e-"[rng() % 10]); break;
            default: s.erase(at, rng() % 4); break;
            }
        }
        try {
            const Calibration c = parseCalibration(s, "fuzz.json");
            REQUIRE(c.accel.scale.allFinite());
            ++accepted;
        } catch (const InputError& e) {
            REQUIRE(std::string(e.what()).find("fuzz.json") != std::string::npos);
            ++refused;
        }
    }
    CHECK(refused > 1000);
    CHECK(accepted > 10);
    // Deep nesting is refused, not a stack overflow.
    CHECK_THROWS_AS(parseJson(std::string(100000, '['), "deep.json"), InputError);
}
