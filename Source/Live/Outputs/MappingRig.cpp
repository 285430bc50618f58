#include "Live/Outputs/MappingRig.h"
#include "Core/Errors.h"
#include <algorithm>
#include <array>
#include <stdexcept>

namespace armadillo::live {

MappingRig::MappingRig(const mapping::MappingDocument& doc, engine::Engine& engine, const MappingRigOptions& options)
    : out_(std::make_unique<mapping::MappingOutput>())
{
    specs_ = engine.scene().parameters();
    mapping::BuildOptions build;
    build.sourceName = options.sourceName;
    for (const core::ParamSpec& p : specs_) build.sceneParamIds.push_back(p.id);
    if (build.sceneParamIds.empty()) build.sceneParamIds.push_back("(none)");   // a scene without parameters refuses every "param"
    std::unique_ptr<mapping::MappingSet> set = mapping::MappingSet::build(doc, build);

    osc::HostPort fallback {"127.0.0.1", 9000};
    if (!options.oscDefault.empty()) {
        try {
            fallback = osc::parseHostPort(options.oscDefault);
        } catch (const std::invalid_argument& e) {
            throw core::InputError("", 0, "--osc-out", e.what());
        }
    }
    for (const mapping::OscTarget& t : set->oscTargets()) {
        if (!options.sendOsc) {
            senders_.push_back(nullptr);
            continue;
        }
        osc::HostPort hp {t.host.empty() ? fallback.host : t.host, t.port > 0 ? t.port : fallback.port};
        senders_.push_back(std::make_unique<osc::OscSender>(hp));   // IoError for a host that does not resolve
    }
    mapper_.replace(std::move(set));
    mapper_.setForwardAzimuth(options.forwardDeg);
}

MappingRig::~MappingRig() = default;

std::uint64_t MappingRig::oscSent() const noexcept
{
    std::uint64_t n = 0;
    for (const auto& s : senders_)
        if (s) n += s->sent();
    return n;
}

std::uint64_t MappingRig::dropped() const noexcept
{
    return tally_.overflow.load(std::memory_order_relaxed) + tally_.midiDropped.load(std::memory_order_relaxed) +
           tally_.oscDropped.load(std::memory_order_relaxed) + tally_.mqttDropped.load(std::memory_order_relaxed);
}

bool MappingRig::midi(const mapping::MidiEvent& e) noexcept
{
    if (sink_) sink_(sinkContext_, e);
    return true;
}

bool MappingRig::osc(const mapping::OscPacket& p) noexcept
{
    const auto target = static_cast<std::size_t>(p.target);
    if (target < senders_.size() && senders_[target]) senders_[target]->sendPacket(p.bytes.data(), p.size);
    return true;   // counted whether sent or not (render without --osc-out counts them only)
}

bool MappingRig::mqtt(const mapping::MqttMessage& m) noexcept
{
    return ! mqttSink_ || mqttSink_(mqttContext_, m);   // false: the client's queue was full
}

void MappingRig::stage(const mapping::StageEvent& e) noexcept
{
    if (stageSink_) stageSink_(stageContext_, e);
}

void MappingRig::deliver(engine::Engine* engine) noexcept
{
    SceneParamTarget params;
    if (engine != nullptr && mapper_.active() != nullptr) params = {&engine->scene(), &mapper_.active()->sceneParamIds(), &specs_};
    deliverMapping(*out_, *this, params, tally_);
}

void MappingRig::step(const mapping::MappingInput& in, engine::Engine& engine) noexcept
{
    mapper_.process(in, *out_);
    deliver(&engine);
}

void MappingRig::finish(double t) noexcept
{
    mapper_.flush(t + 3600.0, *out_);   // gesture notes end at their own due time
    mapper_.allNotesOff(t, *out_);      // held notes (zones, postures, thresholds) at the end
    deliver(nullptr);
}

void MappingRig::panic(double t) noexcept
{
    const std::uint64_t before = midiEvents();
    mapper_.panic(t, *out_);
    deliver(nullptr);
    panicMidi_ += midiEvents() - before;
}

} // namespace armadillo::live
