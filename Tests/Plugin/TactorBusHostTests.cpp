// Issue 33, "the display on any tactor rig" in a DAW: the VST3's Tactors output bus (9 or 12
// channels, disabled until the host enables it), hosted through JUCE's VST3 host as a DAW does.
// With the bus enabled, the same host automation gives on each channel the envelope that
// `render --tactile-wav` draws for the same poses (the offline renderer's tactile rows through the
// same tactor renderer, Source/Tactors), nothing allocates on the audio thread, and the bus tests
// pluginval runs (listing the buses, enabling all, disabling the non-main ones, restoring the
// default layout, processing and state in each) pass with the bus on and off.
#include <catch2/catch.hpp>

#include "Common/RealtimeGuard.h"
#include "Core/Csv.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include "Plugin/HostedPlugin.h"
#include "Plugin/TactorBusLayout.h"
#include "Tactors/TactorRenderer.h"
#include <sstream>

using namespace armadillo::test::host;

namespace {

constexpr int kTactorChannels = 9;
constexpr int kFrame = 240;   // 5 ms at 48 kHz: the envelope's frame

void enableTactors(Hosted& h, int channels)
{
    auto layout = h.plugin->getBusesLayout();
    REQUIRE(layout.outputBuses.size() == 2);
    layout.outputBuses.getReference(1) = armadillo::plugin::tactorbus::layoutFor(channels);
    REQUIRE(h.plugin->setBusesLayout(layout));
    REQUIRE(h.plugin->getBus(false, 1)->isEnabled());
    REQUIRE(h.plugin->getTotalNumOutputChannels() == 2 + channels);
}

void settle(int times = 5)
{
    for (int i = 0; i < times; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
}

/// Per-channel peak |x| of each kFrame-sample frame.
std::vector<std::vector<float>> envelope(const std::vector<std::vector<float>>& channels)
{
    std::vector<std::vector<float>> env;
    for (const auto& x : channels) {
        std::vector<float> e(x.size() / kFrame, 0.0f);
        for (std::size_t f = 0; f < e.size(); ++f)
            for (int i = 0; i < kFrame; ++i) e[f] = std::max(e[f], std::abs(x[f * kFrame + static_cast<std::size_t>(i)]));
        env.push_back(std::move(e));
    }
    return env;
}

/// Elevation of the automation at block `b`: held at the start for the warm-up, then a ramp
/// down across the theremin's frets and back up, so each fret's motor holds its level a while.
float elevationAt(int b, int warmBlocks, int rampBlocks)
{
    if (b < warmBlocks) return -50.0f;
    const double u = static_cast<double>(b - warmBlocks) / rampBlocks;   // 0..1
    const double tri = u < 0.5 ? u * 2.0 : 2.0 - u * 2.0;
    return static_cast<float>(-50.0 + 100.0 * tri);
}

} // namespace

TEST_CASE("VST3: the Tactors output bus is declared after the main output, disabled until routed, 9 or 12 channels")
{
    auto h = loadVst3();
    REQUIRE(h.plugin->getBusCount(false) == 2);
    const auto* main = h.plugin->getBus(false, 0);
    const auto* bus = h.plugin->getBus(false, 1);
    REQUIRE(main != nullptr);
    REQUIRE(bus != nullptr);
    CHECK(main->isEnabled());
    CHECK(bus->getName() == "Tactors");
    CHECK_FALSE(bus->isEnabled());   // a host that routes nothing gets the plugin as it was
    CHECK(bus->getLastEnabledLayout().size() == kTactorChannels);
    CHECK(h.plugin->getTotalNumOutputChannels() == 2);
    auto layout = h.plugin->getBusesLayout();
    for (int channels : {9, 12}) {
        layout.outputBuses.getReference(1) = armadillo::plugin::tactorbus::layoutFor(channels);
        CHECK(h.plugin->checkBusesLayoutSupported(layout));
    }
    for (const auto& other : {juce::AudioChannelSet::mono(), juce::AudioChannelSet::stereo(), juce::AudioChannelSet::create7point1(),
                              juce::AudioChannelSet::create7point1point2(), juce::AudioChannelSet::discreteChannels(9)}) {
        INFO(other.getDescription());
        layout.outputBuses.getReference(1) = other;
        CHECK_FALSE(h.plugin->checkBusesLayoutSupported(layout));
    }
    layout.outputBuses.getReference(1) = juce::AudioChannelSet::disabled();
    CHECK(h.plugin->checkBusesLayoutSupported(layout));
}

TEST_CASE("VST3: the Tactors bus carries render --tactile-wav's envelope for the same automation, allocating nothing")
{
    ARMADILLO_REQUIRE_GUARD_SEES_ALLOCATION();
    auto h = loadVst3();
    setOwnSettings(h, {{"tactorModel", "lra"}});   // a 170 Hz carrier: the envelope is clear in 5 ms frames
    enableTactors(h, kTactorChannels);
    h.plugin->prepareToPlay(kRate, kBlock);
    setChoice(h, "Source", "host automation");
    setChoice(h, "Scene", "theremin");
    setValue(h, "Azimuth", 0.0f, 0.0f, 360.0f);
    setValue(h, "Roll", 0.0f, -180.0f, 180.0f);
    setValue(h, "Elevation", -50.0f, -90.0f, 90.0f);
    settle();

    const int outs = h.plugin->getTotalNumOutputChannels();
    const int ins = h.plugin->getTotalNumInputChannels();
    juce::AudioBuffer<float> buffer(std::max(ins, outs), kBlock);
    juce::MidiBuffer midi;
    midi.ensureSize(8192);
    // Tactor channel k as the VST3 numbers it (a DAW's channel k), where JUCE's host puts it.
    const auto* tactorBus = h.plugin->getBus(false, 1);
    std::array<int, kTactorChannels> tactorChannel {};
    for (int k = 0; k < kTactorChannels; ++k) {
        tactorChannel[static_cast<std::size_t>(k)] =
            tactorBus->getChannelIndexInProcessBlockBuffer(armadillo::plugin::tactorbus::juceIndexOfTactor(tactorBus->getCurrentLayout(), k));
        REQUIRE(tactorChannel[static_cast<std::size_t>(k)] >= 2);
    }

    // The host's own first blocks (its buffers, the new scene's engine swapping in) before anything is measured.
    for (int b = 0; b < 40; ++b) {
        buffer.clear();
        h.plugin->processBlock(buffer, midi);
        midi.clear();
        settle(1);
    }
    const int warm = 20, ramp = static_cast<int>(std::lround(4.0 * kRate / kBlock)), blocks = warm + ramp;
    std::vector<std::vector<float>> bus(kTactorChannels);
    std::ostringstream poses;
    poses << "t,elevation,azimuth,roll\n";
    std::uint64_t allocations = 0, hostGrowth = 0, mostEvents = 0;
    std::vector<float> mainOut;
    for (int b = 0; b < blocks; ++b) {
        const float elevation = elevationAt(b, warm, ramp);
        setValue(h, "Elevation", elevation, -90.0f, 90.0f);
        poses << (static_cast<double>(b) * kBlock / kRate) << "," << elevation << ",0,0\n";
        buffer.clear();
        {
            armadillo::test::RealtimeGuard guard;
            h.plugin->processBlock(buffer, midi);
            const auto events = static_cast<std::uint64_t>(midi.getNumEvents());
            if (events > mostEvents) {   // the hosting side's event list grows on its side of the call
                mostEvents = events;
                hostGrowth += guard.allocations();
            } else {
                allocations += guard.allocations();
            }
        }
        midi.clear();
        for (int c = 0; c < kTactorChannels; ++c)
        {
            const float* x = buffer.getReadPointer(tactorChannel[static_cast<std::size_t>(c)]);
            bus[static_cast<std::size_t>(c)].insert(bus[static_cast<std::size_t>(c)].end(), x, x + kBlock);
        }
        mainOut.insert(mainOut.end(), buffer.getReadPointer(0), buffer.getReadPointer(0) + kBlock);
    }
    INFO("host-side growth allocations: " << hostGrowth);
    CHECK(allocations == 0);
    float mainPeak = 0.0f;
    for (float v : mainOut) mainPeak = std::max(mainPeak, std::abs(v));
    CHECK(mainPeak > 0.05f);   // the main output still carries the theremin

    // What `render --tactile-wav` makes of the same poses: the offline renderer's rows, drawn by
    // the same tactor renderer with the same model.
    armadillo::engine::RenderSettings rs;
    rs.engine.scene = "theremin";
    rs.engine.sceneConfig.sampleRate = kRate;
    const auto table = armadillo::core::CsvTable::parse(poses.str(), "poses");
    const auto rendered = armadillo::live::renderOffline(table, rs);
    armadillo::tactors::TactorParams params;
    params.model = armadillo::tactors::TactorModel::Lra;
    armadillo::tactors::TactorRenderer renderer;
    renderer.prepare(params, armadillo::tactors::ChannelMap::identity(kTactorChannels), armadillo::tactors::TactorGains {}, kRate);
    const auto wav = armadillo::tactors::renderTactileRows(rendered.tactile, renderer);
    REQUIRE(wav.channels.size() == kTactorChannels);
    const auto& file = wav.channels;

    const auto p = envelope(bus), r = envelope(file);
    const std::size_t frames = std::min(p[0].size(), r[0].size());
    REQUIRE(frames >= 700);
    // The envelopes agree within one level, frame by frame, allowing the control steps' phase
    // against the blocks (the plugin steps on a 200 Hz grid of its own; the file at its rows):
    // each frame of the bus lies within the file's envelope over ±2 frames, widened by a level.
    constexpr float kLevel = 1.0f / 15.0f;
    int outside = 0, active = 0, channelsUsed = 0;
    std::ostringstream where;
    for (int c = 0; c < kTactorChannels; ++c) {
        bool used = false;
        // From the ramp on: the plugin's engine has been running since its own first blocks, the
        // file's starts at its first row (its first fret's motor jump-starts there, the bus's has long before).
        for (std::size_t f = static_cast<std::size_t>(warm * kBlock / kFrame); f + 2 < frames; ++f) {
            float lo = 1.0f, hi = 0.0f;
            for (std::size_t g = f - 2; g <= f + 2; ++g) {
                lo = std::min(lo, r[static_cast<std::size_t>(c)][g]);
                hi = std::max(hi, r[static_cast<std::size_t>(c)][g]);
            }
            const float v = p[static_cast<std::size_t>(c)][f];
            if (v > 0.2f) {
                ++active;
                used = true;
            }
            if (v < lo - kLevel || v > hi + kLevel) {
                ++outside;
                where << "channel " << c + 1 << " frame " << f << ": bus " << v * 15.0f << ", file " << lo * 15.0f << ".." << hi * 15.0f << "\n";
            }
        }
        if (used) ++channelsUsed;
    }
    INFO(active << " active frames on " << channelsUsed << " channels");
    INFO(where.str());
    CHECK(channelsUsed >= 4);   // the ramp crosses several frets, each on its own motor
    CHECK(active >= 200);
    CHECK(outside == 0);
    h.plugin->releaseResources();
}

TEST_CASE("VST3: pluginval's bus tests with the Tactors bus: all buses enabled, non-main disabled, default restored")
{
    // pluginval (not packaged in Debian) runs these on every plugin at strictness ≥ 5: list the
    // buses, enable all of them and process, disable the non-main ones and process, restore the
    // default layout; at strictness 10 also state round trips and automation in each. Done here
    // through JUCE's VST3 host, the same calls pluginval makes.
    auto h = loadVst3();
    const auto defaults = h.plugin->getBusesLayout();
    setChoice(h, "Source", "simulator");
    setChoice(h, "Scene", "panel");
    settle();
    const auto play = [&h](const char* phase) {
        INFO(phase);
        h.plugin->prepareToPlay(kRate, kBlock);
        const int channels = std::max(h.plugin->getTotalNumInputChannels(), h.plugin->getTotalNumOutputChannels());
        juce::AudioBuffer<float> buffer(channels, kBlock);
        juce::MidiBuffer midi;
        bool finite = true;
        for (int b = 0; b < 100; ++b) {
            buffer.clear();
            for (auto* p : h.plugin->getParameters())
                if (p->isAutomatable() && p->getName(100) != "Source" && p->getName(100) != "Scene" && p != h.plugin->getBypassParameter())
                    p->setValue(0.5f + 0.45f * std::sin(0.1f * static_cast<float>(b)));
            h.plugin->processBlock(buffer, midi);
            midi.clear();
            for (int c = 0; c < buffer.getNumChannels(); ++c)
                for (int i = 0; i < kBlock; ++i) finite = finite && std::isfinite(buffer.getSample(c, i)) && std::abs(buffer.getSample(c, i)) <= 1.0f;
            if (b % 10 == 0) settle(1);
        }
        CHECK(finite);
        juce::MemoryBlock state;
        h.plugin->getStateInformation(state);
        h.plugin->setStateInformation(state.getData(), static_cast<int>(state.getSize()));
        juce::MemoryBlock again;
        h.plugin->getStateInformation(again);
        CHECK(again.getSize() > 0);
        h.plugin->releaseResources();
    };
    play("default layout: the Tactors bus disabled");
    REQUIRE(h.plugin->enableAllBuses());
    CHECK(h.plugin->getBus(false, 1)->isEnabled());
    CHECK(h.plugin->getTotalNumOutputChannels() == 2 + kTactorChannels);
    play("every bus enabled");
    REQUIRE(h.plugin->disableNonMainBuses());
    CHECK_FALSE(h.plugin->getBus(false, 1)->isEnabled());
    play("non-main buses disabled");
    enableTactors(h, 12);
    play("the Tactors bus at 12 channels");
    REQUIRE(h.plugin->setBusesLayout(defaults));
    CHECK(h.plugin->getBusesLayout() == defaults);
    play("default layout restored");
}

TEST_CASE("VST3: with tactorSound, the Tactors bus's voice coils carry the cymbal's own sound", "[sound]")
{
    auto h = loadVst3();
    setOwnSettings(h, {{"tactorModel", "voice-coil"}, {"tactorSound", "1"}});
    enableTactors(h, kTactorChannels);
    h.plugin->prepareToPlay(kRate, kBlock);
    setChoice(h, "Source", "host automation");
    setChoice(h, "Scene", "cymbal");
    setValue(h, "Elevation", 40.0f, -90.0f, 90.0f);
    settle();
    const auto* tactorBus = h.plugin->getBus(false, 1);
    std::array<int, kTactorChannels> tactorChannel {};
    for (int k = 0; k < kTactorChannels; ++k)
        tactorChannel[static_cast<std::size_t>(k)] =
            tactorBus->getChannelIndexInProcessBlockBuffer(armadillo::plugin::tactorbus::juceIndexOfTactor(tactorBus->getCurrentLayout(), k));
    juce::AudioBuffer<float> buffer(std::max(h.plugin->getTotalNumInputChannels(), h.plugin->getTotalNumOutputChannels()), kBlock);
    juce::MidiBuffer midi;
    std::vector<std::vector<float>> bus(kTactorChannels);
    std::vector<double> main;
    const int blocks = static_cast<int>(2.0 * kRate / kBlock);
    for (int b = 0; b < blocks; ++b) {
        // Held up for 0.5 s, struck down through horizontal in 0.15 s, then left ringing.
        const double t = static_cast<double>(b) * kBlock / kRate;
        const double el = t < 0.5 ? 40.0 : (t < 0.65 ? 40.0 - (t - 0.5) / 0.15 * 70.0 : -30.0);
        setValue(h, "Elevation", static_cast<float>(el), -90.0f, 90.0f);
        buffer.clear();
        h.plugin->processBlock(buffer, midi);
        midi.clear();
        for (int c = 0; c < kTactorChannels; ++c) {
            const float* x = buffer.getReadPointer(tactorChannel[static_cast<std::size_t>(c)]);
            bus[static_cast<std::size_t>(c)].insert(bus[static_cast<std::size_t>(c)].end(), x, x + kBlock);
        }
        for (int i = 0; i < kBlock; ++i) main.push_back(0.5 * (double(buffer.getSample(0, i)) + double(buffer.getSample(1, i))));
    }
    // The main output band-passed by a test-side filter (one-pole 40 Hz high-pass, two one-pole
    // 400 Hz low-passes), against the busiest tactor channel over 0.3 s of the ring.
    std::vector<double> ref(main.size());
    double hp = 0.0, prev = 0.0, lp1 = 0.0, lp2 = 0.0;
    const double kh = std::exp(-2.0 * M_PI * 40.0 / kRate), kl = 1.0 - std::exp(-2.0 * M_PI * 400.0 / kRate);
    for (std::size_t i = 0; i < main.size(); ++i) {
        hp = kh * (hp + main[i] - prev);
        prev = main[i];
        lp1 += (hp - lp1) * kl;
        lp2 += (lp1 - lp2) * kl;
        ref[i] = lp2;
    }
    const std::size_t from = static_cast<std::size_t>(0.8 * kRate), to = static_cast<std::size_t>(1.1 * kRate);
    std::size_t best = 0;
    double bestEnergy = 0.0;
    for (std::size_t c = 0; c < bus.size(); ++c) {
        double e = 0.0;
        for (std::size_t i = from; i < to; ++i) e += double(bus[c][i]) * double(bus[c][i]);
        if (e > bestEnergy) {
            bestEnergy = e;
            best = c;
        }
    }
    REQUIRE(bestEnergy > 0.0);
    double xy = 0.0, xx = 0.0, yy = 0.0;
    for (std::size_t i = from; i < to; ++i) {
        xy += double(bus[best][i]) * ref[i];
        xx += double(bus[best][i]) * double(bus[best][i]);
        yy += ref[i] * ref[i];
    }
    const double corr = xy / std::sqrt(xx * yy + 1e-30);
    INFO("tactor channel " << best + 1 << ": correlation with the band-passed cymbal " << corr);
    CHECK(corr > 0.6);
    h.plugin->releaseResources();
}
