#include "Access/ReaderProfile.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <algorithm>
#include <cmath>
#include <filesystem>

namespace armadillo::access {

using armadillo::core::JsonValue;

int ReaderProfile::nextSession() const noexcept
{
    int n = 0;
    for (const auto& s : sessions) n = std::max(n, s.session);
    for (const auto& a : answers) n = std::max(n, a.session);
    return n + 1;
}

namespace {
const core::JsonValue& member(const core::JsonValue& object, const char* key, core::JsonValue::Kind kind, const std::string& source)
{
    const core::JsonValue* v = object.find(key);
    if (!v) throw core::InputError(source, object.line, key, "missing");
    if (v->kind != kind)
        throw core::InputError(source, v->line, key, std::string("is ") + core::JsonValue::kindName(v->kind) + ", expected " + core::JsonValue::kindName(kind));
    return *v;
}

// A session number: a whole number from `least` to a million (a number outside int's range was
// undefined behaviour to convert; found by fuzzing, Tests/Fuzz/regressions/reader_profile/).
int sessionNumber(const core::JsonValue& object, int least, const std::string& source)
{
    const core::JsonValue& v = member(object, "session", core::JsonValue::Kind::Number, source);
    if (!(v.number >= least && v.number <= 1e6) || v.number != std::floor(v.number))
        throw core::InputError(source, v.line, "session", "must be a whole number, " + std::to_string(least) + " or more");
    return static_cast<int>(v.number);
}

std::string optionalString(const core::JsonValue& object, const char* key, const std::string& source)
{
    const core::JsonValue* v = object.find(key);
    if (!v) return {};
    if (v->kind != core::JsonValue::Kind::String) throw core::InputError(source, v->line, key, "expected a string");
    return v->string;
}
} // namespace

ReaderProfile parseReaderProfile(std::string_view json, const std::string& source)
{
    const core::JsonValue root = armadillo::core::parseJson(json, source);
    if (root.kind != core::JsonValue::Kind::Object) throw core::InputError(source, root.line, "", "a reader profile is a JSON object");
    const core::JsonValue& format = member(root, "format", core::JsonValue::Kind::String, source);
    if (format.string != "armadillo-reader") throw core::InputError(source, format.line, "format", "not an armadillo reader profile");
    if (const core::JsonValue* v = root.find("version"); v && (v->kind != core::JsonValue::Kind::Number || v->number != 1.0))
        throw core::InputError(source, v->line, "version", "this program reads reader profile version 1");
    ReaderProfile p;
    p.name = optionalString(root, "name", source);
    if (const core::JsonValue* s = root.find("sessions")) {
        if (s->kind != core::JsonValue::Kind::Array) throw core::InputError(source, s->line, "sessions", "expected an array");
        for (const core::JsonValue& e : s->array) {
            if (e.kind != core::JsonValue::Kind::Object) throw core::InputError(source, e.line, "sessions", "expected objects");
            ReaderSession r;
            r.session = sessionNumber(e, 0, source);
            r.date = optionalString(e, "date", source);
            r.method = optionalString(e, "method", source);
            if (const core::JsonValue* sec = e.find("seconds"); sec && sec->kind == core::JsonValue::Kind::Number) r.seconds = sec->number;
            p.sessions.push_back(r);
        }
    }
    if (const core::JsonValue* a = root.find("answers")) {
        if (a->kind != core::JsonValue::Kind::Array) throw core::InputError(source, a->line, "answers", "expected an array");
        for (const core::JsonValue& e : a->array) {
            if (e.kind != core::JsonValue::Kind::Object) throw core::InputError(source, e.line, "answers", "expected objects");
            ReaderAnswer r;
            r.session = sessionNumber(e, 1, source);
            r.stage = member(e, "stage", core::JsonValue::Kind::String, source).string;
            r.method = optionalString(e, "method", source);
            r.expected = member(e, "expected", core::JsonValue::Kind::String, source).string;
            r.answer = member(e, "answer", core::JsonValue::Kind::String, source).string;
            r.correct = member(e, "correct", core::JsonValue::Kind::Bool, source).boolean;
            if (const core::JsonValue* rt = e.find("rt"); rt && rt->kind == core::JsonValue::Kind::Number) r.rt = rt->number;
            if (const core::JsonValue* t = e.find("t"); t && t->kind == core::JsonValue::Kind::Number) r.t = t->number;
            p.answers.push_back(r);
        }
    }
    return p;
}

ReaderProfile loadReaderProfile(const std::string& path)
{
    if (!std::filesystem::exists(path)) return {};
    return parseReaderProfile(core::readWholeFile(path), path);
}

std::string readerProfileToJson(const ReaderProfile& p)
{
    std::string out = "{\n  \"format\": \"armadillo-reader\",\n  \"version\": 1,\n  \"name\": ";
    armadillo::core::appendJsonString(out, p.name);
    out += ",\n  \"sessions\": [";
    for (std::size_t i = 0; i < p.sessions.size(); ++i) {
        const ReaderSession& s = p.sessions[i];
        out += std::string(i ? "," : "") + "\n    {\"session\": " + std::to_string(s.session) + ", \"date\": ";
        armadillo::core::appendJsonString(out, s.date);
        out += ", \"method\": ";
        armadillo::core::appendJsonString(out, s.method);
        out += ", \"seconds\": ";
        core::appendNumber(out, s.seconds, 6);
        out += "}";
    }
    out += "\n  ],\n  \"answers\": [";
    for (std::size_t i = 0; i < p.answers.size(); ++i) {
        const ReaderAnswer& a = p.answers[i];
        out += std::string(i ? "," : "") + "\n    {\"session\": " + std::to_string(a.session) + ", \"stage\": ";
        armadillo::core::appendJsonString(out, a.stage);
        out += ", \"method\": ";
        armadillo::core::appendJsonString(out, a.method);
        out += ", \"expected\": ";
        armadillo::core::appendJsonString(out, a.expected);
        out += ", \"answer\": ";
        armadillo::core::appendJsonString(out, a.answer);
        out += std::string(", \"correct\": ") + (a.correct ? "true" : "false") + ", \"rt\": ";
        if (a.rt >= 0.0) core::appendNumber(out, a.rt, 6);
        else out += "null";
        out += ", \"t\": ";
        if (a.t >= 0.0) core::appendNumber(out, a.t, 6);
        else out += "null";
        out += "}";
    }
    out += "\n  ]\n}\n";
    return out;
}

void saveReaderProfile(const std::string& path, const ReaderProfile& profile) { core::writeFileAtomically(path, readerProfileToJson(profile)); }

std::map<std::string, ItemStats> itemStats(const std::vector<ReaderAnswer>& answers, const std::string& stage)
{
    std::map<std::string, ItemStats> out;
    std::map<std::string, std::vector<double>> times;
    for (std::size_t i = 0; i < answers.size(); ++i) {
        const ReaderAnswer& a = answers[i];
        if (!stage.empty() && a.stage != stage) continue;
        ItemStats& s = out[a.expected];
        ++s.seen;
        s.right += a.correct;
        s.lastSeen = static_cast<int>(i);
        s.recent.push_back(a.correct);
        if (s.recent.size() > 5) s.recent.erase(s.recent.begin());
        if (!a.correct) ++s.confusedWith[a.answer];
        if (a.rt >= 0.0) times[a.expected].push_back(a.rt);
    }
    for (auto& [item, t] : times) {
        std::sort(t.begin(), t.end());
        const std::size_t n = t.size();
        out[item].medianRt = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
    }
    return out;
}

} // namespace armadillo::access
