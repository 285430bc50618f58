#include "Live/Outputs/MappingSession.h"
#include "Core/AtomicFile.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>

namespace armadillo::live {

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

MappingSession::MappingSession(BlockControl& control, const SceneParameterTable& table, std::function<int()> defaultChannel,
                               OscTargets oscTargets)
    : control_(control), table_(table), defaultChannel_(std::move(defaultChannel)), oscTargets_(std::move(oscTargets))
{
}

MappingSession::~MappingSession() = default;

std::vector<std::string> MappingSession::presets() const
{
    std::vector<std::string> names;
    try {
        names = mapping::presetNames();
    } catch (const std::exception&) {
        // An unreadable user folder: the built-in presets are listed by the core anyway.
    }
    return names;
}

mapping::MappingDocument MappingSession::withClassicChannel(mapping::MappingDocument doc, const std::string& preset) const
{
    // The classic preset is the plugin's wiring from before the mapping: it keeps honouring the
    // `midiChannel` setting those sessions saved (docs/PLUGIN.md "MIDI out").
    if (preset != kDefaultPreset || ! defaultChannel_) return doc;
    const int channel = std::clamp(defaultChannel_(), 1, 16);
    for (auto& m : doc.mappings)
        if (isMidi(m.to.kind)) m.to.channel = channel;
    return doc;
}

std::string MappingSession::setDocument(const mapping::MappingDocument& doc, const std::string& name)
{
    mapping::BuildOptions options;
    for (const auto& entry : table_.scenes)
        for (std::size_t i = 0; i < entry.specs.size(); ++i)
            if (entry.exposed[i]) options.sceneParamIds.push_back(entry.specs[i].id);
    options.sourceName = name;
    std::unique_ptr<mapping::MappingSet> set;
    try {
        set = mapping::MappingSet::build(doc, options);
    } catch (const std::exception& e) {
        return e.what();
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
    std::vector<osc::HostPort> targets;
    for (const auto& t : set.oscTargets())
        targets.push_back(osc::HostPort {t.host.empty() ? oscHost_ : t.host, t.port > 0 ? t.port : oscPort_});
    if (oscTargets_) (void) oscTargets_(targets);   // what was refused: shown by the rig's link status
}

void MappingSession::setDefaultOscTarget(const std::string& host, int port)
{
    oscHost_ = host.empty() ? std::string("127.0.0.1") : host;
    oscPort_ = port > 0 && port <= 65535 ? port : 9000;
    if (auto* set = liveSet()) configureOscTargets(*set);
}

std::string MappingSession::usePreset(const std::string& preset)
{
    mapping::MappingDocument doc;
    try {
        doc = mapping::loadMapping(preset);
    } catch (const std::exception& e) {
        return e.what();
    }
    return setDocument(withClassicChannel(std::move(doc), preset), preset);
}

std::string MappingSession::loadFile(const std::string& path)
{
    std::error_code ec;
    if (! std::filesystem::is_regular_file(path, ec)) return "no such file: " + path;
    if (std::filesystem::file_size(path, ec) > kMaxStateJsonBytes) return path + " is too large for a mapping file";
    mapping::MappingDocument doc;
    try {
        doc = mapping::parseMappingDocument(core::readWholeFile(path), path);
    } catch (const std::exception& e) {
        return e.what();
    }
    return setDocument(doc, std::filesystem::path(path).filename().string());
}

std::string MappingSession::saveFile(const std::string& path) const
{
    try {
        core::writeFileAtomically(path, mapping::toJson(doc_));
    } catch (const std::exception&) {
        return "cannot write " + path;
    }
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

SavedMapping MappingSession::toSaved() const
{
    SavedMapping saved;
    saved.present = true;
    saved.name = name_;
    saved.json = mapping::toJson(doc_);
    saved.forward = control_.mapper().forwardAzimuth();
    return saved;
}

std::string MappingSession::fromSaved(const SavedMapping& saved)
{
    if (! saved.present) {
        control_.mapper().setForwardAzimuth(0.0);
        return usePreset(kDefaultPreset);   // a state from before the mapping: its wiring
    }
    std::size_t cut = std::min<std::size_t>(saved.name.size(), 256);
    while (cut > 0 && cut < saved.name.size() && (static_cast<unsigned char>(saved.name[cut]) & 0xC0) == 0x80) --cut;   // whole UTF-8 characters
    const std::string name = saved.name.substr(0, cut);
    const double forward = saved.forward;
    control_.mapper().setForwardAzimuth(std::isfinite(forward) ? std::fmod(std::fmod(forward, 360.0) + 360.0, 360.0) : 0.0);
    const bool blank = saved.json.find_first_not_of(" \t\r\n") == std::string::npos;
    std::string why;
    if (blank && ! name.empty()) {
        why = usePreset(name);   // a hand-written setup may name a preset instead of holding one
    } else if (saved.json.size() > kMaxStateJsonBytes) {
        why = "the saved mapping is too large";
    } else {
        try {
            const auto doc = mapping::parseMappingDocument(saved.json, "saved mapping '" + name + "'");
            why = setDocument(doc, name.empty() ? std::string("saved") : name);
        } catch (const std::exception& e) {
            why = e.what();
        }
    }
    if (why.empty()) return {};
    const auto fallback = usePreset(kDefaultPreset);
    return "The saved mapping was refused (" + why + "); the classic preset runs instead." + (fallback.empty() ? std::string() : " " + fallback);
}

bool MappingSession::startRangeLearn(int index, std::string& why)
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

std::string MappingSession::finishRangeLearn(bool apply)
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
    if (! why.empty()) return why;
    char text[96];
    std::snprintf(text, sizeof text, "Range learned: %.1f to %.1f.", lo, hi);
    return text;
}

void MappingSession::timerTick()
{
    offerWaiting();
    // Destination learn: the channel messages that arrived since the last tick, in order (a CC
    // 0–31 followed by its +32 partner is a 14-bit pair); anything else is drained and dropped.
    std::uint8_t bytes[96];
    int size = 0;
    IncomingMidi m;
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
            notice_ = why.empty() ? "Destination learned: " + std::to_string(learned.channel) + "/" + std::to_string(learned.number) + "." : why;
        }
    }
    // Macros no mapping drives any longer stop being written (their parameters keep the value).
    for (int k = 0; k < mapping::kMacroCount; ++k)
        if (((macrosUsed_ >> k) & 1u) == 0) control_.mappingOutputs().releaseMacro(k);
}

} // namespace armadillo::live
