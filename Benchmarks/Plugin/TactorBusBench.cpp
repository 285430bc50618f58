// Latency of the VST3's Tactors output bus (issue 33, docs/TACTORS.md): hosted as a DAW hosts it
// (the built VST3 through JUCE's VST3 host, the bus enabled at 9 channels), theremin under host
// automation, the elevation moved to another fret at a block start every 0.3 s. For each move it
// finds the sample at which the new fret's channel starts to carry a signal and prints, per block
// size, p50 / p99 / max of
//   step→bus:       that sample minus the control step that first read the move (the 200 Hz
//                   grid from the first block on): what the bus adds to the motor packet;
//   automation→bus: that sample minus the block start the host set the value at (the step grid's
//                   wait, up to one control period, included).
// Prints numbers only; never passes or fails on time.
#include <juce_audio_processors/juce_audio_processors.h>
#include "HostedParameters.h"
#include "Plugin/TactorBusLayout.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {
constexpr double kRate = 48000.0;
constexpr int kStep = 240;   // the plugin's control grid at 48 kHz (200 Hz)
constexpr int kTactors = 9;

double percentile(std::vector<double> v, double p)
{
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1), std::floor(p * static_cast<double>(v.size()))))];
}
} // namespace

int main()
{
    juce::ScopedJuceInitialiser_GUI juce;
    juce::VST3PluginFormat format;
    juce::OwnedArray<juce::PluginDescription> types;
    format.findAllTypesForFile(types, ARMADILLO_VST3_PATH);
    if (types.isEmpty()) {
        std::fprintf(stderr, "cannot load %s\n", ARMADILLO_VST3_PATH);
        return 1;
    }
    std::printf("Tactors bus latency, VST3 hosted, 48 kHz, theremin under host automation, a fret move every 0.3 s\n");
    std::printf("%6s %6s | %-28s | %-28s\n", "block", "moves", "step->bus ms p50/p99/max", "automation->bus ms p50/p99/max");
    for (int block : {64, 256, 1024}) {
        juce::String error;
        auto plugin = format.createInstanceFromDescription(*types[0], kRate, block, error);
        if (plugin == nullptr) {
            std::fprintf(stderr, "cannot instantiate: %s\n", error.toRawUTF8());
            return 1;
        }
        auto layout = plugin->getBusesLayout();
        layout.outputBuses.getReference(1) = armadillo::plugin::tactorbus::layoutFor(kTactors);
        if (!plugin->setBusesLayout(layout)) {
            std::fprintf(stderr, "the Tactors bus cannot be enabled\n");
            return 1;
        }
        auto* source = armadillo::bench::findParameter(*plugin, "Source");
        auto* scene = armadillo::bench::findParameter(*plugin, "Scene");
        auto* elevation = armadillo::bench::findParameter(*plugin, "Elevation");
        if (!source || !scene || !elevation || !armadillo::bench::setChoice(source, "host automation") || !armadillo::bench::setChoice(scene, "theremin")) {
            std::fprintf(stderr, "contract parameters missing\n");
            return 1;
        }
        const auto setElevation = [elevation](double deg) { elevation->setValueNotifyingHost(static_cast<float>((deg + 90.0) / 180.0)); };
        setElevation(-60.0);
        for (int i = 0; i < 20; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
        plugin->prepareToPlay(kRate, block);   // the control grid starts at the first block's first sample
        const auto* bus = plugin->getBus(false, 1);
        std::vector<int> channel(kTactors);
        for (int k = 0; k < kTactors; ++k)
            channel[static_cast<std::size_t>(k)] = bus->getChannelIndexInProcessBlockBuffer(armadillo::plugin::tactorbus::juceIndexOfTactor(bus->getCurrentLayout(), k));
        juce::AudioBuffer<float> buffer(std::max(plugin->getTotalNumInputChannels(), plugin->getTotalNumOutputChannels()), block);
        juce::MidiBuffer midi;
        std::vector<std::vector<float>> out(kTactors);
        std::vector<long> moves;
        const double elevations[] {-40.0, 35.0, -15.0, 50.0, 5.0, -55.0, 25.0, -25.0, 45.0, -5.0};
        const long total = static_cast<long>(40.0 * kRate);
        const long every = static_cast<long>(0.3 * kRate) + 37;   // moves at every phase of the control grid
        long at = 0, nextMove = static_cast<long>(0.5 * kRate);
        int move = 0;
        while (at < total) {
            if (at >= nextMove) {   // a DAW's automation point at this block's start
                setElevation(elevations[move % 10] + 0.37 * (move / 10 % 7));
                ++move;
                moves.push_back(at);
                nextMove = at + every;
            }
            buffer.clear();
            plugin->processBlock(buffer, midi);
            midi.clear();
            for (int k = 0; k < kTactors; ++k) {
                const float* x = buffer.getReadPointer(channel[static_cast<std::size_t>(k)]);
                out[static_cast<std::size_t>(k)].insert(out[static_cast<std::size_t>(k)].end(), x, x + block);
            }
            at += block;
            if ((at / block) % 64 == 0) juce::MessageManager::getInstance()->runDispatchLoopUntil(1);
        }
        std::vector<double> stepToBus, automationToBus;
        for (long m : moves) {
            // The channel that was silent for the 10 ms before the move and sounds within 20 ms after.
            long onset = -1;
            for (int k = 0; k < kTactors; ++k) {
                const auto& x = out[static_cast<std::size_t>(k)];
                if (m < 480 || m + 960 > static_cast<long>(x.size())) continue;
                bool silent = true;
                for (long i = m - 480; i < m && silent; ++i) silent = x[static_cast<std::size_t>(i)] == 0.0f;
                if (!silent) continue;
                for (long i = m; i < m + 960; ++i)
                    if (x[static_cast<std::size_t>(i)] != 0.0f) {
                        if (onset < 0 || i < onset) onset = i;
                        break;
                    }
            }
            if (onset < 0) continue;   // the move stayed on the same fret's motor
            const long step = (m + kStep - 1) / kStep * kStep;   // the first control step at or after the move
            stepToBus.push_back((onset - step) * 1000.0 / kRate);
            automationToBus.push_back((onset - m) * 1000.0 / kRate);
        }
        std::printf("%6d %6zu | %8.3f %8.3f %8.3f   | %8.3f %8.3f %8.3f\n", block, stepToBus.size(), percentile(stepToBus, 0.5),
                    percentile(stepToBus, 0.99), stepToBus.empty() ? NAN : *std::max_element(stepToBus.begin(), stepToBus.end()),
                    percentile(automationToBus, 0.5), percentile(automationToBus, 0.99),
                    automationToBus.empty() ? NAN : *std::max_element(automationToBus.begin(), automationToBus.end()));
        plugin->releaseResources();
    }
    return 0;
}
