// Issue 27, "stems felt apart" through the plugin: the VST3 declares four sidechain input buses
// (Drums, Bass, Other, Vocals; disabled until the host routes them), and audio-touch feels each
// enabled one as a stem on its own motors with its own band and envelope (the scene's presets,
// docs/INSTRUMENTS.md "Stems felt apart"). Hosted through JUCE's VST3 host, as a DAW would; the
// motor levels are read from the plugin's OSC output on a loopback port. Nothing here links the
// plugin's code.
#include <catch2/catch.hpp>

#include "Common/RealtimeGuard.h"
#include "Plugin/HostedPlugin.h"
#include "MotorListener.h"

using namespace armadillo::test::host;

namespace {

/// The plugin's own settings with OSC out to 127.0.0.1:`port` (docs/PLUGIN.md "State"), inside
/// the document JUCE's VST3 host keeps them in.
void sendMotorsTo(Hosted& h, int port)
{
    setOwnSettings(h, {{"oscOutEnabled", 1}, {"oscOutHost", "127.0.0.1"}, {"oscOutPort", port}});
}

// The scene's presets (docs/INSTRUMENTS.md "Stems felt apart"; motor k of INTERFACES.md is
// index k − 1 of /armadillo/motors): bass at the elbow (m7, m9), vocals at the wrist (m1, m3).
constexpr int kBassMotors[] = {6, 8};
constexpr int kVocalMotors[] = {0, 2};

// The host buffer's channels with every bus enabled (JUCE: the buses' channels in bus order).
constexpr int kMainIn = 0, kBassIn = 4, kVocalsIn = 8, kChannels = 10;   // Drums 2–3, Other 6–7

struct Phase {
    const char* name;
    bool bass, vocals;
    bool kick = false;   ///< a 50 Hz tone on the main input alone (the stems silent)
    bool mixed = false;  ///< audio-touch.stems = mixed for this phase
};

struct Felt {
    std::array<int, 9> highest {};
    int messages = 0;
};

} // namespace

TEST_CASE("VST3: sidechain buses Drums, Bass, Other, Vocals are declared, disabled until routed; LV2 keeps its one input")
{
    auto h = loadVst3();
    REQUIRE(h.plugin->getBusCount(true) == 5);
    CHECK(h.plugin->getBusCount(false) == 2);   // the main output and the Tactors bus (issue 33), disabled
    const char* names[] {"Input", "Drums", "Bass", "Other", "Vocals"};
    for (int b = 0; b < 5; ++b) {
        INFO("input bus " << b);
        const auto* bus = h.plugin->getBus(true, b);
        REQUIRE(bus != nullptr);
        CHECK(bus->getName() == names[b]);
        CHECK(bus->getLastEnabledLayout() == juce::AudioChannelSet::stereo());
        CHECK(bus->isEnabled() == (b == 0));   // the stems wait for the host to route them
    }
    // Accepted enabled (stereo, mono) and disabled, alone and all together.
    auto layout = h.plugin->getBusesLayout();
    for (int b = 1; b < 5; ++b) {
        layout.inputBuses.getReference(b) = juce::AudioChannelSet::stereo();
        CHECK(h.plugin->checkBusesLayoutSupported(layout));
    }
    layout.inputBuses.getReference(2) = juce::AudioChannelSet::mono();
    CHECK(h.plugin->checkBusesLayoutSupported(layout));
    layout.inputBuses.getReference(3) = juce::AudioChannelSet::disabled();
    CHECK(h.plugin->checkBusesLayoutSupported(layout));
    layout.inputBuses.getReference(1) = juce::AudioChannelSet::create5point1();
    CHECK_FALSE(h.plugin->checkBusesLayoutSupported(layout));
    REQUIRE(h.plugin->enableAllBuses());
    CHECK(h.plugin->getTotalNumInputChannels() == kChannels);

    // The scene's choice between the stems apart and one mix (appended to audio-touch's parameters).
    auto* stems = h.param("audio-touch: Stems");
    REQUIRE(stems != nullptr);
    CHECK(stems->getNumSteps() == 2);
    CHECK(stems->getCurrentValueAsText() == "apart");

    auto lv2 = loadLv2();
    CHECK(lv2.plugin->getBusCount(true) == 1);
}

TEST_CASE("VST3: audio-touch feels the Bass bus at the elbow and the Vocals bus at the wrist, apart; nothing allocates")
{
    ARMADILLO_REQUIRE_GUARD();
    auto h = loadVst3();
    MotorListener listener;
    sendMotorsTo(h, listener.port());
    REQUIRE(h.plugin->enableAllBuses());   // main input and the four sidechains, stereo
    REQUIRE(h.plugin->getBus(false, 1)->enable(false));   // not the Tactors output bus (TactorBusHostTests.cpp)
    REQUIRE(h.plugin->getTotalNumInputChannels() == kChannels);
    for (int b = 0; b < 5; ++b) REQUIRE(h.plugin->getBus(true, b)->isEnabled());
    h.plugin->setRateAndBufferSizeDetails(kRate, kBlock);
    h.plugin->prepareToPlay(kRate, kBlock);
    setChoice(h, "Source", "host automation");
    setChoice(h, "Scene", "audio-touch");
    for (int i = 0; i < 5; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);

    // The guard sees the plugin's heap use before its zero is trusted.
    {
        armadillo::test::RealtimeGuard guard;
        juce::MemoryBlock state;
        h.plugin->getStateInformation(state);
        REQUIRE(guard.allocations() > 0);
    }

    // Distinct signals: a bass line (82 Hz) on Bass, a sung 440 Hz on Vocals; the main input
    // carries the mix of both (played through, not felt while a stem sounds). Drums and Other
    // stay silent. Last, the stems fall silent and a 50 Hz tone comes on the main input alone:
    // with `audio-touch.stems` = apart (the default) the main input is felt again once the stems
    // have been silent for 1 s (a host that enables the sidechains and routes nothing).
    const auto bassAt = [](double t) { return 0.3 * std::sin(2.0 * M_PI * 82.41 * t); };
    const auto voiceAt = [](double t) { return 0.3 * std::sin(2.0 * M_PI * 440.0 * t); };
    juce::AudioBuffer<float> buffer(kChannels, kBlock);
    juce::MidiBuffer midi;
    midi.ensureSize(8192);
    const Phase phases[] {{"bass only", true, false}, {"vocals only", false, true}, {"both", true, true}, {"silence", false, false},
                          {"main input only", false, false, true}, {"both, audio-touch.stems = mixed", true, true, false, true}};
    auto* stemsChoice = h.param("audio-touch: Stems");
    REQUIRE(stemsChoice != nullptr);
    const auto kickAt = [](double t) { return 0.3 * std::sin(2.0 * M_PI * 50.0 * t); };
    // A stem's level falls from −13.5 dB to the −40 dB floor in 0.9 s (bass, 150 ms release) and
    // 1.5 s (vocals, 250 ms): each phase is judged after that.
    constexpr double kPhaseSeconds = 3.0, kSettle = 1.8;
    const int blocksPerPhase = static_cast<int>(kPhaseSeconds * kRate / kBlock);
    std::vector<Felt> felt;
    std::uint64_t allocations = 0, deallocations = 0, throws = 0, guarded = 0;
    long sample = 0;
    double worstThrough = 0.0;
    for (const Phase& phase : phases) {
        Felt f;
        stemsChoice->setValueNotifyingHost(phase.mixed ? 1.0f : 0.0f);
        for (int b = 0; b < blocksPerPhase; ++b) {
            buffer.clear();
            for (int i = 0; i < kBlock; ++i) {
                const double t = static_cast<double>(sample + i) / kRate;
                const auto bass = static_cast<float>(phase.bass ? bassAt(t) : 0.0);
                const auto voice = static_cast<float>(phase.vocals ? voiceAt(t) : 0.0);
                const auto kick = static_cast<float>(phase.kick ? kickAt(t) : 0.0);
                for (int c = 0; c < 2; ++c) {
                    buffer.setSample(kMainIn + c, i, bass + voice + kick);
                    buffer.setSample(kBassIn + c, i, bass);
                    buffer.setSample(kVocalsIn + c, i, voice);
                }
            }
            {
                armadillo::test::RealtimeGuard guard;
                h.plugin->processBlock(buffer, midi);
                if (sample >= static_cast<long>(kRate / 2)) {   // after the host's first blocks
                    allocations += guard.allocations();
                    deallocations += guard.deallocations();
                    throws += guard.throws();
                    ++guarded;
                }
            }
            midi.clear();
            for (int c = 0; c < 2; ++c)   // the scene is silent: the output is the main input
                for (int i = 0; i < kBlock; ++i) {
                    const double t = static_cast<double>(sample + i) / kRate;
                    const auto expected = static_cast<float>(phase.bass ? bassAt(t) : 0.0) + static_cast<float>(phase.vocals ? voiceAt(t) : 0.0)
                                          + static_cast<float>(phase.kick ? kickAt(t) : 0.0);
                    worstThrough = std::max(worstThrough, std::fabs(double(buffer.getSample(c, i)) - double(expected)));
                }
            sample += kBlock;
            // In real time: the plugin's control clock sends the motor levels over OSC.
            juce::MessageManager::getInstance()->runDispatchLoopUntil(static_cast<int>(1000.0 * kBlock / kRate));
            const auto motors = listener.drain();
            if (b < static_cast<int>(kSettle * kRate / kBlock)) continue;
            for (const auto& m : motors) {
                if (m.size() < 9) continue;
                ++f.messages;
                for (std::size_t k = 0; k < 9; ++k) f.highest[k] = std::max(f.highest[k], m[k]);
            }
        }
        felt.push_back(f);
    }
    h.plugin->releaseResources();

    for (std::size_t p = 0; p < felt.size(); ++p) {
        const Phase& phase = phases[p];
        const Felt& f = felt[p];
        juce::String levels;
        for (int v : f.highest) levels << v << " ";
        INFO(phase.name << ": highest level per motor m1..m9 " << levels << "over " << f.messages << " OSC messages");
        REQUIRE(f.messages >= 20);
        for (int v : f.highest) CHECK(v <= 15);
        if (phase.mixed) {   // the main input's mix through the three bands: 82 Hz on the elbow row, 440 Hz in the middle
            for (int k : {3, 4, 5, 6, 7, 8}) CHECK(f.highest[static_cast<std::size_t>(k)] > 0);
            for (int k : {0, 1, 2}) CHECK(f.highest[static_cast<std::size_t>(k)] == 0);   // the voice is not at the wrist
            continue;
        }
        if (phase.kick) {   // the main input's lows on the whole elbow row (m8 too: no stem drives it alone)
            for (int k : {6, 7, 8}) CHECK(f.highest[static_cast<std::size_t>(k)] > 0);
            for (int k : {0, 1, 2}) CHECK(f.highest[static_cast<std::size_t>(k)] == 0);
            continue;
        }
        for (int k : kBassMotors) CHECK((f.highest[static_cast<std::size_t>(k)] > 0) == phase.bass);
        for (int k : kVocalMotors) CHECK((f.highest[static_cast<std::size_t>(k)] > 0) == phase.vocals);
        // Drums (m2, m5, m8) and Other (m4, m6) are silent; the main input's mix is not felt.
        for (int k : {1, 3, 4, 5, 7}) CHECK(f.highest[static_cast<std::size_t>(k)] == 0);
    }
    INFO("guarded blocks: " << guarded);
    CHECK(guarded > 1000);
    CHECK(allocations == 0);
    CHECK(deallocations == 0);
    CHECK(throws == 0);
    CHECK(worstThrough < 1e-6);   // the track still plays through
}

TEST_CASE("VST3: with no sidechain routed, audio-touch feels the main input as before")
{
    auto h = loadVst3();
    MotorListener listener;
    sendMotorsTo(h, listener.port());
    prepare(h, true);   // main input only (setPlayConfigDetails disables the sidechains)
    for (int b = 1; b < 5; ++b) REQUIRE_FALSE(h.plugin->getBus(true, b)->isEnabled());
    setChoice(h, "Source", "host automation");
    setChoice(h, "Scene", "audio-touch");
    for (int i = 0; i < 5; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
    // A kick-range 50 Hz tone on the main input: the mixed path's lows, the elbow row m7–m9.
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    Felt f;
    const int blocks = static_cast<int>(2.0 * kRate / kBlock);
    for (int b = 0; b < blocks; ++b) {
        for (int c = 0; c < 2; ++c)
            for (int i = 0; i < kBlock; ++i)
                buffer.setSample(c, i, static_cast<float>(0.3 * std::sin(2.0 * M_PI * 50.0 * (b * kBlock + i) / kRate)));
        h.plugin->processBlock(buffer, midi);
        midi.clear();
        juce::MessageManager::getInstance()->runDispatchLoopUntil(static_cast<int>(1000.0 * kBlock / kRate));
        const auto motors = listener.drain();
        if (b < static_cast<int>(0.8 * kRate / kBlock)) continue;
        for (const auto& m : motors) {
            if (m.size() < 9) continue;
            ++f.messages;
            for (std::size_t k = 0; k < 9; ++k) f.highest[k] = std::max(f.highest[k], m[k]);
        }
    }
    h.plugin->releaseResources();
    juce::String levels;
    for (int v : f.highest) levels << v << " ";
    INFO("highest level per motor m1..m9 " << levels << "over " << f.messages << " OSC messages");
    REQUIRE(f.messages >= 20);
    for (int k : {6, 7, 8}) CHECK(f.highest[static_cast<std::size_t>(k)] > 0);   // the whole elbow row
    for (int k : {0, 1, 2}) CHECK(f.highest[static_cast<std::size_t>(k)] == 0);  // nothing at the wrist
}
