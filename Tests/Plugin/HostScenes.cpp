// armadillo_host_scenes PLUGIN.vst3 [VERSION]: hosts a VST3 of ARMadillo through JUCE's hosting
// classes (what a DAW does) and plays every scene, the score scene with both shipped scores,
// with a playing transport and automated orientation. It measures the audio and counts the motor
// levels the plugin sends on its OSC output (to a UDP port of this program). Used on the
// installed plugin by scripts/check-package.sh, and on the build's plugin by ctest (host_scenes).
// Exit 1 when a scene that must sound is silent, a score moves no motor, or the two scores
// move the motors alike; nothing here links the plugin's code.
#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_events/juce_events.h>
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "MotorListener.h"

namespace {

constexpr double kRate = 48000.0;
constexpr int kBlock = 480;   // 10 ms

/// A DAW's transport, playing from 0 s at 120 bpm.
class PlayingTransport final : public juce::AudioPlayHead {
public:
    juce::Optional<PositionInfo> getPosition() const override
    {
        PositionInfo info;
        info.setIsPlaying(true);
        info.setTimeInSamples(samples);
        info.setTimeInSeconds(static_cast<double>(samples) / kRate);
        info.setBpm(120.0);
        info.setPpqPosition(static_cast<double>(samples) / kRate * 2.0);
        return info;
    }
    juce::int64 samples = 0;
};

juce::AudioProcessorParameter* param(juce::AudioPluginInstance& p, const juce::String& name)
{
    for (auto* q : p.getParameters())
        if (q->getName(100) == name) return q;
    return nullptr;
}

void setChoice(juce::AudioPluginInstance& p, const juce::String& name, const juce::String& choice)
{
    auto* q = param(p, name);
    for (int i = 0; i < q->getNumSteps(); ++i) {
        const float v = static_cast<float>(i) / static_cast<float>(q->getNumSteps() - 1);
        if (q->getText(v, 100) == choice) {
            q->setValueNotifyingHost(v);
            return;
        }
    }
    std::fprintf(stderr, "no choice '%s' for %s\n", choice.toRawUTF8(), name.toRawUTF8());
    std::exit(1);
}

void setValue(juce::AudioPluginInstance& p, const juce::String& name, float value, float lo, float hi)
{
    param(p, name)->setValueNotifyingHost((value - lo) / (hi - lo));
}

/// The plugin's own state (docs/PLUGIN.md "State") with OSC out to `port` and the given score,
/// inside the document JUCE's VST3 host keeps it in (<VST3PluginState><IComponent>).
void setSettings(juce::AudioPluginInstance& p, int port, const juce::String& score)
{
    juce::MemoryBlock hostState;
    p.getStateInformation(hostState);
    auto outer = juce::AudioProcessor::getXmlFromBinary(hostState.getData(), static_cast<int>(hostState.getSize()));
    juce::MemoryBlock own;
    own.fromBase64Encoding(outer->getChildByName("IComponent")->getAllSubText());
    auto xml = juce::AudioProcessor::getXmlFromBinary(own.getData(), static_cast<int>(own.getSize()));
    auto* settings = xml->getChildByName("SETTINGS");
    settings->setAttribute("oscOutEnabled", 1);
    settings->setAttribute("oscOutHost", "127.0.0.1");
    settings->setAttribute("oscOutPort", port);
    settings->setAttribute("score", score);
    juce::MemoryBlock payload, blob;
    juce::AudioProcessor::copyXmlToBinary(*xml, payload);
    juce::XmlElement state("VST3PluginState");
    state.createNewChildElement("IComponent")->addTextElement(payload.toBase64Encoding());
    juce::AudioProcessor::copyXmlToBinary(state, blob);
    p.setStateInformation(blob.getData(), static_cast<int>(blob.getSize()));
}

int run(const juce::String& path, const juce::String& expectedVersion)
{
    juce::VST3PluginFormat format;
    juce::OwnedArray<juce::PluginDescription> types;
    format.findAllTypesForFile(types, path);
    if (types.size() != 1) {
        std::printf("FAIL: no plugin found in %s\n", path.toRawUTF8());
        return 1;
    }
    juce::String error;
    auto plugin = format.createInstanceFromDescription(*types[0], kRate, kBlock, error);
    if (plugin == nullptr) {
        std::printf("FAIL: %s\n", error.toRawUTF8());
        return 1;
    }
    std::printf("host: JUCE %s VST3 host loaded %s: '%s' version %s, instrument=%d\n", juce::SystemStats::getJUCEVersion().toRawUTF8(),
                path.toRawUTF8(), types[0]->name.toRawUTF8(), types[0]->version.toRawUTF8(), types[0]->isInstrument ? 1 : 0);
    bool failed = expectedVersion.isNotEmpty() && types[0]->version != expectedVersion;
    if (failed) std::printf("FAIL: the plugin reports version %s, expected %s\n", types[0]->version.toRawUTF8(), expectedVersion.toRawUTF8());

    PlayingTransport transport;
    plugin->setPlayHead(&transport);
    plugin->setPlayConfigDetails(0, 2, kRate, kBlock);
    plugin->prepareToPlay(kRate, kBlock);
    armadillo::test::host::MotorListener listener;
    // Scenes that must sound under this movement (the cymbal gets strikes: a swing faster than its
    // 150 deg/s strike speed; monitor, compass, braille and score make no sound by design).
    const std::set<juce::String> sounding {"theremin", "cymbal", "panel", "sound-design"};
    const juce::StringArray scenes {"monitor", "theremin", "cymbal", "panel", "sound-design", "compass", "braille", "score", "score"};
    std::vector<std::vector<int>> scorePatterns[2];
    int scoreRun = 0;
    for (const auto& scene : scenes) {
        const juce::String score = scene == "score" && scoreRun == 1 ? "polytope" : "rite-of-spring";
        setSettings(*plugin, listener.port(), score);
        setChoice(*plugin, "Source", "host automation");
        setChoice(*plugin, "Scene", scene);
        transport.samples = 0;
        juce::AudioBuffer<float> buffer(2, kBlock);
        juce::MidiBuffer midi;
        double sum = 0.0;
        long samples = 0;
        bool finite = true;
        std::vector<std::vector<int>> motors;
        const int blocks = static_cast<int>(10.0 * kRate / kBlock);
        for (int b = 0; b < blocks; ++b) {
            const double t = b * kBlock / kRate;
            const double period = scene == "cymbal" ? 1.0 : 4.0;   // s; the cymbal: up to 250 deg/s
            setValue(*plugin, "Elevation", static_cast<float>(40.0 * std::sin(2.0 * M_PI * t / period)), -90.0f, 90.0f);
            setValue(*plugin, "Azimuth", static_cast<float>(std::fmod(360.0 + 20.0 * std::sin(2.0 * M_PI * t / 6.0), 360.0)), 0.0f, 360.0f);
            setValue(*plugin, "Roll", static_cast<float>(70.0 * std::sin(2.0 * M_PI * t / 1.5)), -180.0f, 180.0f);
            buffer.clear();
            midi.clear();
            plugin->processBlock(buffer, midi);
            transport.samples += kBlock;
            // In real time: the plugin builds engines on its message thread and sends OSC from
            // its control clock, as under a DAW.
            juce::MessageManager::getInstance()->runDispatchLoopUntil(static_cast<int>(1000.0 * kBlock / kRate));
            if (t < 1.0) {   // the scene swaps in on the message thread: the previous one's motors are dropped
                listener.drain();
                continue;
            }
            for (int c = 0; c < 2; ++c)
                for (int i = 0; i < kBlock; ++i) {
                    const float s = buffer.getSample(c, i);
                    finite = finite && std::isfinite(s);
                    sum += double(s) * s;
                    ++samples;
                }
            for (auto& m : listener.drain()) motors.push_back(std::move(m));
        }
        const double rms = std::sqrt(sum / double(std::max(1L, samples)));
        int moving = 0, highest = 0;
        for (const auto& m : motors) {
            int top = 0;
            for (int v : m) top = std::max(top, v);
            moving += top > 0;
            highest = std::max(highest, top);
        }
        const bool isScore = scene == "score";
        if (isScore) {
            for (const auto& m : motors)
                if (*std::max_element(m.begin(), m.end()) > 0) scorePatterns[scoreRun].push_back(m);
        }
        const bool ok = finite && highest <= 15 && (sounding.count(scene) == 0 || rms > 1e-3) && (!isScore || moving > 0);
        std::printf("%-4s %-28s audio rms %.4f, %zu motor messages, %d with a motor on, highest level %d\n", ok ? "ok" : "FAIL",
                    (scene + (isScore ? " (" + score + ")" : juce::String())).toRawUTF8(), rms, motors.size(), moving, highest);
        failed = failed || !ok;
        if (isScore) ++scoreRun;
    }
    const auto first = [](const std::vector<std::vector<int>>& v) { return std::vector<std::vector<int>>(v.begin(), v.begin() + std::min<std::size_t>(v.size(), 100)); };
    if (first(scorePatterns[0]) == first(scorePatterns[1])) {
        std::printf("FAIL: the two scores moved the motors alike\n");
        failed = true;
    }
    plugin->releaseResources();
    return failed ? 1 : 0;
}

} // namespace

int main(int argc, char* argv[])
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: armadillo_host_scenes PLUGIN.vst3 [EXPECTED_VERSION]\n");
        return 2;
    }
    juce::ScopedJuceInitialiser_GUI juce;
    return run(juce::File::getCurrentWorkingDirectory().getChildFile(argv[1]).getFullPathName(), argc > 2 ? argv[2] : "");
}
