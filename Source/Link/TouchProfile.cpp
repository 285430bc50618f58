#include "Link/TouchProfile.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <algorithm>
#include <cmath>

namespace armadillo::device {

namespace {
int levelValue(const JsonValue& v, const std::string& source, const std::string& key, int lo, int hi)
{
    if (v.kind != JsonValue::Kind::Number) throw InputError(source, v.line, key, std::string("is ") + JsonValue::kindName(v.kind) + ", not a number");
    if (v.number != std::floor(v.number) || v.number < lo || v.number > hi)
        throw InputError(source, v.line, key, "must be a whole number " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<int>(v.number);
}
} // namespace

TouchProfile parseTouchProfile(std::string_view json, const std::string& source)
{
    const JsonValue root = parseJson(json, source);
    if (root.kind != JsonValue::Kind::Object) throw InputError(source, root.line, "", "a touch profile is a JSON object");
    TouchProfile p;
    if (const JsonValue* f = root.find("format"); f && (f->kind != JsonValue::Kind::String || f->string != "armadillo-touch-profile"))
        throw InputError(source, f->line, "format", "not an armadillo touch profile (\"format\": \"armadillo-touch-profile\")");
    if (const JsonValue* v = root.find("version"); v && levelValue(*v, source, "version", 1, 1000) != 1)
        throw InputError(source, v->line, "version", "this program reads touch profile version 1");
    const JsonValue* t = root.find("threshold");
    if (!t) throw InputError(source, root.line, "threshold", "missing (an array of 9 levels, motors m1..m9)");
    if (t->kind != JsonValue::Kind::Array || t->array.size() != kProfileMotors)
        throw InputError(source, t->line, "threshold", "expected an array of 9 levels (motors m1..m9)");
    for (std::size_t i = 0; i < kProfileMotors; ++i)
        p.threshold[i] = levelValue(t->array[i], source, "threshold[" + std::to_string(i) + "]", 1, kMaxLevel);
    if (const JsonValue* f = root.find("felt")) {
        if (f->kind != JsonValue::Kind::Array || f->array.size() != kProfileMotors)
            throw InputError(source, f->line, "felt", "expected an array of 9 true/false");
        for (std::size_t i = 0; i < kProfileMotors; ++i) {
            if (f->array[i].kind != JsonValue::Kind::Bool) throw InputError(source, f->array[i].line, "felt", "expected true or false");
            p.felt[i] = f->array[i].boolean;
        }
    }
    if (const JsonValue* c = root.find("comfort")) p.comfort = levelValue(*c, source, "comfort", 0, kMaxLevel);
    if (const JsonValue* c = root.find("comfort_motor")) p.comfortMotor = levelValue(*c, source, "comfort_motor", 1, kProfileMotors);
    if (const JsonValue* a = root.find("arm"); a && a->kind == JsonValue::Kind::String) p.arm = a->string;
    if (const JsonValue* d = root.find("date"); d && d->kind == JsonValue::Kind::String) p.date = d->string;
    if (const JsonValue* s = root.find("stimuli"); s && s->kind == JsonValue::Kind::Number) p.stimuli = static_cast<int>(s->number);
    if (const JsonValue* s = root.find("stimulus_seconds"); s && s->kind == JsonValue::Kind::Number) p.stimulusSeconds = s->number;
    return p;
}

TouchProfile loadTouchProfile(const std::string& path) { return parseTouchProfile(readWholeFile(path), path); }

std::string touchProfileToJson(const TouchProfile& p)
{
    std::string out = "{\n  \"format\": \"armadillo-touch-profile\",\n  \"version\": 1,\n  \"threshold\": [";
    for (std::size_t i = 0; i < kProfileMotors; ++i) out += (i ? ", " : "") + std::to_string(p.threshold[i]);
    out += "],\n  \"felt\": [";
    for (std::size_t i = 0; i < kProfileMotors; ++i) out += std::string(i ? ", " : "") + (p.felt[i] ? "true" : "false");
    out += "],\n  \"comfort\": " + std::to_string(p.comfort) + ",\n  \"comfort_motor\": " + std::to_string(p.comfortMotor);
    if (!p.arm.empty()) {
        out += ",\n  \"arm\": ";
        appendJsonString(out, p.arm);
    }
    if (!p.date.empty()) {
        out += ",\n  \"date\": ";
        appendJsonString(out, p.date);
    }
    out += ",\n  \"stimuli\": " + std::to_string(p.stimuli) + ",\n  \"stimulus_seconds\": ";
    appendNumber(out, p.stimulusSeconds, 6);
    out += "\n}\n";
    return out;
}

void saveTouchProfile(const std::string& path, const TouchProfile& profile) { writeFileAtomically(path, touchProfileToJson(profile)); }

std::array<float, kMaxMotors> touchProfileGains(const TouchProfile& profile)
{
    std::array<float, kMaxMotors> g {};
    g.fill(1.0f);
    std::array<int, kProfileMotors> sorted = profile.threshold;
    std::sort(sorted.begin(), sorted.end());
    const double median = std::max(1, sorted[kProfileMotors / 2]);
    for (std::size_t i = 0; i < kProfileMotors; ++i)
        g[i] = static_cast<float>(std::clamp(std::max(1, profile.threshold[i]) / median, 0.25, 4.0));
    return g;
}

} // namespace armadillo::device
