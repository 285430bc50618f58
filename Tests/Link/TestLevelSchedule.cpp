// The motor budget on the packet timeline (issue 13): a host computes the control ticks of each
// audio block back to back (block sizes 64…8192), sometimes stalls for 0.1–2 s, stops and starts
// its transport; the safety stage limits each tick's levels; the LevelSchedule hands them to a
// link that writes a motor packet every lock-step exchange. The bounds are measured on the packets
// the link wrote (time, levels) with the independent checker of Tests/Tactile/Bounds.h.
#include "../Tactile/Bounds.h"
#include "Link/LevelSchedule.h"
#include "Link/Packets.h"
#include "Tactile/TactileEngine.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;
using namespace armadillo::link;

namespace {

struct PacketLog {
    std::vector<MotorLevels> levels;
    std::vector<double> hold;   ///< s each packet stays on (until the next one)
};

/// `seconds` of a host asking for level 15 on every motor (the worst a scene can ask) in blocks of
/// `block` samples at 48 kHz, 200 control ticks a second computed at the block's start, and a link
/// writing a packet every ~3.3 ms (±20 % jitter). `stall(t)` returns how long the host stalls
/// before the block it would compute at wall time t (0: none); while `transportStopped(t)` the
/// host asks for nothing.
PacketLog run(int block, double seconds, const std::function<double(double)>& stall,
              const std::function<bool(double)>& transportStopped, std::uint64_t seed)
{
    constexpr double kRate = 48000.0;
    const int tickSamples = 240;   // 200 Hz
    SafetyStage safety;
    safety.prepare(kDefaultSafetyParams, kGridMotors);
    LevelSchedule schedule;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> jitter(0.8, 1.2);
    PacketLog log;
    double wall = 0.0;            // host's wall clock: when it computes the next block
    double nextPacket = 0.0;
    double lastPacket = -1.0;
    long sampleInTick = 0;
    double lastStamp = -1.0;
    auto linkUntil = [&](double until) {
        while (nextPacket < until) {
            const MotorLevels l = schedule.due(nextPacket);
            if (lastPacket >= 0.0) log.hold.push_back(nextPacket - lastPacket);
            log.levels.push_back(l);
            lastPacket = nextPacket;
            nextPacket += 1.0 / lockStepRate(57600.0) * jitter(rng);
        }
    };
    while (wall < seconds) {
        const double s = stall(wall);
        if (s > 0.0) wall += s;   // nothing is computed meanwhile; the link keeps writing
        linkUntil(wall);
        // The whole block's ticks now, back to back, each stamped with its place in the block.
        MotorLevels request {};
        if (!transportStopped(wall))
            for (int m = 0; m < kGridMotors; ++m) request[static_cast<std::size_t>(m)] = 15;
        for (int i = 0; i < block; ++i) {
            if (sampleInTick++ % tickSamples != 0) continue;
            // The stage charges the previous output with what the motor really got: its tick, or
            // after a stall the time until the link went all-off (LevelSchedule::onTime).
            const double stamp = wall + i / kRate;
            const double onTime = lastStamp < 0.0 ? tickSamples / kRate : schedule.onTime(lastStamp, stamp);
            const MotorLevels out = safety.process(request, onTime);
            schedule.push(stamp, out);
            lastStamp = stamp;
        }
        wall += block / kRate;
    }
    linkUntil(wall);
    log.hold.push_back(1.0 / lockStepRate(57600.0));
    return log;
}

} // namespace

TEST_CASE("level schedule: levels leave when their tick's time comes; stale ones become all-off", "[device][schedule]")
{
    LevelSchedule s;
    MotorLevels a {}, b {};
    a[0] = 9;
    b[0] = 4;
    REQUIRE(s.push(1.000, a));
    REQUIRE(s.push(1.005, b));
    CHECK(s.due(0.999)[0] == 0);     // nothing due yet
    CHECK(s.due(1.001)[0] == 0);     // due now, but a rise waits one packet
    CHECK(s.due(1.004)[0] == 9);
    CHECK(s.due(1.006)[0] == 4);     // a fall never waits
    CHECK(s.due(1.029)[0] == 4);     // 24 ms old: still on
    CHECK(s.due(1.031)[0] == 0);     // 26 ms old: all off
    CHECK(s.staleOffs() == 1);
    REQUIRE(s.push(1.040, a));
    CHECK(s.due(1.041)[0] == 0);
    CHECK(s.due(1.042)[0] == 9);
    s.allOff();                      // disconnect / shutdown: off at once, queued levels forgotten
    REQUIRE(s.push(1.045, a));       // (pushed after the request: forgotten too, it was queued)
    CHECK(s.due(1.043)[0] == 0);
    CHECK(s.due(1.046)[0] == 0);
    CHECK(s.due(1.047)[0] == 0);
    REQUIRE(s.push(1.050, a));       // the next level after the request plays again
    CHECK(s.due(1.051)[0] == 0);
    CHECK(s.due(1.052)[0] == 9);
}

TEST_CASE("level schedule: the motor budget holds on the packet timeline at every block size, stall and transport change",
          "[device][schedule][safety]")
{
    // The probe first: the same host with the old rule (the link sends the newest level computed,
    // whatever its time) holds a 8192-sample block's last level for 170 ms and a stalled host's
    // for the whole stall, which the checker must see.
    {
        SafetyStage safety;
        safety.prepare(kDefaultSafetyParams, kGridMotors);
        MotorLevels request {};
        request.fill(15);
        std::vector<MotorLevels> packets;
        std::vector<double> hold;
        const double period = 1.0 / lockStepRate(57600.0);
        for (int blockIndex = 0; blockIndex < 60; ++blockIndex) {
            MotorLevels newest {};
            for (int tick = 0; tick < 34; ++tick) newest = safety.process(request, 0.005);   // 8192 samples
            for (double t = 0.0; t < 8192 / 48000.0; t += period) {
                packets.push_back(newest);
                hold.push_back(period);
            }
        }
        const test::BoundsReport old = test::measureBounds(packets, hold);
        INFO("old rule: longest run above the rating " << old.maxAboveRun << " s, worst 10 s mean power " << old.maxMeanPower);
        CHECK_FALSE(test::withinBounds(old));
    }

    test::BoundsReport worst {};
    for (const int block : {64, 128, 256, 512, 1024, 2048, 4096, 8192}) {
        for (const double stallSeconds : {0.0, 0.1, 0.5, 2.0}) {
            // Stalls every 3 s, the transport stopped for 1 s in every 7 s.
            auto stall = [&](double t) { return stallSeconds > 0.0 && std::fmod(t, 3.0) < block / 48000.0 ? stallSeconds : 0.0; };
            auto stopped = [](double t) { return std::fmod(t, 7.0) > 6.0; };
            const PacketLog log = run(block, 40.0, stall, stopped, static_cast<std::uint64_t>(block) + 7);
            const test::BoundsReport r = test::measureBounds(log.levels, log.hold);
            INFO("block " << block << ", stalls of " << stallSeconds << " s: longest above-rating run " << r.maxAboveRun
                          << " s, worst 2 s share " << r.maxAboveInWindow / kDefaultSafetyParams.aboveRatingWindow
                          << ", worst 10 s mean power " << r.maxMeanPower << ", longest on-run " << r.maxOnRun << " s");
            CHECK(test::withinBounds(r));
            worst.maxAboveRun = std::max(worst.maxAboveRun, r.maxAboveRun);
            worst.maxAboveInWindow = std::max(worst.maxAboveInWindow, r.maxAboveInWindow);
            worst.maxMeanPower = std::max(worst.maxMeanPower, r.maxMeanPower);
            worst.maxOnRun = std::max(worst.maxOnRun, r.maxOnRun);
        }
    }
    const SafetyParams& p = kDefaultSafetyParams;
    WARN("worst on the packet timeline: above-rating run " << worst.maxAboveRun << " s (limit " << p.maxAboveRatingRun
         << "), 2 s share " << worst.maxAboveInWindow / p.aboveRatingWindow << " (limit " << p.maxAboveRatingFraction
         << "), 10 s mean power " << worst.maxMeanPower << " (limit " << p.maxMeanPower << "), on-run " << worst.maxOnRun
         << " s (limit " << p.maxOnRun << ")");
}
