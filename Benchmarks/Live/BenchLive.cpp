// The live pipeline as `armadillo play --port` runs it, against the simulated forearm on a
// pseudo-terminal: every sensor packet goes through calibration, the SR-UKF (ArmTracker) and the
// engine (scene, shaping, safety stage) before its motor packet is written. Prints the sustained
// rate as a fraction of the 57 600-baud lock-step rate, the unpaced rate, and the time from a
// sensor packet's arrival to its motor packet leaving. Usage: bench_live [seconds] [scene…]
#include "Live/Session/LiveSession.h"
#include "Link/Simulator.h"
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::link;
using namespace armadillo::live;

namespace {

void run(const std::string& scene, double baud, double seconds)
{
    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/bench-live-pty-" + std::to_string(::getpid());
    SimulatorOptions o;
    o.baud = baud;
    o.realtimePriority = 10;
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), o);
    sim.startPty(path);
    LiveConfig c;
    c.source = LiveConfig::Source::Port;
    c.port = path;
    c.engine.scene = scene;
    if (scene == "braille") c.engine.sceneConfig.text = "exit";
    if (scene == "score") c.engine.sceneConfig.score = "rite-of-spring";
    c.link.realtimePriority = 20;
    try {
        LiveSession s(c);
        s.start();
        std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
        s.stop();
        const SessionSummary sum = s.summary();
        const LatencySummary lat = s.latency();
        const double theoretical = lockStepRate(57600.0);
        std::printf("%-13s %-8s %9.1f updates/s%s  arrival->motor packet µs: mean %.1f p50 %.0f p99 %.0f max %.0f  (bad %llu, resyncs %llu)\n",
                    scene.c_str(), baud > 0 ? "paced" : "unpaced", sum.rateHz,
                    baud > 0 ? (" = " + std::to_string(sum.rateHz / theoretical).substr(0, 5) + " of lock-step").c_str() : "",
                    lat.meanUs, lat.p50Us, lat.p99Us, lat.maxUs, static_cast<unsigned long long>(sum.badPackets),
                    static_cast<unsigned long long>(sum.resyncs));
    } catch (const std::exception& e) {
        std::printf("%-13s skipped: %s\n", scene.c_str(), e.what());
    }
    sim.stop();
}

} // namespace

int main(int argc, char** argv)
{
    const double seconds = argc > 1 ? std::atof(argv[1]) : 4.0;
    std::vector<std::string> scenes;
    for (int i = 2; i < argc; ++i) scenes.push_back(argv[i]);
    if (scenes.empty()) scenes = {"monitor", "theremin", "cymbal"};
    std::printf("full live pipeline over a pty (targets: paced >= 0.95 of %.1f/s, unpaced >= 5000/s, latency < 1000 µs)\n",
                lockStepRate(57600.0));
    for (const auto& s : scenes) {
        run(s, 57600.0, seconds);
        run(s, 0.0, seconds);
    }
    return 0;
}
