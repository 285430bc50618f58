// Latency of the mapping matrix on the command line's live path (`armadillo play --map …
// --midi-out NAME`): a sensor sample arrives (the moment LiveSession::control starts with it), is
// calibrated, fused (ArmTracker SR-UKF), drives the scene (Engine::control, safety stage), then the
// Mapper, and its first MIDI event is handed to the ALSA sequencer (snd_seq_event_output_direct).
// Samples arrive on a 200 Hz clock as from the device (the thread sleeps between them, as the link
// thread waits on the port), from the simulated forearm's sensor model. Where no sequencer exists
// (/dev/snd/seq absent) the time is taken where the sequencer event has been built, just before
// snd_seq_event_output_direct, and the output says so. Prints p50, p99, max and the jitter
// (p99 − p50, and the standard deviation) in µs; and Mapper::process alone with 64 mappings.
// The CLI path is not cut into audio blocks: the MIDI leaves on the sensor's thread, whatever the
// sound card's period (64 or 1024 frames), so block size does not enter these figures.
// Usage: bench_mapping [seconds]
#include "Audio/SequencerOut.h"
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Link/Simulator.h"
#include "Live/Session/Instrument.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Outputs/MappingRig.h"
#include "Mapping/Mapper.h"
#include <alsa/asoundlib.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <time.h>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using Clock = std::chrono::steady_clock;

namespace {

struct Sink {
    audio::SequencerOut* seq = nullptr;
    Clock::time_point arrival {};
    bool waiting = false;   // the first event of this update has not been timed yet
    double latencyUs = -1.0;
};

void onMidi(void* context, const mapping::MidiEvent& e)
{
    auto& s = *static_cast<Sink*>(context);
    if (s.seq) {
        s.seq->send(e.bytes.data(), e.size);
    } else {
        snd_seq_event_t ev;
        audio::encodeSequencerEvent(e.bytes.data(), e.size, 0, &ev);
    }
    if (s.waiting) {
        s.latencyUs = std::chrono::duration<double, std::micro>(Clock::now() - s.arrival).count();
        s.waiting = false;
    }
}

struct Stats {
    double p50, p99, max, sd, mean;
};

Stats stats(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))]; };
    double mean = 0.0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    double var = 0.0;
    for (double x : v) var += (x - mean) * (x - mean);
    return {at(0.5), at(0.99), v.back(), std::sqrt(var / static_cast<double>(v.size())), mean};
}

void latency(const std::string& preset, double seconds, audio::SequencerOut* seq)
{
    auto instrument = std::make_unique<live::Instrument>();   // the instrument `play` runs: its one step, then the mapping
    live::ControlLoop& loop = instrument->loop();
    {
        auto slot = std::make_unique<live::EngineSlot>();
        EngineConfig config;
        config.scene = "monitor";
        slot->engine = std::make_unique<Engine>(config);
        slot->sceneName = "monitor";
        loop.replace(std::move(slot));
    }
    Engine& engine = *loop.active()->engine;
    live::MappingRigOptions options;
    options.sendOsc = false;
    live::MappingRig rig(mapping::loadMapping(preset), engine, options);
    Sink sink;
    sink.seq = seq;
    rig.setMidiSink(onMidi, &sink);

    link::WanderingMotion motion(3);
    link::SensorModel sensors;
    const link::Calibration calibration = link::defaultCalibration();
    const double rate = 200.0;
    const auto n = static_cast<std::size_t>(seconds * rate);
    std::vector<double> lat;
    lat.reserve(n);
    std::size_t updatesWithMidi = 0;
    auto next = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
        next += std::chrono::microseconds(5000);
        std::this_thread::sleep_until(next);   // the link thread waits for the next packet
        const double t = static_cast<double>(i) / rate;
        const link::SensorCounts counts = sensors.sample(motion.at(t), t, link::ProtocolLevels {});
        // ---- the sample has arrived ----
        sink.arrival = Clock::now();
        sink.waiting = true;
        sink.latencyUs = -1.0;
        loop.input(live::SourceKind::Device).pushImu(calibration.apply(t, counts));
        live::ControlStep step;
        step.source = live::SourceKind::Device;
        step.dt = 1.0 / rate;
        instrument->beginStage();
        const live::Instrument::Stepped stepped = instrument->step(step, t, true);
        if (stepped.result.ran) rig.step(instrument->mappingInput(stepped, t), engine);
        if (sink.latencyUs >= 0.0) {
            lat.push_back(sink.latencyUs);
            ++updatesWithMidi;
        }
    }
    if (lat.empty()) {
        std::printf("  %-14s no MIDI sent\n", preset.c_str());
        return;
    }
    const Stats s = stats(lat);
    std::printf("  %-14s %5zu updates with MIDI: sample → MIDI out µs  p50 %6.1f  p99 %6.1f  max %7.1f  jitter p99−p50 %6.1f  sd %5.1f\n",
                preset.c_str(), updatesWithMidi, s.p50, s.p99, s.max, s.p99 - s.p50, s.sd);
}

double threadCpuUs()
{
    timespec ts {};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) / 1e3;
}

void processAlone()
{
    // 64 mappings: eight each of cc14, pitch bend, zone notes, OSC, gesture notes, macros, MPE, scene parameters.
    std::string doc = R"({"version": 1, "mappings": [)";
    const char* families[] {
        R"({"source": "elevation", "in": [-45, 45], "smoothMs": 15, "to": {"midi": "cc14", "channel": 1, "cc": 1}})",
        R"({"source": "roll", "curve": "exp", "shape": 2, "to": {"midi": "pitchbend", "channel": 2}})",
        R"({"source": "azimuth", "to": {"midi": "notes", "channel": 3, "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]}})",
        R"({"source": "yaw", "to": {"osc": "/yaw", "args": ["$yaw", "$pitch", "$roll"]}})",
        R"({"source": "gesture:*", "to": {"midi": "note", "channel": 4, "note": 50}})",
        R"({"source": "elevation", "to": {"macro": 1}})",
        R"({"source": "azimuth", "zones": [[0, 120, 60], [120, 240, 64], [240, 360, 67]], "to": {"midi": "mpe", "bend": {"source": "roll", "in": [-90, 90]}}})",
        R"({"source": "roll", "to": {"param": "x"}})",
    };
    for (int i = 0; i < 64; ++i) doc += std::string(i ? "," : "") + families[i % 8];
    doc += "]}";
    mapping::Mapper mapper;
    mapper.replace(mapping::MappingSet::build(mapping::parseMappingDocument(doc, "bench")));
    auto out = std::make_unique<mapping::MappingOutput>();
    ArmState arm;
    arm.valid = true;
    const int n = 20000;
    double best = 1e9;
    for (int rep = 0; rep < 5; ++rep) {
        const double start = threadCpuUs();
        for (int i = 0; i < n; ++i) {
            const double t = i * 0.005;
            arm.features.pose = Pose {60.0 * std::sin(t), std::fmod(t * 30.0, 360.0), 90.0 * std::sin(t * 1.3)};
            arm.q = poseToQuaternion(arm.features.pose);
            mapping::MappingInput in;
            in.t = t;
            in.arm[0] = &arm;
            mapper.process(in, *out);
            out->clear();
        }
        best = std::min(best, (threadCpuUs() - start) / n);
    }
    std::printf("Mapper::process, 64 mappings (8 each: cc14, pitch bend, zone notes, OSC, gesture notes, macro, MPE, scene parameter):\n"
                "  %.2f µs per control update (thread CPU time, best of 5 × %d) = %.3f %% of a 5 ms (200 Hz) update\n",
                best, n, best / 5000.0 * 100.0);
}

} // namespace

int main(int argc, char** argv)
{
    const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
    std::unique_ptr<audio::SequencerOut> seq;
    std::string where;
    try {
        seq = std::make_unique<audio::SequencerOut>("ARMadillo bench");
        where = "handed to snd_seq_event_output_direct (ALSA sequencer port 'ARMadillo bench')";
    } catch (const IoError& e) {
        where = "NO ALSA SEQUENCER HERE (" + std::string(e.what()) +
                "): measured up to the built sequencer event, just before snd_seq_event_output_direct";
    }
    std::printf("CLI path (play --map … --midi-out): sensor sample arrives → calibration → SR-UKF → scene → mapping → MIDI\n"
                "event %s; 200 Hz samples for %.0f s per preset, monitor scene.\n"
                "Anchor: timing jitter above about 3 ms is felt on percussive gestures.\n",
                where.c_str(), seconds);
    for (const char* preset : {"classic", "scenerotator", "mpe"}) latency(preset, seconds, seq.get());
    processAlone();
    return 0;
}
