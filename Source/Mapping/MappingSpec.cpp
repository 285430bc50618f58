#include "Mapping/MappingSpec.h"
#include "Core/Errors.h"
#include "Core/Resources.h"
#include "Core/Json.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <utility>

namespace armadillo::mapping {

namespace {

struct SourceNameEntry {
    SourceKind kind;
    const char* name;
};
constexpr SourceNameEntry kSourceNames[] {
    {SourceKind::Elevation, "elevation"},  {SourceKind::Azimuth, "azimuth"},   {SourceKind::Roll, "roll"},
    {SourceKind::Yaw, "yaw"},              {SourceKind::Pitch, "pitch"},       {SourceKind::QuatW, "qw"},
    {SourceKind::QuatX, "qx"},             {SourceKind::QuatY, "qy"},          {SourceKind::QuatZ, "qz"},
    {SourceKind::AngularSpeed, "speed"},   {SourceKind::FluxFace, "fluxFace"}, {SourceKind::FluxEdge, "fluxEdge"},
    {SourceKind::RollTrigger, "rollTrigger"}, {SourceKind::Punch, "punch"},   {SourceKind::ScenePitch, "scene.pitch"},
    {SourceKind::SceneFret, "scene.fret"}, {SourceKind::SceneStrike, "scene.strike"}, {SourceKind::GestureValue, "value"},
    {SourceKind::YprQuatW, "ypr.qw"},      {SourceKind::YprQuatX, "ypr.qx"},   {SourceKind::YprQuatY, "ypr.qy"},
    {SourceKind::YprQuatZ, "ypr.qz"},      {SourceKind::ArmsAngle, "arms.angle"}, {SourceKind::ArmsRoll, "arms.roll"},
    {SourceKind::ArmsRaised, "arms.raised"},
    {SourceKind::PanelKnob, "panel.knob"}, {SourceKind::PanelLevel, "panel.level"}, {SourceKind::PanelSelected, "panel.selected"},
};

std::string allSourceNames()
{
    std::string s;
    for (const auto& e : kSourceNames) {
        if (e.kind == SourceKind::GestureValue) continue;
        s += e.name;
        s += ", ";
    }
    return s + "left.NAME (the left arm's NAME for every arm source), gesture:NAME, posture:NAME";
}

// ---- reading ---------------------------------------------------------------------------------

using armadillo::core::JsonValue;

class Reader {
public:
    explicit Reader(std::string source) : source_(std::move(source)) {}

    [[noreturn]] void fail(const core::JsonValue& at, const std::string& path, const std::string& message) const
    {
        throw core::InputError(source_, at.line, "", "column " + std::to_string(at.column) + ": " + path + ": " + message);
    }

    void expectKind(const core::JsonValue& v, core::JsonValue::Kind k, const std::string& path) const
    {
        if (v.kind != k)
            fail(v, path, std::string("expected ") + core::JsonValue::kindName(k) + ", found " + core::JsonValue::kindName(v.kind));
    }

    double number(const core::JsonValue& v, const std::string& path) const
    {
        expectKind(v, core::JsonValue::Kind::Number, path);
        if (!std::isfinite(v.number)) fail(v, path, "not a finite number");
        return v.number;
    }

    double numberIn(const core::JsonValue& v, const std::string& path, double lo, double hi) const
    {
        const double x = number(v, path);
        if (x < lo || x > hi) fail(v, path, fmt(x) + " is outside " + fmt(lo) + "…" + fmt(hi));
        return x;
    }

    int integerIn(const core::JsonValue& v, const std::string& path, int lo, int hi) const
    {
        const double x = numberIn(v, path, lo, hi);
        if (x != std::floor(x)) fail(v, path, fmt(x) + " is not a whole number");
        return static_cast<int>(x);
    }

    bool boolean(const core::JsonValue& v, const std::string& path) const
    {
        expectKind(v, core::JsonValue::Kind::Bool, path);
        return v.boolean;
    }

    const std::string& string(const core::JsonValue& v, const std::string& path) const
    {
        expectKind(v, core::JsonValue::Kind::String, path);
        return v.string;
    }

    void pair(const core::JsonValue& v, const std::string& path, double& a, double& b) const
    {
        expectKind(v, core::JsonValue::Kind::Array, path);
        if (v.array.size() != 2) fail(v, path, "expected [low, high] (2 numbers), found " + std::to_string(v.array.size()) + " elements");
        a = number(v.array[0], path + "[0]");
        b = number(v.array[1], path + "[1]");
        if (a == b) fail(v, path, "the two ends are equal (an empty range)");
    }

    /// Refuses keys the format does not know (a misspelt "chanel" must not pass silently).
    void onlyKeys(const core::JsonValue& obj, const std::string& path, std::initializer_list<const char*> allowed) const
    {
        for (const auto& [key, value] : obj.object) {
            bool ok = false;
            for (const char* a : allowed) ok = ok || key == a;
            if (!ok) {
                std::string list;
                for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
                fail(value, path + "." + key, "unknown key \"" + key + "\" (known here: " + list + ")");
            }
        }
    }

    SourceSpec source(const core::JsonValue& v, const std::string& path) const
    {
        SourceSpec s;
        if (!parseSourceName(string(v, path), s)) fail(v, path, "unknown source \"" + v.string + "\" (sources: " + allSourceNames() + ")");
        return s;
    }

    AuxSpec aux(const core::JsonValue& v, const std::string& path) const
    {
        expectKind(v, core::JsonValue::Kind::Object, path);
        onlyKeys(v, path, {"source", "in", "abs"});
        AuxSpec a;
        a.used = true;
        const core::JsonValue* src = v.find("source");
        if (!src) fail(v, path, "missing \"source\"");
        a.source = source(*src, path + ".source");
        if (isEventSource(a.source.kind)) fail(*src, path + ".source", "an event source cannot drive a value here");
        defaultInputRange(a.source.kind, a.lo, a.hi);
        if (const core::JsonValue* in = v.find("in")) pair(*in, path + ".in", a.lo, a.hi);
        if (const core::JsonValue* ab = v.find("abs")) a.abs = boolean(*ab, path + ".abs");
        return a;
    }

    std::vector<ZoneSpec> zones(const core::JsonValue& v, const std::string& path) const
    {
        expectKind(v, core::JsonValue::Kind::Array, path);
        if (v.array.empty()) fail(v, path, "no zones");
        if (v.array.size() > static_cast<std::size_t>(kMaxZones)) fail(v, path, "more than " + std::to_string(kMaxZones) + " zones");
        std::vector<ZoneSpec> out;
        for (std::size_t i = 0; i < v.array.size(); ++i) {
            const core::JsonValue& z = v.array[i];
            const std::string p = path + "[" + std::to_string(i) + "]";
            ZoneSpec zone;
            if (z.kind == core::JsonValue::Kind::Array) {
                if (z.array.size() != 3) fail(z, p, "a zone is [from, to, note] (3 numbers), found " + std::to_string(z.array.size()) + " elements");
                zone.from = number(z.array[0], p + "[0]");
                zone.to = number(z.array[1], p + "[1]");
                zone.value = integerIn(z.array[2], p + "[2]", 0, 16383);
            } else if (z.kind == core::JsonValue::Kind::Object) {
                onlyKeys(z, p, {"from", "to", "elevation", "note", "value"});
                const core::JsonValue* f = z.find("from");
                const core::JsonValue* t = z.find("to");
                if (!f || !t) fail(z, p, "a zone needs \"from\" and \"to\"");
                zone.from = number(*f, p + ".from");
                zone.to = number(*t, p + ".to");
                const core::JsonValue* n = z.find("note");
                if (!n) n = z.find("value");
                if (n) zone.value = integerIn(*n, p + (z.find("note") ? ".note" : ".value"), 0, 16383);
                if (const core::JsonValue* el = z.find("elevation")) {
                    zone.hasElevation = true;
                    pair(*el, p + ".elevation", zone.elFrom, zone.elTo);
                    if (zone.elFrom > zone.elTo) std::swap(zone.elFrom, zone.elTo);
                }
            } else {
                fail(z, p, std::string("a zone is [from, to, note] or an object, found ") + core::JsonValue::kindName(z.kind));
            }
            if (zone.from == zone.to) fail(z, p, "an empty zone (from = to)");
            out.push_back(zone);
        }
        return out;
    }

    OscArgSpec oscArg(const core::JsonValue& v, const std::string& path) const
    {
        OscArgSpec a;
        if (v.kind == core::JsonValue::Kind::Number) {
            a.kind = OscArgSpec::Kind::Number;
            a.number = number(v, path);
            a.type = 'f';
            return a;
        }
        const std::string& s = string(v, path);
        std::string_view name = s;
        if (name.size() > 1 && name[0] == '-' && name[1] == '$') {
            a.negate = true;
            name.remove_prefix(1);
        }
        if (name.empty() || name[0] != '$') {
            a.kind = OscArgSpec::Kind::String;
            a.text = s;
            a.type = 's';
            return a;
        }
        name.remove_prefix(1);
        if (name == "value") a.kind = OscArgSpec::Kind::Value;
        else if (name == "zone") a.kind = OscArgSpec::Kind::Zone;
        else if (name == "on") a.kind = OscArgSpec::Kind::On;
        else {
            a.kind = OscArgSpec::Kind::Source;
            if (!parseSourceName(name, a.source) || isEventSource(a.source.kind) || a.source.kind == SourceKind::GestureValue)
                fail(v, path, "unknown argument \"" + s + "\" ($value, $zone, $on or $SOURCE with a continuous source: " + allSourceNames() + ")");
        }
        a.type = 'f';
        return a;
    }

    void channel(const core::JsonValue& v, const std::string& path, int& out) const
    {
        if (const core::JsonValue* c = v.find("channel")) out = integerIn(*c, path + ".channel", 1, 16);
    }
    void velocity(const core::JsonValue& v, const std::string& path, DestinationSpec& d) const
    {
        if (const core::JsonValue* vel = v.find("velocity")) {
            if (vel->kind == core::JsonValue::Kind::Number) d.velocity = integerIn(*vel, path + ".velocity", 1, 127);
            else d.velocitySource = aux(*vel, path + ".velocity");
        }
    }
    void zonesHere(const core::JsonValue& v, const std::string& path, std::vector<ZoneSpec>& zonesOut) const
    {
        if (const core::JsonValue* z = v.find("zones")) zonesOut = zones(*z, path + ".zones");
    }

    void midiDestination(const core::JsonValue& v, const core::JsonValue* midi, const std::string& path, DestinationSpec& d, std::vector<ZoneSpec>& zonesOut) const
    {
        const std::string& m = string(*midi, path + ".midi");
        if (m == "cc" || m == "cc7" || m == "cc14") {
            onlyKeys(v, path, {"midi", "channel", "cc", "lsbFirst", "zones"});
            d.kind = m == "cc14" ? DestinationKind::Cc14 : DestinationKind::Cc7;
            channel(v, path, d.channel);
            const core::JsonValue* cc = v.find("cc");
            if (!cc) fail(v, path, "missing \"cc\"");
            d.number = integerIn(*cc, path + ".cc", 0, d.kind == DestinationKind::Cc14 ? 31 : 127);
            if (const core::JsonValue* l = v.find("lsbFirst")) {
                if (d.kind != DestinationKind::Cc14) fail(*l, path + ".lsbFirst", "only for \"cc14\"");
                d.lsbFirst = boolean(*l, path + ".lsbFirst");
            }
            zonesHere(v, path, zonesOut);
        } else if (m == "nrpn") {
            onlyKeys(v, path, {"midi", "channel", "number", "zones"});
            d.kind = DestinationKind::Nrpn;
            channel(v, path, d.channel);
            const core::JsonValue* n = v.find("number");
            if (!n) fail(v, path, "missing \"number\" (the NRPN parameter 0…16383)");
            d.number = integerIn(*n, path + ".number", 0, 16383);
            zonesHere(v, path, zonesOut);
        } else if (m == "pitchbend") {
            onlyKeys(v, path, {"midi", "channel", "zones"});
            d.kind = DestinationKind::PitchBend;
            channel(v, path, d.channel);
            zonesHere(v, path, zonesOut);
        } else if (m == "pressure") {
            onlyKeys(v, path, {"midi", "channel", "zones"});
            d.kind = DestinationKind::ChannelPressure;
            channel(v, path, d.channel);
            zonesHere(v, path, zonesOut);
        } else if (m == "notes" || m == "note") {
            onlyKeys(v, path, {"midi", "channel", "velocity", "zones", "note", "lengthMs"});
            d.kind = DestinationKind::Notes;
            channel(v, path, d.channel);
            velocity(v, path, d);
            zonesHere(v, path, zonesOut);
            d.number = 60;
            if (const core::JsonValue* n = v.find("note")) d.number = integerIn(*n, path + ".note", 0, 127);
            if (const core::JsonValue* l = v.find("lengthMs")) d.lengthMs = numberIn(*l, path + ".lengthMs", 1.0, 60000.0);
            for (const ZoneSpec& z : zonesOut)
                if (z.value > 127) fail(v, path + ".zones", "note " + std::to_string(z.value) + " is outside 0…127");
        } else if (m == "mpe") {
            onlyKeys(v, path, {"midi", "channel", "velocity", "zones", "members", "bend", "bendRange", "pressure", "timbre"});
            d.kind = DestinationKind::Mpe;
            channel(v, path, d.channel);
            if (d.channel != 1 && d.channel != 16) fail(*v.find("channel"), path + ".channel", "the MPE master channel is 1 (lower zone) or 16 (upper zone)");
            velocity(v, path, d);
            zonesHere(v, path, zonesOut);
            if (const core::JsonValue* n = v.find("members")) d.mpeMembers = integerIn(*n, path + ".members", 1, 15);
            if (const core::JsonValue* b = v.find("bend")) d.mpeBend = aux(*b, path + ".bend");
            if (const core::JsonValue* b = v.find("bendRange")) d.mpeBendRange = numberIn(*b, path + ".bendRange", 1.0, 96.0);
            if (const core::JsonValue* p = v.find("pressure")) d.mpePressure = aux(*p, path + ".pressure");
            if (const core::JsonValue* t = v.find("timbre")) d.mpeTimbre = aux(*t, path + ".timbre");
            for (const ZoneSpec& z : zonesOut)
                if (z.value > 127) fail(v, path + ".zones", "note " + std::to_string(z.value) + " is outside 0…127");
        } else if (m == "program") {
            onlyKeys(v, path, {"midi", "channel", "program", "zones"});
            d.kind = DestinationKind::ProgramChange;
            channel(v, path, d.channel);
            if (const core::JsonValue* p = v.find("program")) d.number = integerIn(*p, path + ".program", 0, 127);
            zonesHere(v, path, zonesOut);
            for (const ZoneSpec& z : zonesOut)
                if (z.value > 127) fail(v, path + ".zones", "program " + std::to_string(z.value) + " is outside 0…127");
        } else {
            fail(*midi, path + ".midi", "unknown MIDI destination \"" + m + "\" (cc, cc14, nrpn, pitchbend, pressure, notes, note, mpe, program)");
        }
    }

    void oscDestination(const core::JsonValue& v, const core::JsonValue* osc, const std::string& path, DestinationSpec& d, std::vector<ZoneSpec>& zonesOut) const
    {
        onlyKeys(v, path, {"osc", "args", "types", "host", "port", "zones"});
        d.kind = DestinationKind::Osc;
        d.address = string(*osc, path + ".osc");
        if (d.address.empty() || d.address[0] != '/') fail(*osc, path + ".osc", "an OSC address starts with '/'");
        if (d.address.size() > 128) fail(*osc, path + ".osc", "address longer than 128 characters");
        if (const core::JsonValue* args = v.find("args")) {
            expectKind(*args, core::JsonValue::Kind::Array, path + ".args");
            if (args->array.size() > static_cast<std::size_t>(kMaxOscArgs))
                fail(*args, path + ".args", "more than " + std::to_string(kMaxOscArgs) + " arguments");
            for (std::size_t i = 0; i < args->array.size(); ++i)
                d.args.push_back(oscArg(args->array[i], path + ".args[" + std::to_string(i) + "]"));
        }
        if (const core::JsonValue* t = v.find("types")) {
            const std::string& types = string(*t, path + ".types");
            const std::size_t n = d.args.empty() ? 1 : d.args.size();
            if (types.size() != n) fail(*t, path + ".types", "\"" + types + "\" has " + std::to_string(types.size()) + " type tags for " + std::to_string(n) + " arguments");
            if (d.args.empty()) d.args.push_back(OscArgSpec {});
            for (std::size_t i = 0; i < n; ++i) {
                const char c = types[i];
                if (c != 'f' && c != 'i' && c != 'd' && c != 's') fail(*t, path + ".types", std::string("type tag '") + c + "' is not one of f i d s");
                if ((c == 's') != (d.args[i].kind == OscArgSpec::Kind::String))
                    fail(*t, path + ".types", "argument " + std::to_string(i) + ": 's' goes with a string constant and only with one");
                d.args[i].type = c;
            }
        }
        if (const core::JsonValue* h = v.find("host")) {
            d.host = string(*h, path + ".host");
            if (d.host.empty()) fail(*h, path + ".host", "empty host");
        }
        if (const core::JsonValue* p = v.find("port")) d.port = integerIn(*p, path + ".port", 1, 65535);
        zonesHere(v, path, zonesOut);
    }

    void mqttDestination(const core::JsonValue& v, const core::JsonValue* mqtt, const std::string& path, DestinationSpec& d, std::vector<ZoneSpec>& zonesOut) const
    {
        onlyKeys(v, path, {"mqtt", "zones"});
        expectKind(*mqtt, core::JsonValue::Kind::Object, path + ".mqtt");
        onlyKeys(*mqtt, path + ".mqtt", {"topic", "payload", "qos", "retain", "rate"});
        d.kind = DestinationKind::Mqtt;
        const core::JsonValue* topic = mqtt->find("topic");
        if (!topic) fail(*mqtt, path + ".mqtt", "an MQTT destination needs \"topic\"");
        d.address = string(*topic, path + ".mqtt.topic");
        if (d.address.empty()) fail(*topic, path + ".mqtt.topic", "empty topic");
        if (d.address.find_first_of("+#") != std::string::npos)
            fail(*topic, path + ".mqtt.topic", "a topic to publish to has no wildcards ('+', '#')");
        if (d.address.size() > 120) fail(*topic, path + ".mqtt.topic", "topic longer than 120 characters");
        if (const core::JsonValue* p = mqtt->find("payload")) {
            d.payload = string(*p, path + ".mqtt.payload");
            if (const std::string why = mqttPayloadProblem(d.payload); !why.empty()) fail(*p, path + ".mqtt.payload", why);
        }
        if (const core::JsonValue* q = mqtt->find("qos")) d.qos = integerIn(*q, path + ".mqtt.qos", 0, 2);
        if (const core::JsonValue* r = mqtt->find("retain")) {
            expectKind(*r, core::JsonValue::Kind::Bool, path + ".mqtt.retain");
            d.retain = r->boolean;
        }
        if (const core::JsonValue* r = mqtt->find("rate")) {
            expectKind(*r, core::JsonValue::Kind::Number, path + ".mqtt.rate");
            if (!(r->number >= 0.0 && r->number <= 1000.0)) fail(*r, path + ".mqtt.rate", "messages per second from 0 (no limit) to 1000");
            d.rate = r->number;
        }
        zonesHere(v, path, zonesOut);
    }

    void stageDestination(const core::JsonValue& v, const core::JsonValue* stage, const std::string& path, DestinationSpec& d, std::vector<ZoneSpec>& zonesOut) const
    {
        onlyKeys(v, path, {"stage", "cue", "zones"});
        d.kind = DestinationKind::Stage;
        const std::string& a = string(*stage, path + ".stage");
        bool known = false;
        for (core::StageCommand::Kind k : {core::StageCommand::Kind::CueNext, core::StageCommand::Kind::CuePrev, core::StageCommand::Kind::CueGoto, core::StageCommand::Kind::Panic, core::StageCommand::Kind::Resume})
            if (a == stageActionName(k)) {
                d.stage = k;
                known = true;
            }
        if (!known) fail(*stage, path + ".stage", "unknown stage command \"" + a + "\" (next, prev, cue, panic, resume)");
        const core::JsonValue* cue = v.find("cue");
        if (d.stage == core::StageCommand::Kind::CueGoto) {
            if (!cue) fail(v, path, "\"stage\": \"cue\" needs \"cue\": the cue's number (0-based)");
            d.number = integerIn(*cue, path + ".cue", 0, 9999);
        } else if (cue) {
            fail(*cue, path + ".cue", "\"cue\" goes only with \"stage\": \"cue\"");
        }
        zonesHere(v, path, zonesOut);
    }

    DestinationSpec destination(const core::JsonValue& v, const std::string& path, std::vector<ZoneSpec>& zonesOut) const
    {
        expectKind(v, core::JsonValue::Kind::Object, path);
        DestinationSpec d;
        const core::JsonValue* midi = v.find("midi");
        const core::JsonValue* osc = v.find("osc");
        const core::JsonValue* macro = v.find("macro");
        const core::JsonValue* param = v.find("param");
        const core::JsonValue* action = v.find("action");
        const core::JsonValue* stage = v.find("stage");
        const core::JsonValue* mqtt = v.find("mqtt");
        const int kinds = (midi != nullptr) + (osc != nullptr) + (macro != nullptr) + (param != nullptr) + (action != nullptr) + (stage != nullptr) +
                          (mqtt != nullptr);
        if (kinds != 1)
            fail(v, path, "a destination names exactly one of \"midi\", \"osc\", \"mqtt\", \"macro\", \"param\", \"action\", \"stage\"");
        if (midi) {
            midiDestination(v, midi, path, d, zonesOut);
        } else if (osc) {
            oscDestination(v, osc, path, d, zonesOut);
        } else if (mqtt) {
            mqttDestination(v, mqtt, path, d, zonesOut);
        } else if (macro) {
            onlyKeys(v, path, {"macro", "zones"});
            d.kind = DestinationKind::Macro;
            d.number = integerIn(*macro, path + ".macro", 1, kMacroCount);
            zonesHere(v, path, zonesOut);
        } else if (param) {
            onlyKeys(v, path, {"param", "zones"});
            d.kind = DestinationKind::SceneParam;
            d.paramId = string(*param, path + ".param");
            if (d.paramId.empty()) fail(*param, path + ".param", "empty parameter id");
            zonesHere(v, path, zonesOut);
        } else if (stage) {
            stageDestination(v, stage, path, d, zonesOut);
        } else {
            onlyKeys(v, path, {"action"});
            const std::string& a = string(*action, path + ".action");
            if (a != "forward") fail(*action, path + ".action", "unknown action \"" + a + "\" (forward)");
            d.kind = DestinationKind::SetForward;
        }
        return d;
    }

    TransformSpec transform(const core::JsonValue& m, const std::string& path, const SourceSpec& src) const
    {
        TransformSpec t;
        if (const core::JsonValue* in = m.find("in")) {
            t.hasIn = true;
            pair(*in, path + ".in", t.inLo, t.inHi);
        }
        if (const core::JsonValue* out = m.find("out")) {
            t.hasOut = true;
            pair(*out, path + ".out", t.outLo, t.outHi);
        }
        if (const core::JsonValue* x = m.find("invert")) t.invert = boolean(*x, path + ".invert");
        if (const core::JsonValue* x = m.find("abs")) t.abs = boolean(*x, path + ".abs");
        if (const core::JsonValue* x = m.find("forward")) {
            t.forward = boolean(*x, path + ".forward");
            if (t.forward && src.kind != SourceKind::Azimuth) fail(*x, path + ".forward", "only azimuth is measured from forward (yaw always is)");
        }
        if (const core::JsonValue* c = m.find("curve")) {
            const std::string& name = string(*c, path + ".curve");
            if (name == "linear") t.curve = Curve::Linear;
            else if (name == "exp") t.curve = Curve::Exp;
            else if (name == "log") t.curve = Curve::Log;
            else if (name == "s") t.curve = Curve::SCurve;
            else if (name == "table") t.curve = Curve::Table;
            else fail(*c, path + ".curve", "unknown curve \"" + name + "\" (linear, exp, log, s, table)");
        }
        if (const core::JsonValue* s = m.find("shape")) t.shape = numberIn(*s, path + ".shape", -20.0, 20.0);
        if (const core::JsonValue* tab = m.find("table")) {
            if (t.curve != Curve::Table) fail(*tab, path + ".table", "a table needs \"curve\": \"table\"");
            expectKind(*tab, core::JsonValue::Kind::Array, path + ".table");
            if (tab->array.size() < 2 || tab->array.size() > static_cast<std::size_t>(kMaxTablePoints))
                fail(*tab, path + ".table", "a table has 2…" + std::to_string(kMaxTablePoints) + " points [x, y]");
            for (std::size_t i = 0; i < tab->array.size(); ++i) {
                const core::JsonValue& p = tab->array[i];
                const std::string pp = path + ".table[" + std::to_string(i) + "]";
                expectKind(p, core::JsonValue::Kind::Array, pp);
                if (p.array.size() != 2) fail(p, pp, "a point is [x, y]");
                const double x = numberIn(p.array[0], pp + "[0]", 0.0, 1.0);
                const double y = numberIn(p.array[1], pp + "[1]", 0.0, 1.0);
                if (!t.table.empty() && x <= t.table.back()[0]) fail(p, pp, "x must increase from point to point");
                t.table.push_back({x, y});
            }
        } else if (t.curve == Curve::Table) {
            fail(m, path, "\"curve\": \"table\" needs \"table\": [[x, y], …]");
        }
        if (const core::JsonValue* s = m.find("smoothMs")) {
            const double ms = numberIn(*s, path + ".smoothMs", 0.0, 10000.0);
            t.minCutoffHz = ms > 0.0 ? 1000.0 / (2.0 * 3.14159265358979323846 * ms) : 0.0;
        }
        if (const core::JsonValue* s = m.find("smooth")) {
            if (m.find("smoothMs")) fail(*s, path + ".smooth", "give \"smoothMs\" or \"smooth\", not both");
            expectKind(*s, core::JsonValue::Kind::Object, path + ".smooth");
            onlyKeys(*s, path + ".smooth", {"minCutoffHz", "beta", "derivativeCutoffHz"});
            if (const core::JsonValue* x = s->find("minCutoffHz")) t.minCutoffHz = numberIn(*x, path + ".smooth.minCutoffHz", 0.001, 1000.0);
            else fail(*s, path + ".smooth", "missing \"minCutoffHz\"");
            if (const core::JsonValue* x = s->find("beta")) t.beta = numberIn(*x, path + ".smooth.beta", 0.0, 1000.0);
            if (const core::JsonValue* x = s->find("derivativeCutoffHz")) t.derivativeCutoffHz = numberIn(*x, path + ".smooth.derivativeCutoffHz", 0.001, 1000.0);
        }
        if (const core::JsonValue* x = m.find("deadZone")) t.deadZone = numberIn(*x, path + ".deadZone", 0.0, 1e6);
        if (const core::JsonValue* x = m.find("hysteresis")) t.hysteresis = numberIn(*x, path + ".hysteresis", 0.0, 1e6);
        if (const core::JsonValue* x = m.find("threshold")) {
            t.hasThreshold = true;
            t.threshold = number(*x, path + ".threshold");
        }
        if (const core::JsonValue* x = m.find("steps")) t.steps = integerIn(*x, path + ".steps", 2, 16384);
        if (const core::JsonValue* x = m.find("scale")) {
            t.scale = string(*x, path + ".scale");
            if (scaleIntervals(t.scale) == 0) fail(*x, path + ".scale", "unknown scale \"" + t.scale + "\" (" + kScaleList + ")");
        }
        if (const core::JsonValue* x = m.find("root")) t.scaleRoot = integerIn(*x, path + ".root", 0, 11);
        return t;
    }

    PostureSpec posture(const core::JsonValue& v, const std::string& path) const
    {
        expectKind(v, core::JsonValue::Kind::Object, path);
        onlyKeys(v, path, {"name", "examples", "radius", "hysteresis", "maxSpeed"});
        PostureSpec p;
        const core::JsonValue* name = v.find("name");
        if (!name) fail(v, path, "missing \"name\"");
        p.name = string(*name, path + ".name");
        if (p.name.empty()) fail(*name, path + ".name", "empty name");
        const core::JsonValue* ex = v.find("examples");
        if (!ex) fail(v, path, "missing \"examples\" (quaternions [w, x, y, z])");
        expectKind(*ex, core::JsonValue::Kind::Array, path + ".examples");
        if (ex->array.empty() || ex->array.size() > 64) fail(*ex, path + ".examples", "a posture has 1…64 examples");
        for (std::size_t i = 0; i < ex->array.size(); ++i) {
            const core::JsonValue& q = ex->array[i];
            const std::string pq = path + ".examples[" + std::to_string(i) + "]";
            expectKind(q, core::JsonValue::Kind::Array, pq);
            if (q.array.size() != 4) fail(q, pq, "a quaternion is [w, x, y, z]");
            std::array<double, 4> e {};
            double n2 = 0.0;
            for (int k = 0; k < 4; ++k) {
                e[static_cast<std::size_t>(k)] = numberIn(q.array[static_cast<std::size_t>(k)], pq + "[" + std::to_string(k) + "]", -1.0001, 1.0001);
                n2 += e[static_cast<std::size_t>(k)] * e[static_cast<std::size_t>(k)];
            }
            if (std::fabs(std::sqrt(n2) - 1.0) > 0.01) fail(q, pq, "not a unit quaternion (norm " + fmt(std::sqrt(n2)) + ")");
            for (double& c : e) c /= std::sqrt(n2);
            p.examples.push_back(e);
        }
        if (const core::JsonValue* x = v.find("radius")) p.radiusDeg = numberIn(*x, path + ".radius", 1.0, 180.0);
        if (const core::JsonValue* x = v.find("hysteresis")) p.hysteresisDeg = numberIn(*x, path + ".hysteresis", 0.0, 90.0);
        if (const core::JsonValue* x = v.find("maxSpeed")) p.maxSpeedDegS = numberIn(*x, path + ".maxSpeed", 1.0, 10000.0);
        return p;
    }

    MappingSpec mapping(const core::JsonValue& m, const std::string& path) const
    {
        expectKind(m, core::JsonValue::Kind::Object, path);
        onlyKeys(m, path, {"label", "source", "arm", "in", "out", "invert", "abs", "forward", "curve", "shape", "table", "smoothMs", "smooth",
                           "deadZone", "hysteresis", "threshold", "steps", "scale", "root", "zones", "muted", "to"});
        MappingSpec s;
        if (const core::JsonValue* l = m.find("label")) s.label = string(*l, path + ".label");
        const core::JsonValue* src = m.find("source");
        if (!src) fail(m, path, "missing \"source\"");
        s.source = source(*src, path + ".source");
        if (s.source.kind == SourceKind::GestureValue) fail(*src, path + ".source", "\"value\" is only a velocity/aux source of an event mapping");
        if (const core::JsonValue* arm = m.find("arm")) {
            // "arm": "left" (or 1) is the same as the "left." name; "right" (or 0) the unprefixed one.
            int which = 0;
            if (arm->kind == core::JsonValue::Kind::String) {
                if (arm->string != "right" && arm->string != "left") fail(*arm, path + ".arm", "unknown arm \"" + arm->string + "\" (right, left)");
                which = arm->string == "left" ? 1 : 0;
            } else {
                which = integerIn(*arm, path + ".arm", 0, 1);
            }
            if (!isArmSource(s.source.kind) && which != 0)
                fail(*arm, path + ".arm", "\"" + sourceName(s.source) + "\" is not read from one arm (only arm sources have a left arm: " +
                                              "elevation, azimuth, roll, yaw, pitch, qw…qz, ypr.q*, speed, fluxFace, fluxEdge, rollTrigger, punch)");
            if (isArmSource(s.source.kind) && s.source.arm == 1 && which == 0)
                fail(*arm, path + ".arm", "\"" + sourceName(s.source) + "\" is the left arm's, but \"arm\" says right");
            if (isArmSource(s.source.kind)) s.source.arm = std::max(s.source.arm, which);
        }
        s.transform = transform(m, path, s.source);
        if (s.source.kind == SourceKind::ArmsRaised) {   // a gate: always a threshold (docs/MAPPING.md "Two arms")
            if (m.find("zones") || (m.find("to") && m.find("to")->find("zones")))
                fail(*src, path + ".source", "\"arms.raised\" is a gate (both elevations above a threshold): no zones");
            if (!s.transform.hasThreshold) {
                s.transform.hasThreshold = true;
                s.transform.threshold = kDefaultArmsRaisedDeg;
            }
        }
        if (const core::JsonValue* z = m.find("zones")) s.zones = zones(*z, path + ".zones");
        if (const core::JsonValue* mu = m.find("muted")) s.muted = boolean(*mu, path + ".muted");
        const core::JsonValue* to = m.find("to");
        if (!to) fail(m, path, "missing \"to\" (the destination)");
        std::vector<ZoneSpec> zonesInTo;
        s.to = destination(*to, path + ".to", zonesInTo);
        if (!zonesInTo.empty()) {
            if (!s.zones.empty()) fail(*to, path + ".to.zones", "zones are given twice (beside \"to\" and in it)");
            s.zones = std::move(zonesInTo);
        }
        validate(s, m, path);
        return s;
    }

    void validate(const MappingSpec& s, const core::JsonValue& at, const std::string& path) const
    {
        const bool event = isEventSource(s.source.kind) || s.transform.hasThreshold;
        const bool zoned = !s.zones.empty();
        if (zoned && isEventSource(s.source.kind)) fail(at, path, "zones need a continuous source, not \"" + sourceName(s.source) + "\"");
        if (zoned && s.transform.hasThreshold) fail(at, path, "give zones or a threshold, not both");
        if (s.zones.size() > static_cast<std::size_t>(kMaxZones)) fail(at, path, "more than " + std::to_string(kMaxZones) + " zones");
        switch (s.to.kind) {
        case DestinationKind::Notes:
            if (!event && !zoned) fail(at, path, "notes need zones, a threshold or an event source (gesture:…, posture:…)");
            break;
        case DestinationKind::Mpe:
            if (!zoned) fail(at, path, "MPE needs zones (one note per zone)");
            break;
        case DestinationKind::SetForward:
            if (!event && !zoned) fail(at, path, "\"action\": \"forward\" needs an event (gesture, posture, threshold or zones)");
            break;
        case DestinationKind::Stage:
            if (!event && !zoned) fail(at, path, "\"stage\" needs an event (gesture, posture, threshold or zones): it acts once as it begins");
            break;
        default:
            break;
        }
        if (s.to.velocitySource.used && s.to.velocitySource.source.kind == SourceKind::GestureValue && s.source.kind != SourceKind::Gesture)
            fail(at, path, "velocity from \"value\" needs a gesture source");
    }

    static std::string fmt(double x)
    {
        char b[32];
        std::snprintf(b, sizeof b, "%g", x);
        return b;
    }

    static constexpr const char* kScaleList = "chromatic, major, minor, pentatonic, minor-pentatonic, dorian, whole-tone, blues";

public:
    static int scaleIntervals(const std::string& name);

private:
    std::string source_;
};

int Reader::scaleIntervals(const std::string& name)
{
    // Bit k set: pitch class k above the root belongs to the scale.
    if (name == "chromatic") return 0xFFF;
    if (name == "major") return (1 << 0) | (1 << 2) | (1 << 4) | (1 << 5) | (1 << 7) | (1 << 9) | (1 << 11);
    if (name == "minor") return (1 << 0) | (1 << 2) | (1 << 3) | (1 << 5) | (1 << 7) | (1 << 8) | (1 << 10);
    if (name == "pentatonic") return (1 << 0) | (1 << 2) | (1 << 4) | (1 << 7) | (1 << 9);
    if (name == "minor-pentatonic") return (1 << 0) | (1 << 3) | (1 << 5) | (1 << 7) | (1 << 10);
    if (name == "dorian") return (1 << 0) | (1 << 2) | (1 << 3) | (1 << 5) | (1 << 7) | (1 << 9) | (1 << 10);
    if (name == "whole-tone") return (1 << 0) | (1 << 2) | (1 << 4) | (1 << 6) | (1 << 8) | (1 << 10);
    if (name == "blues") return (1 << 0) | (1 << 3) | (1 << 5) | (1 << 6) | (1 << 7) | (1 << 10);
    return 0;
}

// ---- writing ---------------------------------------------------------------------------------

std::string num(double x)
{
    if (x == std::floor(x) && std::fabs(x) < 1e15) return std::to_string(static_cast<long long>(x));
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", x);
    // Shortest text that reads back to the same double.
    for (int p = 1; p <= 17; ++p) {
        char c[40];
        std::snprintf(c, sizeof c, "%.*g", p, x);
        if (std::strtod(c, nullptr) == x) return c;
    }
    return b;
}

std::string str(std::string_view s)
{
    std::string out;
    armadillo::core::appendJsonString(out, s);
    return out;
}

std::string auxJson(const AuxSpec& a)
{
    std::string s = "{\"source\": " + str(sourceName(a.source)) + ", \"in\": [" + num(a.lo) + ", " + num(a.hi) + "]";
    if (a.abs) s += ", \"abs\": true";
    return s + "}";
}

std::string zonesJson(const std::vector<ZoneSpec>& zones)
{
    std::string s = "[";
    for (std::size_t i = 0; i < zones.size(); ++i) {
        const ZoneSpec& z = zones[i];
        if (i) s += ", ";
        if (z.hasElevation)
            s += "{\"from\": " + num(z.from) + ", \"to\": " + num(z.to) + ", \"elevation\": [" + num(z.elFrom) + ", " + num(z.elTo) +
                 "], \"value\": " + std::to_string(z.value) + "}";
        else
            s += "[" + num(z.from) + ", " + num(z.to) + ", " + std::to_string(z.value) + "]";
    }
    return s + "]";
}

std::string oscArgJson(const OscArgSpec& a)
{
    const std::string neg = a.negate ? "-" : "";
    switch (a.kind) {
    case OscArgSpec::Kind::Number: return num(a.number);
    case OscArgSpec::Kind::String: return str(a.text);
    case OscArgSpec::Kind::Value: return str(neg + "$value");
    case OscArgSpec::Kind::Zone: return str(neg + "$zone");
    case OscArgSpec::Kind::On: return str(neg + "$on");
    case OscArgSpec::Kind::Source: return str(neg + "$" + sourceName(a.source));
    }
    return "0";
}

std::string destinationJson(const MappingSpec& m)
{
    const DestinationSpec& d = m.to;
    const std::string ch = ", \"channel\": " + std::to_string(d.channel);
    const auto velocity = [&]() {
        return d.velocitySource.used ? ", \"velocity\": " + auxJson(d.velocitySource) : ", \"velocity\": " + std::to_string(d.velocity);
    };
    switch (d.kind) {
    case DestinationKind::Cc7: return "{\"midi\": \"cc\"" + ch + ", \"cc\": " + std::to_string(d.number) + "}";
    case DestinationKind::Cc14:
        return "{\"midi\": \"cc14\"" + ch + ", \"cc\": " + std::to_string(d.number) + (d.lsbFirst ? ", \"lsbFirst\": true" : "") + "}";
    case DestinationKind::Nrpn: return "{\"midi\": \"nrpn\"" + ch + ", \"number\": " + std::to_string(d.number) + "}";
    case DestinationKind::PitchBend: return "{\"midi\": \"pitchbend\"" + ch + "}";
    case DestinationKind::ChannelPressure: return "{\"midi\": \"pressure\"" + ch + "}";
    case DestinationKind::Notes: {
        std::string s = "{\"midi\": \"" + std::string(m.zones.empty() ? "note" : "notes") + "\"" + ch + velocity();
        if (m.zones.empty()) s += ", \"note\": " + std::to_string(d.number);
        if (d.lengthMs > 0.0) s += ", \"lengthMs\": " + num(d.lengthMs);
        return s + "}";
    }
    case DestinationKind::Mpe: {
        std::string s = "{\"midi\": \"mpe\"" + ch + velocity() + ", \"members\": " + std::to_string(d.mpeMembers) +
                        ", \"bendRange\": " + num(d.mpeBendRange);
        if (d.mpeBend.used) s += ", \"bend\": " + auxJson(d.mpeBend);
        if (d.mpePressure.used) s += ", \"pressure\": " + auxJson(d.mpePressure);
        if (d.mpeTimbre.used) s += ", \"timbre\": " + auxJson(d.mpeTimbre);
        return s + "}";
    }
    case DestinationKind::ProgramChange: return "{\"midi\": \"program\"" + ch + ", \"program\": " + std::to_string(d.number) + "}";
    case DestinationKind::Osc: {
        std::string s = "{\"osc\": " + str(d.address);
        if (!d.args.empty()) {
            s += ", \"args\": [";
            std::string types;
            for (std::size_t i = 0; i < d.args.size(); ++i) {
                s += (i ? ", " : "") + oscArgJson(d.args[i]);
                types += d.args[i].type;
            }
            s += "], \"types\": " + str(types);
        }
        if (!d.host.empty()) s += ", \"host\": " + str(d.host);
        if (d.port > 0) s += ", \"port\": " + std::to_string(d.port);
        return s + "}";
    }
    case DestinationKind::Mqtt: {
        std::string s = "{\"mqtt\": {\"topic\": " + str(d.address) + ", \"payload\": " + str(d.payload) + ", \"qos\": " + std::to_string(d.qos) +
                        ", \"retain\": " + (d.retain ? "true" : "false");
        if (d.rate >= 0.0) s += ", \"rate\": " + num(d.rate);
        return s + "}}";
    }
    case DestinationKind::Macro: return "{\"macro\": " + std::to_string(d.number) + "}";
    case DestinationKind::SceneParam: return "{\"param\": " + str(d.paramId) + "}";
    case DestinationKind::SetForward: return "{\"action\": \"forward\"}";
    case DestinationKind::Stage:
        return std::string("{\"stage\": \"") + stageActionName(d.stage) + "\"" +
               (d.stage == core::StageCommand::Kind::CueGoto ? ", \"cue\": " + std::to_string(d.number) : std::string()) + "}";
    }
    return "{}";
}

} // namespace

// ---- public ----------------------------------------------------------------------------------

const char* stageActionName(core::StageCommand::Kind a) noexcept
{
    switch (a) {
    case core::StageCommand::Kind::CueNext: return "next";
    case core::StageCommand::Kind::CuePrev: return "prev";
    case core::StageCommand::Kind::CueGoto: return "cue";
    case core::StageCommand::Kind::Panic: return "panic";
    case core::StageCommand::Kind::Resume: return "resume";
    }
    return "next";
}

std::string sourceName(const SourceSpec& s)
{
    if (s.kind == SourceKind::Gesture) return "gesture:" + s.name;
    if (s.kind == SourceKind::Posture) return "posture:" + s.name;
    const std::string prefix = s.arm == 1 && isArmSource(s.kind) ? "left." : "";
    for (const auto& e : kSourceNames)
        if (e.kind == s.kind) return prefix + e.name;
    return "?";
}

bool parseSourceName(std::string_view text, SourceSpec& out)
{
    // "left.NAME" / "right.NAME": one arm's NAME, for the sources read from one arm.
    for (const auto& [prefix, arm] : {std::pair<std::string_view, int> {"left.", 1}, {"right.", 0}}) {
        if (text.substr(0, prefix.size()) != prefix) continue;
        SourceSpec s;
        if (!parseSourceName(text.substr(prefix.size()), s) || !isArmSource(s.kind) || s.arm != 0) return false;
        s.arm = arm;
        out = s;
        return true;
    }
    SourceSpec s;
    if (text.substr(0, 8) == "gesture:" && text.size() > 8) {
        s.kind = SourceKind::Gesture;
        s.name = std::string(text.substr(8));
        out = s;
        return true;
    }
    if (text.substr(0, 8) == "posture:" && text.size() > 8) {
        s.kind = SourceKind::Posture;
        s.name = std::string(text.substr(8));
        out = s;
        return true;
    }
    for (const auto& e : kSourceNames) {
        if (text == e.name) {
            s.kind = e.kind;
            out = s;
            return true;
        }
    }
    return false;
}

bool isEventSource(SourceKind k) noexcept { return k == SourceKind::Gesture || k == SourceKind::Posture; }

bool isAngleSource(SourceKind k) noexcept
{
    return k == SourceKind::Elevation || k == SourceKind::Azimuth || k == SourceKind::Roll || k == SourceKind::Yaw ||
           k == SourceKind::Pitch || k == SourceKind::ArmsAngle || k == SourceKind::ArmsRoll || k == SourceKind::ArmsRaised;
}

bool isSteppedPanelSource(SourceKind k) noexcept
{
    return k == SourceKind::PanelKnob || k == SourceKind::PanelLevel || k == SourceKind::PanelSelected;
}

bool isArmSource(SourceKind k) noexcept
{
    switch (k) {
    case SourceKind::ScenePitch:
    case SourceKind::SceneFret:
    case SourceKind::SceneStrike:
    case SourceKind::PanelKnob:
    case SourceKind::PanelLevel:
    case SourceKind::PanelSelected:
    case SourceKind::Gesture:
    case SourceKind::Posture:
    case SourceKind::GestureValue:
    case SourceKind::ArmsAngle:
    case SourceKind::ArmsRoll:
    case SourceKind::ArmsRaised: return false;
    default: return true;
    }
}

bool isTwoArmSource(SourceKind k) noexcept
{
    return k == SourceKind::ArmsAngle || k == SourceKind::ArmsRoll || k == SourceKind::ArmsRaised;
}

void defaultInputRange(SourceKind k, double& lo, double& hi) noexcept
{
    switch (k) {
    case SourceKind::Elevation:
    case SourceKind::Pitch:
    case SourceKind::ArmsRaised: lo = -90.0; hi = 90.0; return;
    case SourceKind::ArmsAngle: lo = 0.0; hi = 180.0; return;
    case SourceKind::ArmsRoll: lo = -180.0; hi = 180.0; return;
    case SourceKind::Azimuth: lo = 0.0; hi = 360.0; return;
    case SourceKind::Roll:
    case SourceKind::Yaw: lo = -180.0; hi = 180.0; return;
    case SourceKind::QuatW:
    case SourceKind::QuatX:
    case SourceKind::QuatY:
    case SourceKind::QuatZ:
    case SourceKind::YprQuatW:
    case SourceKind::YprQuatX:
    case SourceKind::YprQuatY:
    case SourceKind::YprQuatZ: lo = -1.0; hi = 1.0; return;
    case SourceKind::AngularSpeed: lo = 0.0; hi = 720.0; return;
    case SourceKind::FluxFace:
    case SourceKind::FluxEdge: lo = -720.0; hi = 720.0; return;
    case SourceKind::RollTrigger: lo = -5.0; hi = 5.0; return;
    case SourceKind::Punch: lo = -20.0; hi = 20.0; return;
    case SourceKind::ScenePitch: lo = 0.0; hi = 127.0; return;
    case SourceKind::SceneFret: lo = 0.0; hi = 24.0; return;
    case SourceKind::SceneStrike: lo = 0.0; hi = 1000.0; return;
    case SourceKind::PanelKnob:
    case SourceKind::PanelSelected: lo = 0.0; hi = 17.0; return;
    case SourceKind::PanelLevel: lo = 0.0; hi = 1.0; return;
    case SourceKind::Gesture:
    case SourceKind::Posture:
    case SourceKind::GestureValue: lo = 0.0; hi = 1.0; return;
    }
    lo = 0.0;
    hi = 1.0;
}

int scaleMask(const std::string& name) { return Reader::scaleIntervals(name); }

MappingDocument parseMappingDocument(std::string_view text, const std::string& sourceName)
{
    const core::JsonValue root = armadillo::core::parseJson(text, sourceName);
    Reader r(sourceName);
    r.expectKind(root, core::JsonValue::Kind::Object, "the file");
    r.onlyKeys(root, "the file", {"version", "name", "mappings", "postures"});
    MappingDocument doc;
    const core::JsonValue* version = root.find("version");
    if (!version) r.fail(root, "the file", "missing \"version\" (this program reads version " + std::to_string(kMappingFileVersion) + ")");
    doc.version = r.integerIn(*version, "version", 0, 1000000);
    if (doc.version != kMappingFileVersion)
        r.fail(*version, "version", "version " + std::to_string(doc.version) + " is not supported (this program reads version " +
                                        std::to_string(kMappingFileVersion) + ")");
    if (const core::JsonValue* n = root.find("name")) doc.name = r.string(*n, "name");
    if (const core::JsonValue* p = root.find("postures")) {
        r.expectKind(*p, core::JsonValue::Kind::Array, "postures");
        if (p->array.size() > 16) r.fail(*p, "postures", "more than 16 postures");
        std::set<std::string> names;
        for (std::size_t i = 0; i < p->array.size(); ++i) {
            doc.postures.push_back(r.posture(p->array[i], "postures[" + std::to_string(i) + "]"));
            if (!names.insert(doc.postures.back().name).second)
                r.fail(p->array[i], "postures[" + std::to_string(i) + "]", "a second posture named \"" + doc.postures.back().name + "\"");
        }
    }
    const core::JsonValue* mappings = root.find("mappings");
    if (!mappings) r.fail(root, "the file", "missing \"mappings\"");
    r.expectKind(*mappings, core::JsonValue::Kind::Array, "mappings");
    if (mappings->array.size() > static_cast<std::size_t>(kMaxMappings))
        r.fail(*mappings, "mappings", "more than " + std::to_string(kMaxMappings) + " mappings");
    for (std::size_t i = 0; i < mappings->array.size(); ++i) {
        const std::string path = "mappings[" + std::to_string(i) + "]";
        doc.mappings.push_back(r.mapping(mappings->array[i], path));
        const MappingSpec& m = doc.mappings.back();
        const auto names = [&](const SourceSpec& s) {
            if (s.kind != SourceKind::Posture) return;
            bool found = false;
            for (const PostureSpec& p : doc.postures) found = found || p.name == s.name;
            if (!found) r.fail(mappings->array[i], path + ".source", "no posture named \"" + s.name + "\" in \"postures\"");
        };
        names(m.source);
    }
    return doc;
}

std::string toJson(const MappingDocument& doc)
{
    std::string s = "{\"version\": " + std::to_string(doc.version);
    if (!doc.name.empty()) s += ", \"name\": " + str(doc.name);
    s += ", \"mappings\": [";
    for (std::size_t i = 0; i < doc.mappings.size(); ++i) {
        const MappingSpec& m = doc.mappings[i];
        const TransformSpec& t = m.transform;
        s += i ? ",\n  {" : "\n  {";
        if (!m.label.empty()) s += "\"label\": " + str(m.label) + ", ";
        s += "\"source\": " + str(sourceName(m.source));
        if (t.hasIn) s += ", \"in\": [" + num(t.inLo) + ", " + num(t.inHi) + "]";
        if (t.hasOut) s += ", \"out\": [" + num(t.outLo) + ", " + num(t.outHi) + "]";
        if (t.invert) s += ", \"invert\": true";
        if (t.abs) s += ", \"abs\": true";
        if (t.forward) s += ", \"forward\": true";
        static constexpr const char* curves[] {"linear", "exp", "log", "s", "table"};
        if (t.curve != Curve::Linear) s += ", \"curve\": \"" + std::string(curves[static_cast<int>(t.curve)]) + "\"";
        if (t.curve == Curve::Exp || t.curve == Curve::Log || t.curve == Curve::SCurve) s += ", \"shape\": " + num(t.shape);
        if (t.curve == Curve::Table) {
            s += ", \"table\": [";
            for (std::size_t k = 0; k < t.table.size(); ++k) s += (k ? ", [" : "[") + num(t.table[k][0]) + ", " + num(t.table[k][1]) + "]";
            s += "]";
        }
        if (t.minCutoffHz > 0.0)
            s += ", \"smooth\": {\"minCutoffHz\": " + num(t.minCutoffHz) + ", \"beta\": " + num(t.beta) + ", \"derivativeCutoffHz\": " +
                 num(t.derivativeCutoffHz) + "}";
        if (t.deadZone > 0.0) s += ", \"deadZone\": " + num(t.deadZone);
        if (t.hysteresis >= 0.0) s += ", \"hysteresis\": " + num(t.hysteresis);
        if (t.hasThreshold) s += ", \"threshold\": " + num(t.threshold);
        if (t.steps > 1) s += ", \"steps\": " + std::to_string(t.steps);
        if (!t.scale.empty()) s += ", \"scale\": " + str(t.scale) + ", \"root\": " + std::to_string(t.scaleRoot);
        if (!m.zones.empty()) s += ", \"zones\": " + zonesJson(m.zones);
        if (m.muted) s += ", \"muted\": true";
        s += ", \"to\": " + destinationJson(m) + "}";
    }
    s += "]";
    if (!doc.postures.empty()) {
        s += ",\n \"postures\": [";
        for (std::size_t i = 0; i < doc.postures.size(); ++i) {
            const PostureSpec& p = doc.postures[i];
            s += (i ? ",\n  {" : "\n  {") + std::string("\"name\": ") + str(p.name) + ", \"radius\": " + num(p.radiusDeg);
            if (p.hysteresisDeg >= 0.0) s += ", \"hysteresis\": " + num(p.hysteresisDeg);
            s += ", \"maxSpeed\": " + num(p.maxSpeedDegS) + ", \"examples\": [";
            for (std::size_t k = 0; k < p.examples.size(); ++k) {
                const auto& q = p.examples[k];
                s += (k ? ", [" : "[") + num(q[0]) + ", " + num(q[1]) + ", " + num(q[2]) + ", " + num(q[3]) + "]";
            }
            s += "]}";
        }
        s += "]";
    }
    return s + "}\n";
}

std::vector<std::string> presetNames(const std::string& extraDir)
{
    std::set<std::string> names;
    for (const core::EmbeddedFile& f : core::embeddedResources()) {
        const std::string_view p = f.path;
        if (p.substr(0, 9) == "Mappings/" && p.size() > 14 && p.substr(p.size() - 5) == ".json")
            names.insert(std::string(p.substr(9, p.size() - 14)));
    }
    for (const std::string& dir : core::resourceSearchDirs(extraDir)) {
        std::error_code ec;
        const std::filesystem::path folder = std::filesystem::path(dir) / "Mappings";
        if (!std::filesystem::is_directory(folder, ec)) continue;
        for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
            if (entry.path().extension() == ".json") names.insert(entry.path().stem().string());
        }
    }
    return {names.begin(), names.end()};
}

namespace {
MappingDocument loadMappingFile(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw core::IoError("--map " + path + ": cannot open the mapping file");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw core::IoError("--map " + path + ": cannot read the mapping file");
    return parseMappingDocument(text, path);
}
} // namespace

MappingDocument loadMapping(const std::string& presetOrPath, const std::string& extraDir)
{
    if (presetOrPath.empty()) throw core::InputError("", 0, "--map", "empty mapping name (a preset or a .json file)");
    const bool looksLikeName = presetOrPath.find('/') == std::string::npos && presetOrPath.find('.') == std::string::npos;
    if (looksLikeName) {
        if (auto found = core::findResource("Mappings/" + presetOrPath + ".json", extraDir))
            return parseMappingDocument(found->bytes, found->origin);
        std::error_code ec;
        if (std::filesystem::is_regular_file(presetOrPath, ec)) return loadMappingFile(presetOrPath);
        std::string list;
        for (const std::string& n : presetNames(extraDir)) list += (list.empty() ? "" : ", ") + n;
        throw core::IoError("--map " + presetOrPath + ": no preset and no file of that name (presets: " + list + ")");
    }
    return loadMappingFile(presetOrPath);
}

std::vector<MqttPayloadPart> splitMqttPayload(const std::string& payload)
{
    static const std::pair<const char*, MqttPayloadPart::Field> names[] {
        {"{value}", MqttPayloadPart::Field::Value}, {"{round}", MqttPayloadPart::Field::Round}, {"{zone}", MqttPayloadPart::Field::Zone},
        {"{on}", MqttPayloadPart::Field::On},       {"{state}", MqttPayloadPart::Field::State}, {"{arm}", MqttPayloadPart::Field::Arm}};
    std::vector<MqttPayloadPart> parts(1);
    for (std::size_t i = 0; i < payload.size();) {
        bool matched = false;
        for (const auto& [name, field] : names) {
            const std::size_t n = std::char_traits<char>::length(name);
            if (payload.compare(i, n, name) == 0) {
                parts.back().field = field;
                parts.emplace_back();
                i += n;
                matched = true;
                break;
            }
        }
        if (!matched) parts.back().text += payload[i++];
    }
    return parts;
}

std::string mqttPayloadProblem(const std::string& payload)
{
    // A "{word}" of letters that is not a placeholder is a typo, not JSON (JSON keys are quoted).
    for (std::size_t i = 0; i < payload.size(); ++i) {
        if (payload[i] != '{') continue;
        std::size_t k = i + 1;
        while (k < payload.size() && std::isalpha(static_cast<unsigned char>(payload[k]))) ++k;
        if (k > i + 1 && k < payload.size() && payload[k] == '}') {
            const std::string name = payload.substr(i, k - i + 1);
            if (name != "{value}" && name != "{round}" && name != "{zone}" && name != "{on}" && name != "{state}" && name != "{arm}")
                return "unknown placeholder " + name + " (value, round, zone, on, state, arm)";
        }
    }
    if (payload.size() > 300) return "payload template longer than 300 characters";
    return {};
}

} // namespace armadillo::mapping
