// Latency and jitter of the plugin's mapping path (issue 23): from a sensor sample arriving to
// the MIDI event it produces, placed in the plugin's MIDI buffer. Hosted as a DAW hosts it (the
// built VST3 through JUCE's VST3 host), with the arm coming over OSC (`/armadillo/orientation`
// on loopback, the path of a phone or a self-fusing tracker) and one mapping: elevation → 14-bit
// CC 1/33 (docs/BENCHMARKS.md "Mapping latency").
//
// An "audio thread" calls processBlock in real time (one block every N/48000 s, paced by the
// monotonic clock); a sender thread sends orientations at irregular moments (every 3–17 ms),
// each with its own elevation, so each CC pair names the sample it came from. For each event:
//   latency = (wall time processBlock began + offset / 48000) − wall time the sample was sent,
// i.e. where the event sits on the audio timeline relative to the block's start, which is what
// a DAW plays it at (add the sound card's output latency for the ear). Prints p1/p50/p99/max and
// the jitter (p99 − p1) at 64- and 1024-sample blocks. Numbers only: it never passes or fails.
#include "Core/Pose.h"
#include "Core/ThreadPriority.h"
#include "Osc/OscIo.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include "HostedParameters.h"
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <unistd.h>
#include <vector>

namespace {

using namespace armadillo;
using namespace armadillo::core;

constexpr double kRate = 48000.0;
constexpr int kIds = 240;                 // elevations −60 … +59.5 in 0.5° steps, reused cyclically
constexpr double kElevationStep = 0.5;

double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double elevationOf(int idx)
{
    return -60.0 + kElevationStep * idx;
}

void setState(juce::AudioPluginInstance& plugin, int oscPort)
{
    // Source OSC (2), scene monitor (0), OSC in on oscPort, one mapping (docs/PLUGIN.md "State").
    const juce::String json = R"({"version": 1, "mappings": [{"source": "elevation", "in": [-90, 90], "to": {"midi": "cc14", "channel": 1, "cc": 1}}]})";
    const auto xml = "<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"source\" value=\"2\"/><PARAM id=\"scene\" value=\"0\"/></PARAMETERS>"
                     "<SETTINGS oscInEnabled=\"1\" oscInPort=\"" + juce::String(oscPort) + "\"/><MAPPING name=\"bench\" json=\""
                     + json.replace("\"", "&quot;") + "\"/></ARMADILLO>";
    juce::MemoryBlock payload;
    juce::AudioProcessor::copyXmlToBinary(*juce::parseXML(xml), payload);
    juce::XmlElement state("VST3PluginState");
    state.createNewChildElement("IComponent")->addTextElement(payload.toBase64Encoding());
    juce::MemoryBlock blob;
    juce::AudioProcessor::copyXmlToBinary(state, blob);
    plugin.setStateInformation(blob.getData(), static_cast<int>(blob.getSize()));
}

struct Result {
    std::vector<double> ms;
    int sent = 0;
    int lateWakeups = 0;   ///< blocks whose processBlock began > 1 ms after its deadline
    bool realtime = false; ///< the audio thread got SCHED_FIFO
};

Result run(juce::AudioPluginInstance& plugin, int block, double seconds, int oscPort)
{
    plugin.setPlayConfigDetails(0, 2, kRate, block);
    plugin.prepareToPlay(kRate, block);
    std::array<std::atomic<double>, kIds> sentAt {};
    for (auto& s : sentAt) s.store(-1.0);
    std::atomic<bool> running {true}, measuring {false};
    Result r;

    std::thread sender([&] {
        osc::OscSender out(osc::HostPort {"127.0.0.1", oscPort});
        std::mt19937 rng(2311);
        std::uniform_real_distribution<double> gap(0.003, 0.017);
        int id = 0;
        while (running.load()) {
            const int idx = id % kIds;
            const auto q = poseToQuaternion(Pose {elevationOf(idx), 90.0, 0.0});
            const double t = now();
            if (measuring.load()) sentAt[static_cast<std::size_t>(idx)].store(t);
            out.sendOrientation(q);
            if (measuring.load()) ++r.sent;
            ++id;
            std::this_thread::sleep_for(std::chrono::duration<double>(gap(rng)));
        }
    });

    std::thread audio([&] {
        // A DAW's audio thread runs real-time (JUCE's device threads ask for it); so does this one
        // when the system allows it (the header says whether it did).
        r.realtime = requestRealtimePriority(70);
        juce::AudioBuffer<float> buffer(2, block);
        juce::MidiBuffer midi;
        const double period = block / kRate;
        const double warmup = 1.0;
        const double start = now();
        int lastIdx = -1;
        for (long k = 0;; ++k) {
            const double deadline = start + k * period;
            if (deadline - start > warmup + seconds) break;
            std::this_thread::sleep_until(std::chrono::steady_clock::time_point(
                std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(deadline))));
            const double began = now();
            if (began - deadline > 0.001) ++r.lateWakeups;
            measuring.store(began - start > warmup);
            buffer.clear();
            midi.clear();
            plugin.processBlock(buffer, midi);
            int msb = -1;
            for (const auto m : midi) {
                if (m.numBytes != 3 || (m.data[0] & 0xF0) != 0xB0) continue;
                if (m.data[1] == 1) msb = m.data[2];
                if (m.data[1] != 33 || msb < 0) continue;
                const int value = 128 * msb + m.data[2];
                const double elevation = -90.0 + 180.0 * value / 16383.0;
                const int idx = static_cast<int>(std::lround((elevation + 60.0) / kElevationStep));
                if (idx < 0 || idx >= kIds || idx == lastIdx) continue;
                lastIdx = idx;
                const double sent = sentAt[static_cast<std::size_t>(idx)].exchange(-1.0);
                if (sent < 0.0 || ! (began - start > warmup)) continue;
                r.ms.push_back(1e3 * (began + m.samplePosition / kRate - sent));
            }
        }
        running.store(false);
    });

    // The plugin's message thread (timers: set hand-over, parameters) is this one.
    while (running.load()) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
    audio.join();
    sender.join();
    plugin.releaseResources();
    return r;
}

double pct(const std::vector<double>& sorted, double p)
{
    return sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(p * static_cast<double>(sorted.size() - 1))];
}

} // namespace

int main(int argc, char* argv[])
{
    juce::ScopedJuceInitialiser_GUI juce;
    const double seconds = argc > 1 ? std::atof(argv[1]) : 20.0;
    const int oscPort = 20000 + static_cast<int>(getpid() % 20000);
    juce::VST3PluginFormat format;
    juce::OwnedArray<juce::PluginDescription> types;
    format.findAllTypesForFile(types, ARMADILLO_VST3_PATH);
    if (types.isEmpty()) {
        std::fprintf(stderr, "cannot load %s\n", ARMADILLO_VST3_PATH);
        return 1;
    }
    std::printf("Mapping latency, plugin path: OSC orientation (loopback) -> control step -> 14-bit CC in the block's MIDI buffer\n");
    std::printf("VST3 hosted, 48 kHz, control rate 200 Hz, sensor samples every 3-17 ms, %g s per block size\n", seconds);
    std::printf("%-7s %7s %8s %8s %8s %8s %10s %6s %4s\n", "block", "events", "p1_ms", "p50_ms", "p99_ms", "max_ms", "jitter_ms", "late", "rt");
    for (int block : {64, 1024}) {
        juce::String error;
        auto plugin = format.createInstanceFromDescription(*types[0], kRate, block, error);
        if (plugin == nullptr) {
            std::fprintf(stderr, "cannot instantiate: %s\n", error.toRawUTF8());
            return 1;
        }
        if (bench::findParameter(*plugin, "Source") == nullptr) {
            std::fprintf(stderr, "contract parameters missing\n");
            return 1;
        }
        setState(*plugin, oscPort);
        for (int i = 0; i < 20; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
        auto r = run(*plugin, block, seconds, oscPort);
        std::sort(r.ms.begin(), r.ms.end());
        std::printf("%-7d %7zu %8.2f %8.2f %8.2f %8.2f %10.2f %6d %4s\n", block, r.ms.size(), pct(r.ms, 0.01), pct(r.ms, 0.5),
                    pct(r.ms, 0.99), r.ms.empty() ? 0.0 : r.ms.back(), pct(r.ms, 0.99) - pct(r.ms, 0.01), r.lateWakeups,
                    r.realtime ? "yes" : "no");
        if (r.ms.empty()) std::printf("  (no events matched: is the OSC input port %d free?)\n", oscPort);
    }
    return 0;
}
