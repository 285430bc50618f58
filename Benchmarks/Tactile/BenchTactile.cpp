// Cost of one control update of the tactile engine (target < 2 µs): 16 motors, every pattern
// voice busy, sustained targets changing, left-arm mirroring on; and the safety stage alone on a
// stream that changes every motor's level every packet (its worst case: the longest history).
// Prints numbers; never passes or fails on time.
#include "Tactile/ScoreScene.h"
#include "Tactile/TactileEngine.h"
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <random>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {

volatile unsigned g_sink = 0;   // keeps the results alive

// The machine may be shared (parallel builds): time is this thread's CPU time, and the
// figure printed is the best of several repeats with the median beside it.
double threadSeconds()
{
    timespec ts {};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Timing {
    double best, median;   // ns per call
};

template <typename F>
Timing nsPerCall(int calls, int repeats, F&& f)
{
    std::vector<double> runs;
    for (int r = 0; r < repeats; ++r) {
        const double t0 = threadSeconds();
        for (int i = 0; i < calls; ++i) f(i);
        runs.push_back((threadSeconds() - t0) * 1e9 / calls);
    }
    std::sort(runs.begin(), runs.end());
    return {runs.front(), runs[runs.size() / 2]};
}

void benchEngine(double dt, int voices)
{
    TactileEngine e;
    TactileConfig c;
    c.motorCount = kMaxMotors;
    c.side = ArmSide::Left;
    e.prepare(c);
    const PatternKind kinds[] = {PatternKind::Breathing, PatternKind::Tickle, PatternKind::Massage, PatternKind::Twist,
                                 PatternKind::BrokenGlass, PatternKind::GearPull, PatternKind::Geiger, PatternKind::Pulse};
    for (int v = 0; v < voices; ++v) {
        PatternRequest r;
        r.kind = kinds[v];
        r.motors = 0xFFFF;
        r.level = 7.0f;
        r.duration = -1.0;
        r.voice = v;
        e.trigger(r);
    }
    // Warm up: fill the safety stage's 10 s history.
    for (int i = 0; i * dt < 12.0; ++i) g_sink = g_sink + e.tick(dt)[0];
    const int calls = 200000;
    const Timing ns = nsPerCall(calls, 7, [&](int i) {
        if (i % 50 == 0) e.setLevel(i % kMaxMotors, float(i % 13) * 0.5f);
        g_sink = g_sink + e.tick(dt)[static_cast<std::size_t>(i & 15)];
    });
    std::printf("TactileEngine::tick   16 motors, %d voices, dt = 1/%.0f s:  %7.1f ns per control update (median %.1f)\n",
                voices, 1.0 / dt, ns.best, ns.median);
}

void benchSafetyWorstCase(double dt)
{
    SafetyStage s;
    s.prepare(kDefaultSafetyParams, kMaxMotors);
    std::mt19937 rng(1);
    std::vector<MotorLevels> stream(4096);
    for (auto& l : stream)
        for (auto& x : l) x = static_cast<std::uint8_t>(rng() % 16);
    for (int i = 0; i * dt < 12.0; ++i) g_sink = g_sink + s.process(stream[static_cast<std::size_t>(i) & 4095], dt)[0];
    const Timing ns = nsPerCall(200000, 7, [&](int i) {
        g_sink = g_sink + s.process(stream[static_cast<std::size_t>(i) & 4095], dt)[static_cast<std::size_t>(i & 15)];
    });
    std::printf("SafetyStage::process  16 motors, new random levels every packet, dt = 1/%.0f s:  %7.1f ns (median %.1f)\n",
                1.0 / dt, ns.best, ns.median);
}

struct NullEvents final : EventSink {
    void emit(const char*, float) override {}
};

void benchScore(const char* name)
{
    auto scene = makeScoreScene();
    SceneConfig config;
    config.score = name;
    scene->prepare(config);
    TactileEngine e;
    e.prepare(TactileConfig {});
    NullEvents events;
    SceneOutput out {e, events};
    const double dt = 0.005;
    int step = 0;
    const int calls = 14000;   // 70 s of score at 200 Hz
    const Timing ns = nsPerCall(calls, 5, [&](int i) {
        if (i == 0) scene->reset();
        ControlInput in;
        in.dt = i == 0 ? 0.0 : dt;
        scene->control(in, out);
        g_sink = g_sink + e.tick(in.dt)[static_cast<std::size_t>(step++ & 7)];
    });
    std::printf("score scene %-15s control + tick, 9 motors, 200 Hz:  %7.1f ns per control update (median %.1f)\n",
                name, ns.best, ns.median);
}

} // namespace

int main()
{
    std::printf("bench_tactile (target: tick < 2000 ns for 16 motors)\n");
    benchEngine(1.0 / 200.0, 8);
    benchEngine(1.0 / 285.0, 8);
    benchEngine(1.0 / 200.0, 4);
    benchEngine(1.0 / 200.0, 0);
    benchSafetyWorstCase(1.0 / 200.0);
    benchSafetyWorstCase(1.0 / 1000.0);
    benchScore("rite-of-spring");
    benchScore("polytope");
    return g_sink == 12345u ? 1 : 0;
}
