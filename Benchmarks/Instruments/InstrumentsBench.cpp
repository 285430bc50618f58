// bench_instruments: how fast the instrument scenes render, measured in one run.
//   render speed  = seconds of audio per second of wall time, one core, 48 kHz, with control()
//                   at 200 Hz (a 240-sample block per control update), scripted arm motion;
//   per-block cost = wall time of one renderAudio(64) with sound playing, and its share of the
//                   1.33 ms a 64-sample block lasts at 48 kHz.
// The arm states are built before timing starts (that is the tracker's cost, not the scene's).
#include "Core/Pose.h"
#include "Fusion/ArmFeatures.h"
#include "Instruments/Scenes.h"
#include <chrono>
#include <ctime>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using namespace armadillo;
using namespace armadillo::fusion;
using namespace armadillo::instruments;
using namespace armadillo::core;
using Clock = std::chrono::steady_clock;

/// CPU time of this thread, s: what "one core" means even when the machine is shared (wall time
/// would count the time other processes held the core).
double threadSeconds()
{
    timespec ts {};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

namespace {

constexpr double kSampleRate = 48000.0;
constexpr double kControlRate = 200.0;

class NullCanvas final : public MotorCanvas {
public:
    void setLevel(int, float) override { ++calls; }
    void clearLevels() override { ++calls; }
    void trigger(const PatternRequest&) override { ++calls; }
    void stopVoice(int) override { ++calls; }
    long calls = 0;
};
class NullEvents final : public EventSink {
public:
    void emit(const char*, float) override { ++count; }
    long count = 0;
};

std::vector<ArmState> script(double seconds, const std::function<Pose(double)>& poseAt)
{
    std::vector<ArmState> out;
    const int n = static_cast<int>(seconds * kControlRate);
    Eigen::Quaterniond prev = poseToQuaternion(poseAt(0.0));
    for (int i = 0; i < n; ++i) {
        const double t = i / kControlRate;
        ArmState s;
        s.t = t;
        s.q = poseToQuaternion(poseAt(t));
        Eigen::Quaterniond d = prev.conjugate() * s.q;
        if (d.w() < 0.0) d.coeffs() = -d.coeffs();
        const Eigen::AngleAxisd aa(d);
        s.gyro = aa.axis() * (aa.angle() * kControlRate);
        s.accel = s.q.conjugate() * Eigen::Vector3d(0.0, kStandardGravity, 0.0);
        s.features = computeArmFeatures(s.q, s.gyro, s.accel);
        s.valid = true;
        prev = s.q;
        out.push_back(s);
    }
    return out;
}

struct Result {
    double realtimeMultiple = 0.0;     ///< audio seconds per CPU second
    double wallMultiple = 0.0;         ///< audio seconds per wall second (lower on a busy machine)
    double controlMicros = 0.0;   ///< mean per control update
    long events = 0;
};

Result renderSpeed(Scene& scene, const std::vector<ArmState>& arm, int repeats)
{
    NullCanvas canvas;
    NullEvents events;
    SceneOutput out {canvas, events};
    const int block = static_cast<int>(kSampleRate / kControlRate);
    std::vector<float> l(static_cast<std::size_t>(block)), r(static_cast<std::size_t>(block));
    double best = 1e300, bestWall = 1e300, controlSeconds = 0.0;
    for (int rep = 0; rep < repeats; ++rep) {
        scene.reset();
        double controlTime = 0.0;
        const auto start = Clock::now();
        const double cpuStart = threadSeconds();
        for (const ArmState& s : arm) {
            ControlInput in;
            in.arm = s;
            in.dt = 1.0 / kControlRate;
            const double c0 = threadSeconds();
            scene.control(in, out);
            controlTime += threadSeconds() - c0;
            std::fill(l.begin(), l.end(), 0.0f);
            std::fill(r.begin(), r.end(), 0.0f);
            scene.renderAudio(l.data(), r.data(), block);
        }
        const double cpu = threadSeconds() - cpuStart;
        bestWall = std::min(bestWall, std::chrono::duration<double>(Clock::now() - start).count());
        if (cpu < best) {
            best = cpu;
            controlSeconds = controlTime;
        }
    }
    Result res;
    res.realtimeMultiple = (static_cast<double>(arm.size()) / kControlRate) / best;
    res.wallMultiple = (static_cast<double>(arm.size()) / kControlRate) / bestWall;
    res.controlMicros = controlSeconds / static_cast<double>(arm.size()) * 1e6;
    res.events = events.count / repeats;
    return res;
}

/// Mean cost of renderAudio(64) while sounding; `excite` brings the scene into its busiest state.
double blockCostNanos(Scene& scene, const std::function<void(Scene&)>& excite, int blocks)
{
    std::vector<float> l(64), r(64);
    excite(scene);
    double best = 1e300;
    for (int rep = 0; rep < 5; ++rep) {
        excite(scene);
        const double start = threadSeconds();
        for (int b = 0; b < blocks; ++b) scene.renderAudio(l.data(), r.data(), 64);
        best = std::min(best, threadSeconds() - start);
    }
    return best / blocks * 1e9;
}

void drive(Scene& scene, const std::vector<ArmState>& arm)
{
    NullCanvas canvas;
    NullEvents events;
    SceneOutput out {canvas, events};
    std::vector<float> l(240), r(240);
    for (const ArmState& s : arm) {
        ControlInput in;
        in.arm = s;
        scene.control(in, out);
        scene.renderAudio(l.data(), r.data(), 240);
    }
}

} // namespace

int main()
{
    SceneConfig config;
    config.sampleRate = kSampleRate;
    config.seed = 1;
    constexpr double kSeconds = 30.0;
    std::printf("bench_instruments: %.0f s scripted motion, %.0f Hz audio, control %.0f Hz, one thread\n", kSeconds,
                kSampleRate, kControlRate);
    std::printf("times are this thread's CPU time (best of 3 runs); 'wall x RT' also counts time the core was busy elsewhere\n");
    std::printf("%-10s %11s %12s %10s %15s %11s %12s\n", "scene", "prepare ms", "render x RT", "wall x RT",
                "control us/upd", "block64 ns", "block64 %RT");

    // Theremin: slow swoops in pitch and volume, with quick vibrato.
    const auto thereminArm = script(kSeconds, [](double t) {
        return Pose {40.0 * std::sin(0.5 * t) + 3.0 * std::sin(30.0 * t), 40.0 * std::sin(0.23 * t), 0.0};
    });
    // Cymbal: a strike every 2 s (up to +30°, down fast to −30°), brushing inside in between.
    const auto cymbalArm = script(kSeconds, [](double t) {
        const double phase = std::fmod(t, 2.0);
        double el = -30.0;
        if (phase < 0.5) el = -30.0 + 120.0 * phase;            // up to +30° in 0.5 s
        else if (phase < 0.6) el = 30.0 - 600.0 * (phase - 0.5); // down at 600°/s
        return Pose {el, 40.0 * std::sin(1.7 * t), 10.0 * std::sin(2.3 * t)};
    });

    struct Entry {
        const char* name;
        std::unique_ptr<Scene> (*make)();
        const std::vector<ArmState>* arm;
    };
    // Panel and sound design: dialling with a quick roll every 1.5 s.
    const auto dialArm = script(kSeconds, [](double t) {
        const double phase = std::fmod(t, 1.5);
        const double roll = phase < 0.1 ? 600.0 * phase : std::max(0.0, 60.0 - 60.0 * (phase - 0.1));
        return Pose {45.0 * std::sin(0.4 * t), 60.0 * std::sin(0.3 * t), roll};
    });
    const Entry entries[] = {{"theremin", &makeThereminScene, &thereminArm},
                             {"cymbal", &makeCymbalScene, &cymbalArm},
                             {"panel", &makePanelScene, &dialArm},
                             {"sound-des.", &makeSoundDesignScene, &dialArm},
                             {"compass", &makeCompassScene, &thereminArm}};
    for (const Entry& e : entries) {
        auto scene = e.make();
        if (!scene) continue;
        const double p0 = threadSeconds();
        scene->prepare(config);
        const double prepareMs = (threadSeconds() - p0) * 1e3;
        const Result r = renderSpeed(*scene, *e.arm, 3);
        // Busiest audio: the first 2.6 s of the script (the cymbal has struck and rings).
        const std::vector<ArmState> lead(e.arm->begin(), e.arm->begin() + static_cast<long>(2.6 * kControlRate));
        const double ns = blockCostNanos(*scene, [&](Scene& s) { s.reset(); drive(s, lead); }, 2000);
        const double blockNs = 64.0 / kSampleRate * 1e9;
        std::printf("%-10s %11.1f %12.0f %10.0f %15.2f %11.0f %11.3f%%\n", e.name, prepareMs, r.realtimeMultiple,
                    r.wallMultiple, r.controlMicros, ns, 100.0 * ns / blockNs);
        if (std::string(e.name) == "cymbal") std::printf("           (%ld strike/damp events per run)\n", r.events);
    }
    return 0;
}
