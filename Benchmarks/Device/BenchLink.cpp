// Link throughput and latency over a real pseudo-terminal (SerialPort termios path + DeviceLink
// thread ↔ simulated forearm):
//  1. paced like a 57 600-baud 8N1 wire: sustained updates/s as a fraction of the lock-step
//     theoretical rate (19 bytes × 10 bits per update ⇒ ≈ 303/s; target ≥ 0.95);
//  2. unpaced: how fast the host side can go (target ≥ 5 000 updates/s);
//  3. sensor-packet arrival → motor-packet written, on the link thread (target < 1 ms).
// Prints numbers; never passes or fails on time. Usage: bench_device [seconds per run, default 5]
#include "Device/Calibration.h"
#include "Device/DeviceLink.h"
#include "Device/Simulator.h"
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::device;

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
    return 0;
}
