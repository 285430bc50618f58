#include "Plugin/PluginState.h"
#include "Core/Version.h"
#include "Link/TouchProfile.h"
#include "Procedures/AdaptiveTraining.h"
#include "Tactors/TactorRenderer.h"
#include <cmath>
#include <limits>

namespace armadillo::plugin::PluginState {

juce::ValueTree defaultSettings()
{
    juce::ValueTree s(SettingIds::root);
    s.setProperty(SettingIds::oscOutEnabled, false, nullptr);
    s.setProperty(SettingIds::oscOutHost, "127.0.0.1", nullptr);
    s.setProperty(SettingIds::oscOutPort, 9000, nullptr);
    s.setProperty(SettingIds::oscInEnabled, false, nullptr);
    s.setProperty(SettingIds::oscInPort, 9001, nullptr);
    s.setProperty(SettingIds::oscInFormat, "", nullptr);
    s.setProperty(SettingIds::oscInMount, "", nullptr);
    s.setProperty(SettingIds::serialPort, "", nullptr);
    s.setProperty(SettingIds::baudRate, 57600, nullptr);
    s.setProperty(SettingIds::calibrationFile, "", nullptr);
    s.setProperty(SettingIds::armSide, "right", nullptr);
    s.setProperty(SettingIds::backMotors, false, nullptr);
    s.setProperty(SettingIds::brailleText, "armadillo", nullptr);
    s.setProperty(SettingIds::score, "rite-of-spring", nullptr);
    s.setProperty(SettingIds::midiChannel, 1, nullptr);
    s.setProperty(SettingIds::editorWidth, 1040, nullptr);
    s.setProperty(SettingIds::editorHeight, 700, nullptr);
    s.setProperty(SettingIds::simWandering, true, nullptr);
    s.setProperty(SettingIds::connectOnStart, false, nullptr);
    s.setProperty(SettingIds::readerVoice, "auto", nullptr);
    s.setProperty(SettingIds::speechRate, 0, nullptr);
    s.setProperty(SettingIds::armFeedback, false, nullptr);
    s.setProperty(SettingIds::touchProfile, "", nullptr);
    s.setProperty(SettingIds::setList, "", nullptr);
    s.setProperty(SettingIds::setListName, "", nullptr);
    s.setProperty(SettingIds::cueNextNote, 0, nullptr);   // Stage::kNextNote
    s.setProperty(SettingIds::cuePrevNote, 1, nullptr);   // Stage::kPrevNote
    s.setProperty(SettingIds::stageOscEnabled, false, nullptr);
    s.setProperty(SettingIds::stageOscPort, 9002, nullptr);
    s.setProperty(SettingIds::stageOscBind, "127.0.0.1", nullptr);
    s.setProperty(SettingIds::stageOscAllow, "", nullptr);
    s.setProperty(SettingIds::panicGesture, false, nullptr);
    s.setProperty(SettingIds::leftArmOsc, false, nullptr);
    s.setProperty(SettingIds::leftArmOscPort, 9003, nullptr);
    s.setProperty(SettingIds::adaptiveTrials, 20, nullptr);
    s.setProperty(SettingIds::adaptiveStages, "letters,words", nullptr);
    s.setProperty(SettingIds::adaptiveMethod, "rows", nullptr);
    s.setProperty(SettingIds::adaptiveLevel, 8, nullptr);
    s.setProperty(SettingIds::readerProfile, "", nullptr);
    s.setProperty(SettingIds::tactorModel, "erm", nullptr);
    s.setProperty(SettingIds::tactorMap, "", nullptr);
    s.setProperty(SettingIds::tactorGains, "", nullptr);
    s.setProperty(SettingIds::tactorSound, false, nullptr);
    s.setProperty(SettingIds::tactorOutput, false, nullptr);
    s.setProperty(SettingIds::mqttEnabled, false, nullptr);
    s.setProperty(SettingIds::webEnabled, false, nullptr);
    s.setProperty(SettingIds::webPort, 0, nullptr);
    s.setProperty(SettingIds::webBind, "", nullptr);
    s.setProperty(SettingIds::mqttBroker, "localhost:1883", nullptr);
    s.setProperty(SettingIds::mqttTopics, "arm/inbox", nullptr);
    s.setProperty(SettingIds::mqttUrgent, "", nullptr);
    s.setProperty(SettingIds::mqttConfig, "", nullptr);
    s.setProperty(SettingIds::messageDisplay, "roll", nullptr);
    s.setProperty(SettingIds::tactorDevice, "", nullptr);
    s.setProperty(SettingIds::tactorConnect, "", nullptr);
    return s;
}

void installSettings(juce::ValueTree& settings, const juce::ValueTree& loaded)
{
    // Start from the defaults and take only known properties of the right kind and range.
    const auto defaults = defaultSettings();
    for (int i = 0; i < defaults.getNumProperties(); ++i) {
        const auto id = defaults.getPropertyName(i);
        const auto& fallback = defaults[id];
        juce::var value = fallback;
        if (loaded.isValid() && loaded.hasProperty(id)) {
            const auto& v = loaded[id];
            if (fallback.isBool()) value = static_cast<bool>(v);
            else if (fallback.isInt()) value = static_cast<int>(v);
            else value = v.toString().substring(0, id == SettingIds::setList ? kMaxSetListChars : 4096);
        }
        settings.setProperty(id, value, nullptr);
    }
    auto clampInt = [&settings](const juce::Identifier& id, int lo, int hi, int fallback) {
        const int v = static_cast<int>(settings[id]);
        settings.setProperty(id, v < lo || v > hi ? fallback : v, nullptr);
    };
    clampInt(SettingIds::oscOutPort, 1, 65535, 9000);
    clampInt(SettingIds::oscInPort, 1, 65535, 9001);
    clampInt(SettingIds::baudRate, 1200, 4000000, 57600);
    clampInt(SettingIds::midiChannel, 1, 16, 1);
    clampInt(SettingIds::editorWidth, 400, 8000, 1040);
    clampInt(SettingIds::editorHeight, 300, 8000, 700);
    if (settings[SettingIds::armSide].toString() != "left") settings.setProperty(SettingIds::armSide, "right", nullptr);
    if (settings[SettingIds::score].toString().isEmpty()) settings.setProperty(SettingIds::score, "rite-of-spring", nullptr);
    if (settings[SettingIds::messageDisplay].toString() != "timed") settings.setProperty(SettingIds::messageDisplay, "roll", nullptr);
    if (tactors::TactorModel m; ! tactors::parseModel(settings[SettingIds::tactorModel].toString().toStdString(), m))
        settings.setProperty(SettingIds::tactorModel, "erm", nullptr);
    clampInt(SettingIds::speechRate, -100, 100, 0);
    clampInt(SettingIds::cueNextNote, -1, 127, 0);
    clampInt(SettingIds::cuePrevNote, -1, 127, 1);
    clampInt(SettingIds::stageOscPort, 0, 65535, 9002);
    clampInt(SettingIds::leftArmOscPort, 1, 65535, 9003);
    clampInt(SettingIds::webPort, 0, 65535, 0);
    // The set list's text is checked (parsed, every cue prepared) by the processor, which says
    // in the status line why a saved one is not used (ArmadilloProcessor::applySavedSetList).
    const auto voice = settings[SettingIds::readerVoice].toString();
    if (voice != "on" && voice != "off") settings.setProperty(SettingIds::readerVoice, "auto", nullptr);
    clampInt(SettingIds::adaptiveTrials, 1, 10000, 20);
    clampInt(SettingIds::adaptiveLevel, 1, 15, 8);
    if (const auto m = settings[SettingIds::adaptiveMethod].toString(); m != "rows" && m != "whole" && m != "columns" && m != "dots")
        settings.setProperty(SettingIds::adaptiveMethod, "rows", nullptr);
    {
        procedures::AdaptiveChoices c;   // the stages as the session checks them
        c.stages = settings[SettingIds::adaptiveStages].toString().toStdString();
        if (! c.problem().empty()) settings.setProperty(SettingIds::adaptiveStages, "letters,words", nullptr);
    }
    // A touch profile is kept only when it parses (Link/TouchProfile.h), so the engine never gets
    // a gain from a damaged state; a refused one means none (every motor gain 1).
    if (const auto json = settings[SettingIds::touchProfile].toString(); json.isNotEmpty()) {
        try {
            (void) link::parseTouchProfile(json.toStdString(), "the saved touch profile");
        } catch (const std::exception&) {
            settings.setProperty(SettingIds::touchProfile, "", nullptr);
        }
    }
}

void resetToDefaults(juce::AudioProcessor& processor, juce::ValueTree& settings)
{
    for (auto* p : processor.getParameters())
        if (auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p))
            ranged->setValueNotifyingHost(ranged->getDefaultValue());
    installSettings(settings, {});
}

void save(juce::AudioProcessorValueTreeState& parameters, const juce::ValueTree& settings, juce::MemoryBlock& dest,
          const juce::ValueTree& mapping)
{
    juce::ValueTree root("ARMADILLO");
    root.setProperty("version", kVersion, nullptr);
    root.setProperty("pluginVersion", juce::String(std::string(armadillo::core::kVersion)), nullptr); // project(VERSION)
    root.appendChild(parameters.copyState(), nullptr);
    root.appendChild(settings.createCopy(), nullptr);
    if (mapping.isValid()) root.appendChild(mapping.createCopy(), nullptr);   // additive: older builds ignore it
    if (auto xml = root.createXml()) juce::AudioProcessor::copyXmlToBinary(*xml, dest);
}

juce::String restore(juce::AudioProcessor& processor, juce::AudioProcessorValueTreeState& parameters,
                     juce::ValueTree& settings, const void* data, int sizeInBytes, juce::ValueTree* mapping)
{
    if (mapping != nullptr) *mapping = juce::ValueTree();
    std::unique_ptr<juce::XmlElement> xml;
    if (data != nullptr && sizeInBytes > 0) xml = juce::AudioProcessor::getXmlFromBinary(data, sizeInBytes);
    const auto root = xml != nullptr ? juce::ValueTree::fromXml(*xml) : juce::ValueTree();
    juce::String problem;
    if (! root.isValid() || ! root.hasType("ARMADILLO"))
        problem = "The saved state is not an ARMadillo state (damaged or from another plugin)";
    else if (static_cast<int>(root["version"]) < 1 || static_cast<int>(root["version"]) > kVersion)
        problem = "The saved state has format version " + root["version"].toString() + ", this build reads up to "
                  + juce::String(kVersion);
    if (problem.isNotEmpty()) {
        resetToDefaults(processor, settings);
        return problem + "; defaults loaded.";
    }

    const auto saved = root.getChildWithName(parameters.state.getType());
    int rejected = 0;
    for (auto* p : processor.getParameters()) {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p);
        if (ranged == nullptr) continue;
        const auto node = saved.getChildWithProperty("id", ranged->getParameterID());
        const double v = node.isValid() ? static_cast<double>(node["value"]) : std::numeric_limits<double>::quiet_NaN();
        if (node.isValid() && ! std::isfinite(v)) ++rejected;
        const auto& range = ranged->getNormalisableRange();
        const float value = std::isfinite(v) ? juce::jlimit(range.start, range.end, static_cast<float>(v))
                                             : range.convertFrom0to1(ranged->getDefaultValue());
        ranged->setValueNotifyingHost(ranged->convertTo0to1(value));
    }
    installSettings(settings, root.getChildWithName(SettingIds::root));
    if (mapping != nullptr) *mapping = root.getChildWithName("MAPPING").createCopy();
    return rejected > 0 ? juce::String(rejected) + " saved parameter values were not numbers; defaults used for them."
                        : juce::String();
}

juce::String writeSetupFile(const juce::MemoryBlock& state, const juce::File& file)
{
    const auto xml = juce::AudioProcessor::getXmlFromBinary(state.getData(), static_cast<int>(state.getSize()));
    if (xml == nullptr) return "the current state could not be read";
    juce::TemporaryFile tmp(file);   // written beside the target, then moved over it
    if (!xml->writeTo(tmp.getFile()) || !tmp.overwriteTargetFileWithTemporary())
        return "cannot write " + file.getFullPathName();
    return {};
}

juce::String readSetupFile(const juce::File& file, juce::MemoryBlock& state)
{
    if (!file.existsAsFile()) return "no such file: " + file.getFullPathName();
    if (file.getSize() > 1024 * 1024) return file.getFileName() + " is too large to be a setup";
    const auto xml = juce::parseXML(file);
    if (xml == nullptr || !xml->hasTagName("ARMADILLO")) return file.getFileName() + " is not an ARMadillo setup";
    state.reset();
    juce::AudioProcessor::copyXmlToBinary(*xml, state);
    return {};
}

namespace {
const juce::Identifier kMappingRoot {"MAPPING"};   // child of the saved state
const juce::Identifier kMappingName {"name"};      // preset name or file name it came from
const juce::Identifier kMappingJson {"json"};      // the document (docs/MAPPING.md)
const juce::Identifier kMappingForward {"forward"};   // the forward reference, azimuth deg
} // namespace

juce::ValueTree mappingNode(const live::SavedMapping& saved)
{
    juce::ValueTree node(kMappingRoot);
    node.setProperty(kMappingName, juce::String(saved.name), nullptr);
    node.setProperty(kMappingJson, juce::String(saved.json), nullptr);
    node.setProperty(kMappingForward, saved.forward, nullptr);
    return node;
}

live::SavedMapping savedMapping(const juce::ValueTree& node)
{
    live::SavedMapping saved;
    if (! node.isValid() || ! node.hasType(kMappingRoot)) return saved;
    saved.present = true;
    saved.name = node[kMappingName].toString().toStdString();
    saved.json = node[kMappingJson].toString().toStdString();
    saved.forward = static_cast<double>(node[kMappingForward]);
    return saved;
}

live::TactorSettings tactorSettings(const juce::ValueTree& settings)
{
    live::TactorSettings t;
    t.model = settings[SettingIds::tactorModel].toString().toStdString();
    t.map = settings[SettingIds::tactorMap].toString().toStdString();
    t.gains = settings[SettingIds::tactorGains].toString().toStdString();
    t.sound = static_cast<bool>(settings[SettingIds::tactorSound]);
    t.device = settings[SettingIds::tactorDevice].toString().toStdString();
    t.connect = settings[SettingIds::tactorConnect].toString().toStdString();
    return t;
}

live::MessagesSettings messagesSettings(const juce::ValueTree& settings)
{
    live::MessagesSettings m;
    m.configFile = settings[SettingIds::mqttConfig].toString().toStdString();
    m.broker = settings[SettingIds::mqttBroker].toString().toStdString();
    m.topics = settings[SettingIds::mqttTopics].toString().toStdString();
    m.urgent = settings[SettingIds::mqttUrgent].toString().toStdString();
    m.timed = settings[SettingIds::messageDisplay].toString() == "timed";
    return m;
}

} // namespace armadillo::plugin::PluginState
