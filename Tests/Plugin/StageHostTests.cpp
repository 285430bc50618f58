// On stage through a host (issue 28): the built VST3 loaded with JUCE's VST3 hosting, as a DAW
// does, given a state whose settings hold a four-cue set list; its cues stepped by the cue note
// (note 0, docs/INTERFACES.md "MIDI implementation") at the MIDI input: each switch without a
// discontinuity above -60 dBFS beyond the signal's own, no allocation in the plugin's blocks;
// CC 120 at the input silences it within the block. (Program change cannot be tested here: VST3
// has no program-change event; Tests/Plugin/StageTests.cpp steps by program change through
// processBlock itself.)
#include "Plugin/HostedPlugin.h"

using namespace armadillo::test::host;

namespace {
// Silent and sounding cues in turn, so each step is heard (or not) in the output.
const char* kCues = R"({"armadillo_setlist": 1, "cues": [
  {"name": "Quiet", "scene": "monitor"},
  {"name": "Tone", "scene": "theremin"},
  {"name": "Quiet again", "scene": "monitor"},
  {"name": "Wide", "scene": "theremin", "parameters": {"theremin.range": 24}}]})";

void setVst3State(Hosted& h, const juce::String& ownXml)
{
    auto own = juce::parseXML(ownXml);
    REQUIRE(own != nullptr);
    juce::MemoryBlock payload;
    juce::AudioProcessor::copyXmlToBinary(*own, payload);
    juce::XmlElement state("VST3PluginState");   // JUCE's VST3 wrapper's state document
    state.createNewChildElement("IComponent")->addTextElement(payload.toBase64Encoding());
    juce::MemoryBlock blob;
    juce::AudioProcessor::copyXmlToBinary(state, blob);
    h.plugin->setStateInformation(blob.getData(), static_cast<int>(blob.getSize()));
}

double rmsOf(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double s = 0.0;
    for (std::size_t i = from; i < to; ++i) s += static_cast<double>(x[i]) * x[i];
    return std::sqrt(s / static_cast<double>(to - from));
}

double maxStep(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double m = 0.0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < std::min(to, x.size()); ++i)
        m = std::max(m, std::fabs(static_cast<double>(x[i]) - x[i - 1]));
    return m;
}
} // namespace

TEST_CASE("VST3: a set list in the state, stepped by the cue note, switches click-free; CC 120 silences", "[plugin][stage]")
{
    ARMADILLO_REQUIRE_GUARD();
    {
        armadillo::test::RealtimeGuard probe;   // the guard sees an allocation before its zero is trusted
        auto p = std::make_unique<double>(1.0);
        CHECK(probe.allocations() >= 1);
    }
    auto h = loadVst3();
    const auto json = juce::String(kCues).replace("&", "&amp;").replace("\"", "&quot;").replace("<", "&lt;");
    // source 3 = host automation (the arm holds still at the parameters' values)
    setVst3State(h, "<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"source\" value=\"3\"/><PARAM id=\"elevation\" value=\"10\"/>"
                    "</PARAMETERS><SETTINGS setList=\"" + json + "\" setListName=\"show.json\"/></ARMADILLO>");
    prepare(h);
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    midi.ensureSize(8192);
    std::vector<float> out;
    const int blocksPerCue = static_cast<int>(kRate) / kBlock;   // ~1 s each
    out.reserve(static_cast<std::size_t>((4 * blocksPerCue + 40) * kBlock));
    // Warm-up: JUCE's VST3 hosting side allocates in its first block and grows its event lists
    // the first time a block carries an event in (HostedPlugin.h): a note the stage ignores.
    for (int b = 0; b < 20; ++b) {
        buffer.clear();
        midi.clear();
        if (b == 10) midi.addEvent(juce::MidiMessage::noteOn(1, 60, 0.5f), 5);
        h.plugin->processBlock(buffer, midi);
    }
    std::vector<std::size_t> switches;
    std::uint64_t allocations = 0, throws = 0;
    const auto next = juce::MidiMessage::noteOn(1, 0, 1.0f);   // the cue note (default 0)
    for (int b = 0; b < 4 * blocksPerCue; ++b) {
        buffer.clear();
        midi.clear();
        if (b > 0 && b % blocksPerCue == 0 && b / blocksPerCue <= 3) {
            midi.addEvent(next, 10);
            switches.push_back(out.size());   // it acts at the block's start
        }
        {
            armadillo::test::RealtimeGuard guard;
            h.plugin->processBlock(buffer, midi);
            allocations += guard.allocations();
            throws += guard.throws();
        }
        for (int i = 0; i < kBlock; ++i) out.push_back(buffer.getSample(0, i));
    }
    REQUIRE(switches.size() == 3);
    // Each cue as itself: quiet, tone, quiet, tone (the steps arrived).
    const auto fade = static_cast<std::size_t>(0.05 * kRate) + kBlock;
    const auto segment = [&](int cue) {
        const std::size_t from = (cue == 0 ? kBlock * 20 : switches[static_cast<std::size_t>(cue - 1)] + fade);
        const std::size_t to = cue < 3 ? switches[static_cast<std::size_t>(cue)] : out.size();
        return rmsOf(out, from, to);
    };
    CHECK(segment(0) < 1e-4);
    CHECK(segment(1) > 0.01);
    CHECK(segment(2) < 1e-4);
    CHECK(segment(3) > 0.01);
    const double minus60 = std::pow(10.0, -60.0 / 20.0);
    for (const auto s : switches) {
        const double around = std::max(maxStep(out, s - 9600, s), maxStep(out, s + fade, s + fade + 9600));
        const double excess = std::max(0.0, maxStep(out, s, s + fade) - around);
        std::printf("VST3 set list: cue note at sample %zu: largest step above its neighbourhood %.2e\n", s, excess);
        CHECK(excess <= minus60);
    }
    CHECK(allocations == 0);
    CHECK(throws == 0);

    // CC 120 (All Sound Off) at the MIDI input, as the host hands it to the VST3.
    buffer.clear();
    midi.clear();
    midi.addEvent(juce::MidiMessage::allSoundOff(1), 0);
    h.plugin->processBlock(buffer, midi);
    float tail = 0.0f;
    for (int i = 48; i < kBlock; ++i) tail = std::max(tail, std::fabs(buffer.getSample(0, i)));
    INFO("samples 48.. of the block after CC 120: largest " << tail);
    CHECK(tail == 0.0f);
}
