#include "Link/TouchProfile.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <algorithm>
#include <cmath>

namespace armadillo::link {

namespace {
int levelValue(const core::JsonValue& v, const std::string& source, const std::string& key, int lo, int hi)
{
    if (v.kind != core::JsonValue::Kind::Number) throw core::InputError(source, v.line, key, std::string("is ") + core::JsonValue::kindName(v.kind) + ", not a number");
    if (v.number != std::floor(v.number) || v.number < lo || v.number > hi)
        throw core::InputError(source, v.line, key, "must be a whole number " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<int>(v.number);
}
} // namespace

TouchProfile parseTouchProfile(std::string_view json, const std::string& source)
{
    const core::JsonValue root = core::parseJson(json, source);
    if (root.kind != core::JsonValue::Kind::Object) throw core::InputError(source, root.line, "", "a touch profile is a JSON object");
    TouchProfile p;
    if (const core::JsonValue* f = root.find("format"); f && (f->kind != core::JsonValue::Kind::String || f->string != "armadillo-touch-profile"))
        throw core::InputError(source, f->line, "format", "not an armadillo touch profile (\"format\": \"armadillo-touch-profile\")");
    if (const core::JsonValue* v = root.find("version"); v && levelValue(*v, source, "version", 1, 1000) != 1)
        throw core::InputError(source, v->line, "version", "this program reads touch profile version 1");
    const core::JsonValue* t = root.find("threshold");
    if (!t) throw core::InputError(source, root.line, "threshold", "missing (an array of 9 levels, motors m1..m9)");
    if (t->kind != core::JsonValue::Kind::Array || t->array.size() != kProfileMotors)
        throw core::InputError(source, t->line, "threshold", "expected an array of 9 levels (motors m1..m9)");
    for (std::size_t i = 0; i < kProfileMotors; ++i)
        p.threshold[i] = levelValue(t->array[i], source, "threshold[" + std::to_string(i) + "]", 1, core::kMaxLevel);
    if (const core::JsonValue* f = root.find("felt")) {
        if (f->kind != core::JsonValue::Kind::Array || f->array.size() != kProfileMotors)
            throw core::InputError(source, f->line, "felt", "expected an array of 9 true/false");
        for (std::size_t i = 0; i < kProfileMotors; ++i) {
            if (f->array[i].kind != core::JsonValue::Kind::Bool) throw core::InputError(source, f->array[i].line, "felt", "expected true or false");
            p.felt[i] = f->array[i].boolean;
        }
    }
    if (const core::JsonValue* c = root.find("comfort")) p.comfort = levelValue(*c, source, "comfort", 0, core::kMaxLevel);
    if (const core::JsonValue* c = root.find("comfort_motor")) p.comfortMotor = levelValue(*c, source, "comfort_motor", 1, kProfileMotors);
    if (const core::JsonValue* a = root.find("arm"); a && a->kind == core::JsonValue::Kind::String) p.arm = a->string;
    if (const core::JsonValue* d = root.find("date"); d && d->kind == core::JsonValue::Kind::String) p.date = d->string;
    if (const core::JsonValue* s = root.find("stimuli"); s && s->kind == core::JsonValue::Kind::Number) p.stimuli = static_cast<int>(s->number);
    if (const core::JsonValue* s = root.find("stimulus_seconds"); s && s->kind == core::JsonValue::Kind::Number) p.stimulusSeconds = s->number;
    return p;
}

TouchProfile loadTouchProfile(const std::string& path) { return parseTouchProfile(core::readWholeFile(path), path); }

std::string touchProfileToJson(const TouchProfile& p)
{
    std::string out = "{\n  \"format\": \"armadillo-touch-profile\",\n  \"version\": 1,\n  \"threshold\": [";
    for (std::size_t i = 0; i < kProfileMotors; ++i) out += (i ? ", " : "") + std::to_string(p.threshold[i]);
    out += "],\n  \"felt\": [";
    for (std::size_t i = 0; i < kProfileMotors; ++i) out += std::string(i ? ", " : "") + (p.felt[i] ? "true" : "false");
    out += "],\n  \"comfort\": " + std::to_string(p.comfort) + ",\n  \"comfort_motor\": " + std::to_string(p.comfortMotor);
    if (!p.arm.empty()) {
        out += ",\n  \"arm\": ";
        core::appendJsonString(out, p.arm);
    }
    if (!p.date.empty()) {
        out += ",\n  \"date\": ";
        core::appendJsonString(out, p.date);
    }
    out += ",\n  \"stimuli\": " + std::to_string(p.stimuli) + ",\n  \"stimulus_seconds\": ";
    core::appendNumber(out, p.stimulusSeconds, 6);
    out += "\n}\n";
    return out;
}

void saveTouchProfile(const std::string& path, const TouchProfile& profile) { core::writeFileAtomically(path, touchProfileToJson(profile)); }

std::array<float, core::kMaxMotors> touchProfileGains(const TouchProfile& profile)
{
    std::array<float, core::kMaxMotors> g {};
    g.fill(1.0f);
    std::array<int, kProfileMotors> sorted = profile.threshold;
    std::sort(sorted.begin(), sorted.end());
    const double median = std::max(1, sorted[kProfileMotors / 2]);
    for (std::size_t i = 0; i < kProfileMotors; ++i)
        g[i] = static_cast<float>(std::clamp(std::max(1, profile.threshold[i]) / median, 0.25, 4.0));
    return g;
}

} // namespace armadillo::link
