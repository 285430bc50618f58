// Cost of the plugin's processBlock at 48 kHz / 64 samples for each scene, hosted as a DAW hosts
// it (the built VST3 through JUCE's VST3 host), with elevation and azimuth automated every block
// under source = host automation (elevation swings ±72° at 0.7 Hz: fast enough to strike the
// cymbal every cycle). Prints numbers; never passes or fails on time.
#include <juce_audio_processors/juce_audio_processors.h>
#include "HostedParameters.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {
constexpr double kRate = 48000.0;
constexpr int kBlock = 64;

} // namespace

int main(int argc, char* argv[])
{
    juce::ScopedJuceInitialiser_GUI juce;
    const double seconds = argc > 1 ? std::atof(argv[1]) : 4.0;   // audio rendered per scene
    juce::VST3PluginFormat format;
    juce::OwnedArray<juce::PluginDescription> types;
    format.findAllTypesForFile(types, ARMADILLO_VST3_PATH);
    if (types.isEmpty()) {
        std::fprintf(stderr, "cannot load %s\n", ARMADILLO_VST3_PATH);
        return 1;
    }
    juce::String error;
    auto plugin = format.createInstanceFromDescription(*types[0], kRate, kBlock, error);
    if (plugin == nullptr) {
        std::fprintf(stderr, "cannot instantiate: %s\n", error.toRawUTF8());
        return 1;
    }
    plugin->setPlayConfigDetails(0, 2, kRate, kBlock);
    plugin->prepareToPlay(kRate, kBlock);
    auto* scene = armadillo::bench::findParameter(*plugin, "Scene");
    auto* source = armadillo::bench::findParameter(*plugin, "Source");
    auto* elevation = armadillo::bench::findParameter(*plugin, "Elevation");
    auto* azimuth = armadillo::bench::findParameter(*plugin, "Azimuth");
    if (!scene || !source || !elevation || !azimuth) {
        std::fprintf(stderr, "contract parameters missing\n");
        return 1;
    }
    armadillo::bench::setChoice(source, "host automation");

    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    const double blockSeconds = kBlock / kRate;
    std::printf("processBlock cost, %g kHz / %d samples, VST3 hosted, elevation+azimuth automated every block\n",
                kRate / 1000.0, kBlock);
    std::printf("%-14s %10s %10s %10s %12s\n", "scene", "mean_us", "p99_us", "max_us", "core_%");
    for (int s = 0; s < scene->getNumSteps(); ++s) {
        const float v = static_cast<float>(s) / static_cast<float>(scene->getNumSteps() - 1);
        const auto name = scene->getText(v, 100);
        scene->setValueNotifyingHost(v);
        // Let the plugin's message thread build the scene, then warm up for 0.5 s of audio.
        for (int i = 0; i < 400; ++i) {
            plugin->processBlock(buffer, midi);
            midi.clear();
            juce::MessageManager::getInstance()->runDispatchLoopUntil(1);
        }
        const int blocks = static_cast<int>(seconds / blockSeconds);
        std::vector<double> us;
        us.reserve(static_cast<size_t>(blocks));
        for (int b = 0; b < blocks; ++b) {
            const double t = b * blockSeconds;
            elevation->setValue(static_cast<float>(0.5 + 0.4 * std::sin(2.0 * M_PI * 0.7 * t)));
            azimuth->setValue(static_cast<float>(0.5 + 0.1 * std::sin(2.0 * M_PI * 0.2 * t)));
            const auto start = std::chrono::steady_clock::now();
            plugin->processBlock(buffer, midi);
            const auto stop = std::chrono::steady_clock::now();
            midi.clear();
            us.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
        }
        std::vector<double> sorted = us;
        std::sort(sorted.begin(), sorted.end());
        double mean = 0.0;
        for (double x : us) mean += x;
        mean /= static_cast<double>(us.size());
        const double p99 = sorted[static_cast<size_t>(0.99 * static_cast<double>(sorted.size() - 1))];
        std::printf("%-14s %10.2f %10.2f %10.2f %11.3f%%\n", name.toRawUTF8(), mean, p99, sorted.back(),
                    100.0 * mean * 1.0e-6 / blockSeconds);
    }
    plugin->releaseResources();
    return 0;
}
