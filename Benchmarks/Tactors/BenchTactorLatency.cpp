// The tactor output's latency (issue 33): from a control step's motor levels (TactorOutput::push,
// the moment LiveSession hands them over) to the first sample that carries them — the start of
// the period that renders them, plus what the device still has queued before that period (ALSA:
// snd_pcm_delay; JACK: one period, or the playback latency JACK reports for connected ports).
// Control steps at 200 Hz with random phase against the audio clock; p50/p99/max printed.
// Also the renderer's cost per period (thread CPU time, best of 5) for each model.
// Prints numbers only; nothing passes or fails on time.
#include "Tactors/JackFixtures.h"
#include "Live/Outputs/TactorOutput.h"
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <random>
#include <thread>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;

namespace {

double percentile(std::vector<double> v, double p)
{
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

double threadCpu()
{
    timespec ts {};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void measure(const char* what, live::TactorOutputConfig config, double seconds)
{
    live::TactorOutput out(config);
    out.start();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> jitter(0.0, 0.005);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));   // the device's first periods
    live::TactorLatency drop;
    while (out.popLatency(drop)) {
    }
    std::vector<double> render, output;
    const auto start = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(jitter(rng)));
    MotorLevels l {};
    for (int i = 0; i * 0.005 < seconds; ++i) {
        std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(i * 0.005)));
        for (int m = 0; m < 9; ++m) l[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>((i + m) % 5);
        out.push(i * 0.005, l);
        live::TactorLatency r;
        while (out.popLatency(r)) {
            render.push_back(r.toRender * 1e3);
            output.push_back(r.toOutput * 1e3);
        }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    live::TactorLatency r;
    while (out.popLatency(r)) {
        render.push_back(r.toRender * 1e3);
        output.push_back(r.toOutput * 1e3);
    }
    out.stop();
    const double period = 1e3 * out.periodFrames() / out.sampleRate();
    std::printf("%-34s period %5.2f ms (%d frames at %.0f Hz), %zu steps: to the period p50 %.2f ms, p99 %.2f, max %.2f;"
                " to the first sample out p50 %.2f ms, p99 %.2f, max %.2f; anchor (period + 2 ms) %.2f ms; dropped %llu\n",
                what, period, out.periodFrames(), out.sampleRate(), render.size(), percentile(render, 0.5), percentile(render, 0.99),
                render.empty() ? 0.0 : *std::max_element(render.begin(), render.end()), percentile(output, 0.5), percentile(output, 0.99),
                output.empty() ? 0.0 : *std::max_element(output.begin(), output.end()), period + 2.0,
                static_cast<unsigned long long>(out.recordsDropped()));
    std::fflush(stdout);
}

void renderCost()
{
    for (auto model : {tactors::TactorModel::Erm, tactors::TactorModel::Lra, tactors::TactorModel::VoiceCoil}) {
        tactors::TactorParams p;
        p.model = model;
        tactors::TactorRenderer r;
        r.prepare(p, tactors::ChannelMap::identity(12), tactors::TactorGains {}, 48000.0);
        std::vector<std::vector<float>> buf(12, std::vector<float>(256));
        std::array<float*, tactors::kMaxChannels> ptr {};
        for (int c = 0; c < 12; ++c) ptr[static_cast<std::size_t>(c)] = buf[static_cast<std::size_t>(c)].data();
        double best = 1e9;
        for (int round = 0; round < 5; ++round) {
            MotorLevels l {};
            const double t0 = threadCpu();
            for (int b = 0; b < 2000; ++b) {
                for (int m = 0; m < 12; ++m) l[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>(1 + (b / 20 + m) % 5);
                r.setLevels(l, 256.0 / 48000.0);
                r.render(ptr.data(), 256);
            }
            best = std::min(best, (threadCpu() - t0) / 2000.0);
        }
        std::printf("renderer %-10s 12 channels, 256-sample period: %.1f us of thread CPU (%.2f %% of the period)\n", tactors::modelName(model), best * 1e6,
                    100.0 * best / (256.0 / 48000.0));
    }
}

} // namespace

int main()
{
    renderCost();
    for (double latency : {0.005, 0.010}) {
        live::TactorOutputConfig c;
        c.device = "null";
        c.latencySeconds = latency;
        char name[64];
        std::snprintf(name, sizeof name, "ALSA null, %.0f ms buffer:", latency * 1e3);
        measure(name, c, 10.0);
    }
    for (int period : {64, 256}) {
        test::JackServer server(48000, period, 2);
        if (!server.running()) {
            std::printf("JACK dummy backend: jackd did not start (skipped)\n");
            continue;
        }
        live::TactorOutputConfig c;
        c.device = "jack";
        char name[64];
        std::snprintf(name, sizeof name, "JACK dummy, period %d:", period);
        measure(name, c, 10.0);
    }
    return 0;
}
