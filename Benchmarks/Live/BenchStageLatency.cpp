// Arm-to-sound latency on stage (issue 28): how long from a sensor packet's arrival until the
// sound it causes is handed to the sound card, through the path `armadillo play` uses —
// ArmTracker (orientation source) → Engine::control → the scene's lock-free targets → the sound
// card thread's Engine::renderAudio → Audio/SoundCard → ALSA. The card is ALSA's `null` PCM (no
// hardware here; JACK is not installed and `snd-aloop` cannot be loaded in this sandbox), which
// SoundCard paces to the wall clock, one buffer ahead, as a real card paces it by its clock.
//
// What is measured, per event: t_event = the steady clock just before the control step that
// receives the new arm state (elevation steps from −30° to +30°); the probe scene's audio then
// turns on at the first sample rendered after control() published it; t_out = the steady clock
// when the sound card thread's render callback started for that period, plus the sample's index
// in the period / fs. Printed: p50/p99/max of t_out − t_event ("to the card"), and that plus the
// card's queue (its buffer, bufferFrames / fs: what a real card holds before the DAC; not
// measured acoustically) = arm-to-sound. For buffers of 5, 10 and 20 ms. 400 events each, at
// random phases against the card's periods.
#include "Audio/SoundCard.h"
#include "Core/Pose.h"
#include "Fusion/ArmTracker.h"
#include "Engine/Engine.h"
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>
#include <thread>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::fusion;
using Clock = std::chrono::steady_clock;

namespace {
/// Silent until the arm is above the horizon, then a full-scale square (no smoothing: the
/// pipeline's latency, not a scene's attack).
class ProbeScene final : public Scene {
public:
    std::string_view name() const override { return "probe"; }
    void prepare(const SceneConfig&) override {}
    void control(const ControlInput& in, SceneOutput&) override { up.store(in.arm.features.pose.elevationDeg > 0.0, std::memory_order_release); }
    void renderAudio(float* l, float* r, int n) noexcept override
    {
        const bool on = up.load(std::memory_order_acquire);
        if (!on) return;
        for (int i = 0; i < n; ++i) l[i] = r[i] = (i & 8) ? 0.5f : -0.5f;
    }
    bool producesAudio() const override { return true; }
    std::atomic<bool> up {false};
};

double percentile(std::vector<double> v, double p)
{
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1), p * static_cast<double>(v.size() - 1) + 0.5))];
}
} // namespace

int main()
{
    std::printf("arm-to-sound through Audio/SoundCard on ALSA 'null' (48 kHz), probe scene, 400 events per buffer size\n");
    for (const double latency : {0.005, 0.010, 0.020}) {
        EngineConfig config;
        config.scene = "probe";
        Engine engine(config, std::make_unique<ProbeScene>());
        ArmTracker tracker;
        std::unique_ptr<audio::SoundCard> card;
        try {
            card = std::make_unique<audio::SoundCard>("null", 48000.0, latency);
        } catch (const std::exception& e) {
            std::printf("cannot open ALSA 'null': %s\n", e.what());
            return 0;
        }
        const double fs = card->info().sampleRate;
        std::atomic<bool> armed {false};
        std::atomic<double> seenAt {-1.0};   // s since `origin`
        const Clock::time_point origin = Clock::now();
        std::vector<float> scratch(65536);
        card->start(
            [&](float* l, float* r, int n) {
                const double now = std::chrono::duration<double>(Clock::now() - origin).count();
                engine.renderAudio(l, r, n);
                if (!armed.load(std::memory_order_acquire)) return;
                for (int i = 0; i < n; ++i)
                    if (l[i] != 0.0f) {
                        seenAt.store(now + i / fs, std::memory_order_release);
                        armed.store(false, std::memory_order_release);
                        return;
                    }
            },
            0);
        std::mt19937 rng(28);
        std::uniform_real_distribution<double> jitter(0.0, 0.011);
        std::vector<double> toCard;
        double t = 0.0;
        auto step = [&](double elevation) {
            t += 0.005;
            return tracker.updateOrientation(t, poseToQuaternion(Pose {elevation, 0.0, 0.0}));
        };
        for (int e = 0; e < 400; ++e) {
            (void) engine.control(step(-30.0), Transport {}, 0.005);
            std::this_thread::sleep_for(std::chrono::duration<double>(0.015 + jitter(rng)));   // random phase vs the periods
            seenAt.store(-1.0);
            armed.store(true, std::memory_order_release);
            const ArmState up = step(30.0);
            const double tEvent = std::chrono::duration<double>(Clock::now() - origin).count();
            (void) engine.control(up, Transport {}, 0.005);
            const auto deadline = Clock::now() + std::chrono::milliseconds(500);
            while (seenAt.load(std::memory_order_acquire) < 0.0 && Clock::now() < deadline) std::this_thread::sleep_for(std::chrono::microseconds(200));
            const double seen = seenAt.load(std::memory_order_acquire);
            if (seen >= 0.0) toCard.push_back(seen - tEvent);
            armed.store(false);
        }
        card->stop();
        const double queue = card->info().bufferFrames / fs;
        if (toCard.empty()) {
            std::printf("buffer %.0f ms: no event seen\n", 1000.0 * latency);
            continue;
        }
        std::printf("buffer %4.1f ms (period %d frames, buffer %d frames): to the card p50 %.2f ms, p99 %.2f ms, max %.2f ms;"
                    " + queue %.2f ms = arm-to-sound p50 %.2f ms, p99 %.2f ms (%zu events, %llu underruns)\n",
                    1000.0 * latency, card->info().periodFrames, card->info().bufferFrames, 1000.0 * percentile(toCard, 0.5),
                    1000.0 * percentile(toCard, 0.99), 1000.0 * percentile(toCard, 1.0), 1000.0 * queue, 1000.0 * (percentile(toCard, 0.5) + queue),
                    1000.0 * (percentile(toCard, 0.99) + queue), toCard.size(), static_cast<unsigned long long>(card->underruns()));
    }
    return 0;
}
