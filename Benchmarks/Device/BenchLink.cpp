// Link throughput and latency over a real pseudo-terminal (SerialPort termios path + DeviceLink
// thread ↔ simulated forearm):
//  1. paced like a 57 600-baud 8N1 wire: sustained updates/s as a fraction of the lock-step
//     theoretical rate (19 bytes × 10 bits per update ⇒ ≈ 303/s; target ≥ 0.95);
//  2. unpaced: how fast the host side can go (target ≥ 5 000 updates/s);
//  3. sensor-packet arrival → motor-packet written, on the link thread (target < 1 ms).
// Prints numbers; never passes or fails on time. Usage: bench_device [seconds per run, default 5]
#include "Link/Calibration.h"
#include "Link/DeviceLink.h"
#include "Link/Simulator.h"
#include <algorithm>
#include <cstdio>
#include <mutex>
#include <vector>
#include <cstdlib>
#include <string>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;

namespace {

struct Result {
    double rate = 0.0;
    LatencySummary latency;
    LinkStats stats;
};

Result run(double baud, double seconds)
{
    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/bench-device-pty-" + std::to_string(::getpid());
    SimulatorOptions o;
    o.baud = baud;
    o.realtimePriority = 10;
    DeviceLinkOptions lo;
    lo.realtimePriority = 20;
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), o);
    sim.startPty(path);
    const Calibration cal = defaultCalibration();
    volatile double sink = 0.0;
    // The handler does what the live session's cheapest path does: counts → SI.
    DeviceLink link(std::make_unique<SerialPort>(path, 57600), [&](const SensorCounts& c, double t) {
        const ImuSample s = cal.apply(t, c);
        sink = sink + s.accel.x();
        return MotorLevels {};
    }, lo);
    link.start();
    link.waitFor([](const LinkStats& s) { return s.packets >= 50; }, 30.0);   // warm up, in step
    const LinkStats a = link.stats();
    link.waitFor([&](const LinkStats& s) { return s.lastPacketTime - a.lastPacketTime >= seconds; }, seconds + 30.0);
    const LinkStats b = link.stats();
    link.stop();
    sim.stop();
    Result r;
    r.stats = b;
    const double span = b.lastPacketTime - a.lastPacketTime;
    r.rate = span > 0 ? static_cast<double>(b.packets - a.packets) / span : 0.0;
    r.latency = link.latency();
    return r;
}

void print(const char* name, const Result& r)
{
    std::printf("%-28s %9.1f updates/s   latency µs: mean %.1f  p50 %.0f  p99 %.0f  max %.0f   (packets %llu, bad %llu, resyncs %llu)\n", name,
                r.rate, r.latency.meanUs, r.latency.p50Us, r.latency.p99Us, r.latency.maxUs,
                static_cast<unsigned long long>(r.stats.packets), static_cast<unsigned long long>(r.stats.badPackets),
                static_cast<unsigned long long>(r.stats.resyncs));
}

/// Recovery times over the pty: end-nibble corruption → next good packet, and unplug → port back
/// → first good packet (the targets are "within two packets" and "within 1 s").
void recovery(int rounds)
{
    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/bench-device-rec-" + std::to_string(::getpid());
    SimulatorOptions o;
    o.baud = 57600.0;
    o.stampSequence = true;
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), o);
    sim.startPty(path);
    std::mutex m;
    std::vector<std::pair<std::chrono::steady_clock::time_point, int>> got;
    DeviceLink link(std::make_unique<SerialPort>(path, 57600), [&](const SensorCounts& c, double) {
        std::lock_guard<std::mutex> l(m);
        got.emplace_back(std::chrono::steady_clock::now(), c[kAx]);
        return MotorLevels {};
    });
    link.start();
    double worstSync = 0.0, worstReconnect = 0.0;
    int worstLost = 0;
    for (int r = 0; r < rounds; ++r) {
        const auto before = link.stats().packets;
        link.waitFor([&](const LinkStats& s) { return s.packets >= before + 30; }, 30.0);
        std::size_t mark;
        {
            std::lock_guard<std::mutex> l(m);
            mark = got.size();
        }
        sim.corruptNextEndNibble();
        const auto t0 = std::chrono::steady_clock::now();
        const auto bad = link.stats().badPackets;
        const bool ok = link.waitFor([&](const LinkStats& s) { return s.badPackets > bad && s.inSync && s.packets > before + 32; }, 30.0);
        if (std::getenv("BENCH_DEBUG")) {
            std::lock_guard<std::mutex> l(m);
            std::printf("ok %d bad %llu mark %zu size %zu:", ok, (unsigned long long) link.stats().badPackets, mark, got.size());
            for (std::size_t i = mark > 2 ? mark - 2 : 0; i < got.size(); ++i) std::printf(" %d", got[i].second);
            std::printf("\n");
        }
        {
            std::lock_guard<std::mutex> l(m);
            for (std::size_t i = std::max<std::size_t>(mark, 1); i < got.size(); ++i) {
                const int step = (got[i].second - got[i - 1].second + 4096) % 4096;
                if (step != 1) {
                    worstLost = std::max(worstLost, step - 1);
                    worstSync = std::max(worstSync, std::chrono::duration<double>(got[i].first - t0).count());
                    break;
                }
            }
        }
        const auto conns = sim.stats().connections;
        sim.disconnectFor(0.3);
        sim.waitFor([&](const SimulatorStats& s) { return s.connections > conns; }, 30.0);
        const auto plugged = sim.stats().lastPlug;
        const auto rec = link.stats().reconnects;
        link.waitFor([&](const LinkStats& s) { return s.reconnects > rec && s.inSync; }, 30.0);
        std::lock_guard<std::mutex> l(m);
        for (const auto& [t, seq] : got)
            if (t > plugged) {
                worstReconnect = std::max(worstReconnect, std::chrono::duration<double>(t - plugged).count());
                break;
            }
        got.erase(got.begin(), got.end() - 1);
    }
    link.stop();
    sim.stop();
    std::printf("recovery over %d rounds: corruption -> back in step after at most %d lost packet(s), worst %.1f ms (target: 2 packets)\n",
                rounds, worstLost, worstSync * 1e3);
    std::printf("                      port back -> first good packet, worst %.0f ms (target < 1000 ms)\n", worstReconnect * 1e3);
}

} // namespace

int main(int argc, char** argv)
{
    const double seconds = argc > 1 ? std::atof(argv[1]) : 5.0;
    const double theoretical = lockStepRate(57600.0);
    const Result paced = run(57600.0, seconds);
    print("pty, 57600-baud pacing:", paced);
    std::printf("  lock-step theoretical %.1f updates/s  ->  sustained fraction %.3f  (target >= 0.95); overhead beyond the wire %.0f us/update\n",
                theoretical, paced.rate / theoretical, paced.rate > 0 ? (1.0 / paced.rate - 1.0 / theoretical) * 1e6 : 0.0);
    std::printf("  (load average now: ");
    if (FILE* f = std::fopen("/proc/loadavg", "r")) {
        char buf[64] = {};
        if (std::fgets(buf, sizeof buf, f)) std::printf("%.*s", 14, buf);
        std::fclose(f);
    }
    std::printf(")\n");
    const Result fast = run(0.0, seconds);
    print("pty, unpaced:", fast);
    std::printf("  unpaced rate %.0f updates/s  (target >= 5000)\n", fast.rate);
    std::printf("sensor arrival -> motor packet written: p99 %.0f us paced, %.0f us unpaced  (target < 1000 us)\n", paced.latency.p99Us,
                fast.latency.p99Us);
    recovery(10);
    return 0;
}
