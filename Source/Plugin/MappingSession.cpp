#include "Plugin/MappingSession.h"
#include "Osc/OscIo.h"
#include "Plugin/Connections.h"
#include <cmath>
#include <exception>

namespace armadillo::plugin {

namespace {
constexpr const char* kDefaultPreset = "classic";
constexpr std::size_t kMaxStateJsonBytes = 1024 * 1024;   // a state's mapping larger than this is refused

bool isMidi(mapping::DestinationKind k) noexcept
{
    using K = mapping::DestinationKind;
    return k == K::Cc7 || k == K::Cc14 || k == K::Nrpn || k == K::PitchBend || k == K::ChannelPressure || k == K::Notes
           || k == K::ProgramChange;
}
} // namespace

MappingSession::MappingSession(live::BlockControl& control, Connections& connections, const SceneParameterTable& table,
                               std::function<int()> defaultChannel)
    : control_(control), connections_(connections), table_(table), defaultChannel_(std::move(defaultChannel))
{
}

MappingSession::~MappingSession() = default;

juce::StringArray MappingSession::presets() const
{
    juce::StringArray names;
    try {
        for (const auto& n : mapping::presetNames()) names.add(juce::String(n));
    } catch (const std::exception&) {
        // An unreadable user folder: the built-in presets are listed by the core anyway.
    }
    return names;
}

mapping::MappingDocument MappingSession::withClassicChannel(mapping::MappingDocument doc, const juce::String& preset) const
{
    // The classic preset is the plugin's wiring from before the mapping: it keeps honouring the
    // `midiChannel` setting those sessions saved (docs/PLUGIN.md "MIDI out").
    if (preset != kDefaultPreset || ! defaultChannel_) return doc;
    const int channel = juce::jlimit(1, 16, defaultChannel_());
    for (auto& m : doc.mappings)
        if (isMidi(m.to.kind)) m.to.channel = channel;
    return doc;
}

juce::String MappingSession::setDocument(const mapping::MappingDocument& doc, const juce::String& name)
{
    mapping::BuildOptions options;
    for (const auto& entry : table_.scenes)
        for (std::size_t i = 0; i < entry.specs.size(); ++i)
            if (entry.exposed[i]) options.sceneParamIds.push_back(entry.specs[i].id);
    options.sourceName = name.toStdString();
    std::unique_ptr<mapping::MappingSet> set;
    try {
        set = mapping::MappingSet::build(doc, options);
    } catch (const std::exception& e) {
        return juce::String(e.what());
    }
    configureOscTargets(*set);
    macrosUsed_ = set->macrosUsed();
    doc_ = doc;
    name_ = name;
    waiting_ = std::move(set);   // a set built earlier and still waiting is replaced (freed here)
    offerWaiting();
    return {};
}

void MappingSession::offerWaiting()
{
    auto& mapper = control_.mapper();
    if (controlStopped_) {
        if (waiting_ != nullptr) mapper.replace(std::move(waiting_));
        return;
    }
    mapper.collect();   // the set the control side gave up: freed here, on the message thread
    if (waiting_ != nullptr && mapper.offer(waiting_)) waiting_.reset();
}

void MappingSession::configureOscTargets(const mapping::MappingSet& set)
{
    std::vector<device::HostPort> targets;
    for (const auto& t : set.oscTargets())
        targets.push_back(device::HostPort {t.host.empty() ? oscHost_.toStdString() : t.host, t.port > 0 ? t.port : oscPort_});
    const auto why = connections_.configureMappingOsc(targets);
    juce::ignoreUnused(why);   // shown by the editor's status line through Connections::linkStatus
}

void MappingSession::setDefaultOscTarget(const juce::String& host, int port)
{
    oscHost_ = host.isEmpty() ? juce::String("127.0.0.1") : host;
    oscPort_ = port > 0 && port <= 65535 ? port : 9000;
    if (auto* set = liveSet()) configureOscTargets(*set);
}

juce::String MappingSession::usePreset(const juce::String& preset)
{
    mapping::MappingDocument doc;
    try {
        doc = mapping::loadMapping(preset.toStdString());
    } catch (const std::exception& e) {
        return juce::String(e.what());
    }
    return setDocument(withClassicChannel(std::move(doc), preset), preset);
}

juce::String MappingSession::loadFile(const juce::File& file)
{
    if (! file.existsAsFile()) return "no such file: " + file.getFullPathName();
    if (file.getSize() > static_cast<juce::int64>(kMaxStateJsonBytes)) return file.getFullPathName() + " is too large for a mapping file";
    mapping::MappingDocument doc;
    try {
        doc = mapping::parseMappingDocument(file.loadFileAsString().toStdString(), file.getFullPathName().toStdString());
    } catch (const std::exception& e) {
        return juce::String(e.what());
    }
    return setDocument(doc, file.getFileName());
}

juce::String MappingSession::saveFile(const juce::File& file) const
{
    juce::TemporaryFile tmp(file);
    if (! tmp.getFile().replaceWithText(juce::String(mapping::toJson(doc_))) || ! tmp.overwriteTargetFileWithTemporary())
        return "cannot write " + file.getFullPathName();
    return {};
}

void MappingSession::setMuted(int index, bool muted)
{
    if (index < 0 || index >= static_cast<int>(doc_.mappings.size())) return;
    doc_.mappings[static_cast<std::size_t>(index)].muted = muted;
    const auto i = static_cast<std::size_t>(index);
    if (auto* set = liveSet(); set != nullptr && i < set->size()) set->setMuted(i, muted);
    if (waiting_ != nullptr && i < waiting_->size()) waiting_->setMuted(i, muted);
}

float MappingSession::meter(int index) noexcept
{
    auto* set = liveSet();
    return set != nullptr && index >= 0 && static_cast<std::size_t>(index) < set->size() ? set->meter(static_cast<std::size_t>(index))
                                                                                          : std::nanf("");
}

bool MappingSession::active(int index) noexcept
{
    auto* set = liveSet();
    return set != nullptr && index >= 0 && static_cast<std::size_t>(index) < set->size() && set->active(static_cast<std::size_t>(index));
}

juce::ValueTree MappingSession::toState() const
{
    juce::ValueTree node(MappingIds::root);
    node.setProperty(MappingIds::name, name_, nullptr);
    node.setProperty(MappingIds::json, juce::String(mapping::toJson(doc_)), nullptr);
    node.setProperty(MappingIds::forward, control_.mapper().forwardAzimuth(), nullptr);
    return node;
}

juce::String MappingSession::fromState(const juce::ValueTree& node)
{
    if (! node.isValid() || ! node.hasType(MappingIds::root)) {
        control_.mapper().setForwardAzimuth(0.0);
        return usePreset(kDefaultPreset);   // a state from before the mapping: its wiring
    }
    const auto name = node[MappingIds::name].toString().substring(0, 256);
    const auto json = node[MappingIds::json].toString();
    const double forward = static_cast<double>(node[MappingIds::forward]);
    control_.mapper().setForwardAzimuth(std::isfinite(forward) ? std::fmod(std::fmod(forward, 360.0) + 360.0, 360.0) : 0.0);
    juce::String why;
    if (json.trim().isEmpty() && name.isNotEmpty()) {
        why = usePreset(name);   // a hand-written setup may name a preset instead of holding one
    } else if (json.getNumBytesAsUTF8() > kMaxStateJsonBytes) {
        why = "the saved mapping is too large";
    } else {
        try {
            const auto doc = mapping::parseMappingDocument(json.toStdString(), "saved mapping '" + name.toStdString() + "'");
            why = setDocument(doc, name.isEmpty() ? juce::String("saved") : name);
        } catch (const std::exception& e) {
            why = juce::String(e.what());
        }
    }
    if (why.isEmpty()) return {};
    const auto fallback = usePreset(kDefaultPreset);
    return "The saved mapping was refused (" + why + "); the classic preset runs instead."
           + (fallback.isEmpty() ? juce::String() : " " + fallback);
}

bool MappingSession::startRangeLearn(int index, juce::String& why)
{
    if (index < 0 || index >= static_cast<int>(doc_.mappings.size())) {
        why = "Choose a mapping first.";
        return false;
    }
    const auto& source = doc_.mappings[static_cast<std::size_t>(index)].source;
    if (mapping::isEventSource(source.kind)) {
        why = "An event source (gesture, posture) has no range to learn.";
        return false;
    }
    auto& out = control_.mappingOutputs();
    out.learnedCount.store(0, std::memory_order_relaxed);
    out.learnForward.store(doc_.mappings[static_cast<std::size_t>(index)].transform.forward, std::memory_order_relaxed);
    out.learnGeneration.fetch_add(1, std::memory_order_release);
    out.learnSource.store(static_cast<int>(source.kind), std::memory_order_release);
    rangeIndex_ = index;
    why.clear();
    return true;
}

bool MappingSession::learnedRange(double& lo, double& hi) const
{
    auto& out = control_.mappingOutputs();
    if (rangeIndex_ < 0 || out.learnedCount.load(std::memory_order_acquire) < 2) return false;
    lo = out.learnedLo.load(std::memory_order_relaxed);
    hi = out.learnedHi.load(std::memory_order_relaxed);
    return hi > lo;
}

juce::String MappingSession::finishRangeLearn(bool apply)
{
    control_.mappingOutputs().learnSource.store(-1, std::memory_order_release);
    const int index = rangeIndex_;
    rangeIndex_ = -1;
    double lo = 0.0, hi = 0.0;
    if (! apply || index < 0 || index >= static_cast<int>(doc_.mappings.size())) return {};
    auto& out = control_.mappingOutputs();
    if (out.learnedCount.load(std::memory_order_acquire) < 2 || ! ((hi = out.learnedHi.load()) > (lo = out.learnedLo.load())))
        return "Nothing to learn: move the arm over the range you want while learning.";
    auto doc = doc_;
    auto& t = doc.mappings[static_cast<std::size_t>(index)].transform;
    t.hasIn = true;
    t.inLo = lo;
    t.inHi = hi;
    auto why = setDocument(doc, "edited");
    return why.isEmpty() ? "Range learned: " + juce::String(lo, 1) + " to " + juce::String(hi, 1) + "." : why;
}

void MappingSession::timerTick()
{
    offerWaiting();
    // Destination learn: the channel messages that arrived since the last tick, in order (a CC
    // 0–31 followed by its +32 partner is a 14-bit pair); anything else is drained and dropped.
    std::uint8_t bytes[96];
    int size = 0;
    live::IncomingMidi m;
    while (control_.mappingOutputs().popIncoming(m))
        if (size + m.size <= static_cast<int>(sizeof bytes))
            for (int i = 0; i < m.size; ++i) bytes[size++] = m.bytes[i];
    const int index = destinationIndex_;
    if (size > 0 && index >= 0 && index < static_cast<int>(doc_.mappings.size())) {
        auto doc = doc_;
        auto& to = doc.mappings[static_cast<std::size_t>(index)].to;
        mapping::DestinationSpec learned = to;
        if (mapping::learnDestination(bytes, size, learned)) {
            to = learned;
            destinationIndex_ = -1;
            const auto why = setDocument(doc, "edited");
            notice_ = why.isEmpty() ? "Destination learned: " + juce::String(learned.channel) + "/" + juce::String(learned.number) + "." : why;
        }
    }
    // Macros no mapping drives any longer stop being written (their parameters keep the value).
    for (int k = 0; k < ParamIds::kMacroCount; ++k)
        if (((macrosUsed_ >> k) & 1u) == 0) control_.mappingOutputs().releaseMacro(k);
}

} // namespace armadillo::plugin
