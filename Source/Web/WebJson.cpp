#include "Web/WebJson.h"
#include "Core/Json.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace armadillo::web {

namespace {

void number(std::string& out, double v, int decimals)
{
    if (!std::isfinite(v)) {
        out += "null";
        return;
    }
    char text[48];
    std::snprintf(text, sizeof text, "%.*f", decimals, v);
    out += text;
}

void key(std::string& out, const char* name)
{
    if (out.back() != '{') out += ',';
    out += '"';
    out += name;
    out += "\":";
}

void field(std::string& out, const char* name, const std::string& v)
{
    key(out, name);
    core::appendJsonString(out, v);
}
void field(std::string& out, const char* name, double v, int decimals)
{
    key(out, name);
    number(out, v, decimals);
}
void field(std::string& out, const char* name, std::uint64_t v)
{
    key(out, name);
    out += std::to_string(v);
}
void flag(std::string& out, const char* name, bool v)
{
    key(out, name);
    out += v ? "true" : "false";
}
void strings(std::string& out, const char* name, const std::vector<std::string>& list)
{
    key(out, name);
    out += '[';
    for (std::size_t i = 0; i < list.size(); ++i) {
        if (i > 0) out += ',';
        core::appendJsonString(out, list[i]);
    }
    out += ']';
}

void walkJson(std::string& out, const InstrumentStatus::Walk& w)
{
    key(out, "walk");
    if (!w.on) {
        out += "null";
        return;
    }
    out += '{';
    field(out, "route", w.route);
    field(out, "waypoint", static_cast<std::uint64_t>(std::max(0, w.waypoint)));
    field(out, "waypoints", static_cast<std::uint64_t>(std::max(0, w.waypointCount)));
    field(out, "name", w.waypointName);
    field(out, "distance_m", w.distanceM >= 0.0 ? w.distanceM : std::nan(""), 1);
    field(out, "bearing_deg", w.bearingDeg >= 0.0 ? w.bearingDeg : std::nan(""), 0);
    field(out, "arrivals", static_cast<std::uint64_t>(std::max(0, w.arrivals)));
    flag(out, "finished", w.finished);
    field(out, "fix", w.fix);
    out += '}';
}

void procedureJson(std::string& out, const ProcedureStatus& p)
{
    key(out, "calibration");
    out += '{';
    flag(out, "available", p.available);
    field(out, "why", p.why);
    flag(out, "running", p.running);
    flag(out, "finished", p.finished);
    field(out, "step", static_cast<std::uint64_t>(std::max(0, p.step)));
    field(out, "steps", static_cast<std::uint64_t>(std::max(0, p.steps)));
    field(out, "title", p.title);
    field(out, "instruction", p.instruction);
    field(out, "progress", p.progress, 2);
    flag(out, "ready", p.ready);
    field(out, "note", p.note);
    out += '}';
}

void touchJson(std::string& out, const TouchTestStatus& t)
{
    key(out, "touch");
    out += '{';
    flag(out, "available", t.available);
    field(out, "why", t.why);
    flag(out, "running", t.running);
    flag(out, "asking", t.asking);
    flag(out, "comfort", t.comfort);
    flag(out, "finished", t.finished);
    field(out, "stimuli", static_cast<std::uint64_t>(std::max(0, t.stimuli)));
    field(out, "question", t.question);
    field(out, "result", t.result);
    field(out, "note", t.note);
    out += '}';
}

} // namespace

std::string statusJson(const InstrumentStatus& s)
{
    std::string out = "{";
    field(out, "t", s.t, 3);
    field(out, "source", s.source);
    flag(out, "connected", s.connected);
    field(out, "rate_hz", s.rateHz, 1);
    field(out, "packets", s.packets);
    field(out, "bad_packets", s.badPackets);
    field(out, "gaps", s.gaps);
    field(out, "dropped", s.dropped);
    field(out, "sender", s.sender);
    key(out, "pose");
    if (s.hasPose) {
        out += '{';
        field(out, "elevation_deg", s.elevationDeg, 1);
        field(out, "azimuth_deg", s.azimuthDeg, 1);
        field(out, "roll_deg", s.rollDeg, 1);
        out += '}';
    } else {
        out += "null";
    }
    field(out, "scene", s.scene);
    flag(out, "panicked", s.panicked);
    field(out, "panics", static_cast<std::uint64_t>(s.panics));
    key(out, "cue");
    out += std::to_string(s.cue);
    field(out, "cue_count", static_cast<std::uint64_t>(s.cues.size()));
    strings(out, "messages", s.messages);
    walkJson(out, s.walk);
    procedureJson(out, s.calibration);
    touchJson(out, s.touch);
    out += '}';
    return out;
}

std::string sceneJson(const InstrumentStatus& s, const std::vector<ParameterInfo>& parameters, const std::vector<std::string>& scenes,
                      const std::string& sceneChoice)
{
    std::string out = "{";
    field(out, "scene", s.scene);
    strings(out, "cues", s.cues);
    strings(out, "scenes", scenes);
    field(out, "scene_choice", sceneChoice);
    key(out, "parameters");
    out += '[';
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        const ParameterInfo& p = parameters[i];
        if (i > 0) out += ',';
        out += '{';
        field(out, "id", p.id);
        field(out, "name", p.name);
        field(out, "unit", p.unit);
        field(out, "min", p.min, 4);
        field(out, "max", p.max, 4);
        field(out, "value", p.value, 4);
        strings(out, "choices", p.choices);
        out += '}';
    }
    out += "]}";
    return out;
}

std::string commandJson(const std::string& command, double t)
{
    std::string out = "{";
    flag(out, "ok", true);
    field(out, "command", command);
    field(out, "t", t, 3);
    out += '}';
    return out;
}

std::string parameterSetJson(const std::string& id, double value)
{
    std::string out = "{";
    flag(out, "ok", true);
    field(out, "id", id);
    field(out, "value", value, 4);
    out += '}';
    return out;
}

} // namespace armadillo::web
