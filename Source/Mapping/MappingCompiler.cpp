// The mapping compiler: a MappingDocument → a MappingSet of fixed tables (builder thread; it
// allocates everything the evaluator, Mapper.cpp, will need, and refuses what parsing cannot see).
#include "Mapping/CompiledMapping.h"
#include "Core/Errors.h"
#include "Osc/Osc.h"
#include <algorithm>
#include <cmath>

namespace armadillo::mapping {

using namespace detail;

MappingSet::MappingSet() : impl_(std::make_unique<Impl>()) {}
MappingSet::~MappingSet() = default;

namespace {

void defaultOutputRange(DestinationKind k, double& lo, double& hi) noexcept
{
    switch (k) {
    case DestinationKind::Cc7:
    case DestinationKind::ChannelPressure:
    case DestinationKind::ProgramChange: lo = 0.0; hi = 127.0; return;
    case DestinationKind::Cc14:
    case DestinationKind::Nrpn:
    case DestinationKind::PitchBend: lo = 0.0; hi = 16383.0; return;
    default: lo = 0.0; hi = 1.0; return;
    }
}

std::string replaceAll(std::string s, const std::string& from, const std::string& to)
{
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
    return s;
}

} // namespace

std::unique_ptr<MappingSet> MappingSet::build(const MappingDocument& doc, const BuildOptions& options)
{
    const std::string where = options.sourceName.empty() ? std::string("mapping") : options.sourceName;
    if (doc.mappings.size() > static_cast<std::size_t>(kMaxMappings))
        throw core::InputError(where, 0, "", "more than " + std::to_string(kMaxMappings) + " mappings");
    std::unique_ptr<MappingSet> set(new MappingSet());
    Impl& s = *set->impl_;
    s.doc = doc;
    s.count = doc.mappings.size();
    s.maps = std::make_unique<Compiled[]>(s.count == 0 ? 1 : s.count);
    s.postures = PostureClassifier(doc.postures);
    s.hasPostures = s.postures.size() > 0;
    for (const MappingSpec& m : doc.mappings)
        if (m.source.kind == SourceKind::Gesture && m.source.name != "*" && m.source.name != "other") s.namedGestures.push_back(m.source.name);

    for (std::size_t i = 0; i < s.count; ++i) {
        const MappingSpec& m = doc.mappings[i];
        const std::string name = "mappings[" + std::to_string(i) + "]";
        Compiled& c = s.maps[i];
        c.spec = m;
        c.index = static_cast<int>(i);
        c.stage = m.to.kind == DestinationKind::Stage;
        const TransformSpec& t = m.transform;
        if (t.hasIn) {
            c.inLo = t.inLo;
            c.inHi = t.inHi;
        } else {
            defaultInputRange(m.source.kind, c.inLo, c.inHi);
        }
        if (t.hasOut) {
            c.outLo = t.outLo;
            c.outHi = t.outHi;
        } else {
            defaultOutputRange(m.to.kind, c.outLo, c.outHi);
        }
        c.hysteresis = t.hysteresis >= 0.0               ? t.hysteresis
                       : isAngleSource(m.source.kind)     ? kDefaultHysteresisDeg
                       : isSteppedPanelSource(m.source.kind) ? 0.0   // whole numbers, held by the panel's own hysteresis
                                                         : kDefaultHysteresisFraction * std::fabs(c.inHi - c.inLo);
        c.isPeriodic = periodic(m.source.kind);
        c.scale = t.scale.empty() ? 0 : scaleMask(t.scale);
        c.smooth.minCutoff = t.minCutoffHz;
        c.smooth.beta = t.beta;
        c.smooth.dCutoff = t.derivativeCutoffHz > 0.0 ? t.derivativeCutoffHz : 1.0;
        c.eventDriven = isEventSource(m.source.kind) || t.hasThreshold;
        c.muted.store(m.muted);
        if (m.source.arm < 0 || m.source.arm >= kMaxArms || (m.source.arm != 0 && !isArmSource(m.source.kind)))
            throw core::InputError(where, 0, "", name + ": arm " + std::to_string(m.source.arm) + " has no source \"" + sourceName(m.source) + "\"");
        if (m.source.kind == SourceKind::ArmsRaised && !c.spec.transform.hasThreshold) {   // a gate (documents built in code)
            c.spec.transform.hasThreshold = true;
            c.spec.transform.threshold = kDefaultArmsRaisedDeg;
            c.eventDriven = true;
        }
        if (m.source.kind == SourceKind::Posture) {
            c.posture = s.postures.indexOf(m.source.name);
            if (c.posture < 0) throw core::InputError(where, 0, "", name + ": no posture named \"" + m.source.name + "\"");
        }
        if (m.source.kind == SourceKind::Gesture) {
            c.gestureAny = m.source.name == "*";
            c.gestureOther = m.source.name == "other";
        }
        if (m.zones.size() > static_cast<std::size_t>(kMaxZones)) throw core::InputError(where, 0, "", name + ": too many zones");
        if (m.to.kind == DestinationKind::Macro) {
            if (m.to.number < 1 || m.to.number > kMacroCount) throw core::InputError(where, 0, "", name + ": macro must be 1…8");
            s.macros |= 1u << (m.to.number - 1);
        }
        if (m.to.kind == DestinationKind::SceneParam) {
            if (!options.sceneParamIds.empty() &&
                std::find(options.sceneParamIds.begin(), options.sceneParamIds.end(), m.to.paramId) == options.sceneParamIds.end()) {
                std::string list;
                for (const std::string& id : options.sceneParamIds) list += (list.empty() ? "" : ", ") + id;
                throw core::InputError(where, 0, "", name + ": the scene has no parameter \"" + m.to.paramId + "\" (it has: " + list + ")");
            }
            const auto at = std::find(s.params.begin(), s.params.end(), m.to.paramId);
            c.param = static_cast<int>(at - s.params.begin());
            if (at == s.params.end()) s.params.push_back(m.to.paramId);
        }
        if (m.to.kind == DestinationKind::Mqtt) {
            c.payload = splitMqttPayload(m.to.payload);
            std::size_t longest = 0;   // each value at most 24 characters ("-1.23457e+308", "OFF")
            for (const MqttPayloadPart& part : c.payload) longest += part.text.size() + (part.field == MqttPayloadPart::Field::None ? 0 : 24);
            if (longest > MqttMessage::kMaxPayload)
                throw core::InputError(where, 0, "", name + ": the MQTT payload can grow past " + std::to_string(MqttMessage::kMaxPayload) + " bytes");
            const std::size_t n = m.zones.empty() ? 1 : m.zones.size();
            for (std::size_t z = 0; z < n; ++z) {
                std::string topic = replaceAll(m.to.address, "{arm}", std::to_string(m.source.arm));
                topic = replaceAll(topic, "{zone}", m.zones.empty() ? std::string("0") : std::to_string(m.zones[z].value));
                if (topic.size() >= MqttMessage::kMaxTopic)
                    throw core::InputError(where, 0, "", name + ": MQTT topic \"" + topic + "\" longer than " + std::to_string(MqttMessage::kMaxTopic - 1) + " bytes");
                c.addresses.push_back(topic);
            }
        }
        if (m.to.kind == DestinationKind::Osc) {
            if (!m.to.host.empty() || m.to.port > 0) {
                std::size_t k = 1;
                for (; k < s.targets.size(); ++k)
                    if (s.targets[k].host == m.to.host && s.targets[k].port == m.to.port) break;
                if (k == s.targets.size()) s.targets.push_back({m.to.host, m.to.port});
                c.oscTarget = static_cast<int>(k);
            }
            const std::size_t n = m.zones.empty() ? 1 : m.zones.size();
            for (std::size_t z = 0; z < n; ++z) {
                std::string a = replaceAll(m.to.address, "{arm}", std::to_string(m.source.arm));
                a = replaceAll(a, "{zone}", m.zones.empty() ? std::string("0") : std::to_string(m.zones[z].value));
                // The longest message this address can make must fit one packet.
                osc::OscArg args[kMaxOscArgs];
                const std::size_t argc = m.to.args.empty() ? 1 : std::min<std::size_t>(m.to.args.size(), kMaxOscArgs);
                for (std::size_t k = 0; k < argc; ++k) {
                    const OscArgSpec* spec = m.to.args.empty() ? nullptr : &m.to.args[k];
                    if (spec && spec->type == 's') args[k] = osc::OscArg::string(spec->text);
                    else if (spec && spec->type == 'd') args[k] = osc::OscArg::float64(0.0);
                    else if (spec && spec->type == 'i') args[k] = osc::OscArg::int32(0);
                    else args[k] = osc::OscArg::float32(0.0f);
                }
                std::array<std::uint8_t, kOscPacketCapacity> probe {};
                if (osc::encodeOscMessage(a, args, argc, probe.data(), probe.size()) == 0)
                    throw core::InputError(where, 0, "", name + ": the OSC message to \"" + a + "\" does not encode (a bad address, or longer than " +
                                                       std::to_string(kOscPacketCapacity) + " bytes)");
                c.addresses.push_back(a);
            }
        }
    }
    return set;
}

const MappingDocument& MappingSet::document() const noexcept { return impl_->doc; }
std::size_t MappingSet::size() const noexcept { return impl_->count; }
const std::vector<OscTarget>& MappingSet::oscTargets() const noexcept { return impl_->targets; }
const std::vector<std::string>& MappingSet::sceneParamIds() const noexcept { return impl_->params; }
std::uint32_t MappingSet::macrosUsed() const noexcept { return impl_->macros; }
void MappingSet::setMuted(std::size_t i, bool muted) noexcept
{
    if (i < impl_->count) impl_->maps[i].muted.store(muted, std::memory_order_relaxed);
}
bool MappingSet::muted(std::size_t i) const noexcept { return i < impl_->count && impl_->maps[i].muted.load(std::memory_order_relaxed); }
float MappingSet::meter(std::size_t i) const noexcept
{
    return i < impl_->count ? impl_->maps[i].meter.load(std::memory_order_relaxed) : std::numeric_limits<float>::quiet_NaN();
}
bool MappingSet::active(std::size_t i) const noexcept { return i < impl_->count && impl_->maps[i].active.load(std::memory_order_relaxed); }

} // namespace armadillo::mapping
