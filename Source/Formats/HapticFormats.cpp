// Haptic formats in and out (docs/FORMATS.md):
//  - multichannel WAV, the convention of Syntacts (Pezent et al., "Syntacts: Open-Source Software
//    and Hardware for Audio-Controlled Haptics", IEEE Transactions on Haptics 2020: each channel of
//    a sound card drives one actuator with its audio signal): channel k → motor k (m1…m9, then
//    m10…m12, INTERFACES.md order), level = 15 × the signal's peak amplitude in each frame;
//  - Apple AHAP ("Representing haptic patterns in AHAP files", Core Haptics documentation):
//    `Pattern` entries `Event` (EventType HapticTransient / HapticContinuous, Time,
//    EventDuration, EventParameters HapticIntensity / HapticSharpness), `Parameter` and
//    `ParameterCurve` (ParameterID HapticIntensityControl, Time, ParameterCurveControlPoints of
//    Time relative to the curve and ParameterValue). Intensity control multiplies the events'
//    intensity (CHHapticDynamicParameter); curves interpolate linearly (CHHapticParameterCurve);
//  - Meta Haptics Studio `.haptic` = the Lofelt data model v1 (github.com/Lofelt/NiceVibrations,
//    core/datamodel/src/v1.rs): version {major 1}, signals.continuous.envelopes.amplitude
//    [{time, amplitude 0..1, emphasis {amplitude, frequency}}], optional frequency envelope.
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Core/Json.h"
#include "Formats/ScoreImport.h"
#include "Formats/ScoreText.h"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace armadillo::formats {

namespace {

constexpr double kFullScale = 15.0;   // level of a full-scale signal / intensity 1

std::string header(const std::string& source, const std::string& what)
{
    std::string t = "armadillo-score 2\n# Imported from " + scoretext::oneLine(std::filesystem::path(source).filename().string()) +
                    " by `armadillo score import` (docs/FORMATS.md, \"" + what + "\").\n";
    std::string title = scoretext::oneLine(std::filesystem::path(source).stem().string());
    t += "title " + (title.empty() ? std::string("imported") : title) + "\nunits seconds\n";
    return t;
}

/// A note line of an imported effect: soft (the file's levels exactly: no jump-start spike).
/// Written 1 µs short: start + duration, added in floating point by the player, must not reach
/// the packet at the end time, which belongs to whatever follows (the next step of a WAV channel,
/// AHAP event or .haptic segment, or a gap).
std::string noteLine(double start, double duration, std::uint16_t motors, double a, double b)
{
    std::string s = scoretext::number(start) + " note m=" + scoretext::motorSet(motors) + " dur=" + scoretext::number(std::max(1e-6, duration - 1e-6)) +
                    " level=" + scoretext::number(std::clamp(a, 0.0, kFullScale), 3);
    if (std::fabs(a - b) > 1e-9) s += "->" + scoretext::number(std::clamp(b, 0.0, kFullScale), 3);
    return s + " start=soft\n";
}

ImportedScore finish(std::string text, const std::string& source, ImportReport report)
{
    ImportedScore out;
    out.text = std::move(text);
    out.report = std::move(report);
    out.score = tactile::parseScore(out.text, source);
    return out;
}

// ---- JSON helpers -------------------------------------------------------------------------

using armadillo::core::JsonValue;

const core::JsonValue& require(const core::JsonValue& object, std::string_view key, core::JsonValue::Kind kind, const std::string& source)
{
    const core::JsonValue* v = object.find(key);
    if (!v) throw core::InputError(source, object.line, std::string(key), "missing");
    if (v->kind != kind)
        throw core::InputError(source, v->line, std::string(key), std::string("must be ") + core::JsonValue::kindName(kind) + ", not " + core::JsonValue::kindName(v->kind));
    return *v;
}

double numberOr(const core::JsonValue& object, std::string_view key, double fallback, const std::string& source)
{
    const core::JsonValue* v = object.find(key);
    if (!v) return fallback;
    if (v->kind != core::JsonValue::Kind::Number || !std::isfinite(v->number))
        throw core::InputError(source, v->line, std::string(key), "must be a number");
    return v->number;
}

// ---- AHAP ---------------------------------------------------------------------------------

/// One source of the intensity control: a dynamic parameter (a constant from its time on) or a
/// curve (linear between its points, held before the first and after the last).
struct Control {
    double start = 0.0;
    std::vector<std::pair<double, double>> points;   ///< absolute time, value
    double at(double t) const noexcept
    {
        if (points.size() == 1 || t <= points.front().first) return points.front().second;
        for (std::size_t i = 1; i < points.size(); ++i)
            if (t <= points[i].first) {
                const auto& [t0, v0] = points[i - 1];
                const auto& [t1, v1] = points[i];
                return t1 > t0 ? v0 + (v1 - v0) * (t - t0) / (t1 - t0) : v1;
            }
        return points.back().second;
    }
};

} // namespace

ImportedScore importTactileWav(const std::string& path, const HapticImportOptions& o)
{
    const core::AudioBuffer audio = core::readWav(path);
    const auto channels = static_cast<int>(audio.channels.size());
    if (channels < 1 || channels > core::kMaxMotors)
        throw core::InputError(path, 0, "channels", std::to_string(channels) + " channels: a tactile WAV has one channel per motor (9 or 12, at most 16)");
    if (!(o.frameSeconds >= 0.001 && o.frameSeconds <= 0.1)) throw core::InputError(path, 0, "frame", "the frame must be 1..100 ms");
    // Frames of exactly frameSeconds; the peak of frame f is taken over the samples inside
    // [f·T, (f+1)·T) at least half a sample from its edges, so a level that changes right at an
    // edge is not smeared into the neighbouring frame whatever the rounding of the sample times.
    const double frameSeconds = o.frameSeconds;
    const double perFrame = frameSeconds * audio.sampleRate;
    if (perFrame < 4.0) throw core::InputError(path, 0, "frame", "a frame of fewer than 4 samples at this sample rate");
    const auto frames = static_cast<std::size_t>(std::ceil(static_cast<double>(audio.frames()) / perFrame - 1e-9));
    if (frames == 0) throw core::InputError(path, 0, "", "no samples");
    ImportReport report;
    report.format = "wav";
    if (channels != 9 && channels != 12)
        report.warnings.push_back(std::to_string(channels) + " channels (the convention is 9 or 12): channel k still drives motor k");
    struct Run {
        double start;
        std::size_t frames;
        int level;
        int motor;
    };
    std::vector<Run> runs;
    for (int c = 0; c < channels; ++c) {
        const std::vector<float>& x = audio.channels[static_cast<std::size_t>(c)];
        int current = 0;
        std::size_t from = 0;
        for (std::size_t f = 0; f <= frames; ++f) {
            int level = 0;
            if (f < frames) {
                float peak = 0.0f;
                const auto first = static_cast<std::size_t>(std::ceil(static_cast<double>(f) * perFrame + 0.5 - 1e-9));
                const auto last = static_cast<std::size_t>(std::floor(static_cast<double>(f + 1) * perFrame - 0.5 + 1e-9));
                for (std::size_t i = first; i <= last && i < x.size(); ++i)
                    if (std::isfinite(x[i])) peak = std::max(peak, std::fabs(x[i]));
                level = static_cast<int>(std::lround(std::min(1.0, static_cast<double>(peak)) * kFullScale));
            }
            if (level != current) {
                if (current > 0) runs.push_back({static_cast<double>(from) * frameSeconds, f - from, current, c});
                current = level;
                from = f;
            }
        }
    }
    std::stable_sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.start < b.start; });
    std::string text = header(path, "Multichannel WAV");
    text += "# channel k drives motor k; level = 15 x the peak amplitude of each " + scoretext::number(frameSeconds * 1e3, 3) + " ms frame.\n";
    for (const Run& r : runs) {
        // (noteLine writes it 1 µs short; the frame times themselves are written exactly.)
        text += noteLine(r.start, static_cast<double>(r.frames) * frameSeconds, static_cast<std::uint16_t>(1u << r.motor), r.level, r.level);
        ++report.notes;
    }
    text += "length " + scoretext::lengthNumber(static_cast<double>(frames) * frameSeconds) + "\n";
    return finish(std::move(text), path, std::move(report));
}

ImportedScore importAhap(std::string_view json, const std::string& source, const HapticImportOptions& o)
{
    const core::JsonValue root = armadillo::core::parseJson(json, source);
    if (root.kind != core::JsonValue::Kind::Object) throw core::InputError(source, root.line, "", "an AHAP file is a JSON object with a \"Pattern\" array");
    const core::JsonValue& pattern = require(root, "Pattern", core::JsonValue::Kind::Array, source);
    if (o.motors == 0) throw core::InputError(source, 0, "motors", "no motors for the actuator");
    ImportReport report;
    report.format = "ahap";
    struct Event {
        double time, duration, intensity;
        bool transient;
    };
    std::vector<Event> events;
    std::vector<Control> controls;
    int ignored = 0;
    for (const core::JsonValue& entry : pattern.array) {
        if (entry.kind != core::JsonValue::Kind::Object) throw core::InputError(source, entry.line, "Pattern", "each entry is an object");
        if (const core::JsonValue* ev = entry.find("Event")) {
            if (ev->kind != core::JsonValue::Kind::Object) throw core::InputError(source, ev->line, "Event", "must be an object");
            const std::string& type = require(*ev, "EventType", core::JsonValue::Kind::String, source).string;
            const double time = numberOr(*ev, "Time", 0.0, source);
            if (time < 0.0) throw core::InputError(source, ev->line, "Time", "negative");
            if (type != "HapticTransient" && type != "HapticContinuous") {
                if (type != "AudioContinuous" && type != "AudioCustom") throw core::InputError(source, ev->line, "EventType", "unknown event type '" + type + "'");
                ++ignored;   // sound: not ours to feel
                continue;
            }
            double intensity = 1.0;
            if (const core::JsonValue* params = ev->find("EventParameters")) {
                if (params->kind != core::JsonValue::Kind::Array) throw core::InputError(source, params->line, "EventParameters", "must be an array");
                for (const core::JsonValue& p : params->array) {
                    if (p.kind != core::JsonValue::Kind::Object) throw core::InputError(source, p.line, "EventParameters", "each parameter is an object");
                    const std::string& id = require(p, "ParameterID", core::JsonValue::Kind::String, source).string;
                    const double value = numberOr(p, "ParameterValue", 0.0, source);
                    if (id == "HapticIntensity") intensity = std::clamp(value, 0.0, 1.0);   // out of range: clamped, as Core Haptics does
                }
            }
            const bool transient = type == "HapticTransient";
            double duration = o.transientSeconds;
            if (!transient) {
                duration = numberOr(*ev, "EventDuration", -1.0, source);
                if (!(duration > 0.0)) throw core::InputError(source, ev->line, "EventDuration", "a continuous event needs a duration > 0");
            }
            events.push_back({time, duration, intensity, transient});
        } else if (const core::JsonValue* pc = entry.find("ParameterCurve")) {
            if (pc->kind != core::JsonValue::Kind::Object) throw core::InputError(source, pc->line, "ParameterCurve", "must be an object");
            const std::string& id = require(*pc, "ParameterID", core::JsonValue::Kind::String, source).string;
            const double start = numberOr(*pc, "Time", 0.0, source);
            const core::JsonValue& points = require(*pc, "ParameterCurveControlPoints", core::JsonValue::Kind::Array, source);
            if (id != "HapticIntensityControl") {
                ++ignored;
                continue;
            }
            Control c;
            c.start = start;
            for (const core::JsonValue& p : points.array) {
                if (p.kind != core::JsonValue::Kind::Object) throw core::InputError(source, p.line, "ParameterCurveControlPoints", "each point is an object");
                const double t = start + numberOr(p, "Time", 0.0, source);
                if (!c.points.empty() && t < c.points.back().first) throw core::InputError(source, p.line, "Time", "control points go back in time");
                c.points.emplace_back(t, std::clamp(numberOr(p, "ParameterValue", 1.0, source), 0.0, 1.0));
            }
            if (c.points.empty()) throw core::InputError(source, points.line, "ParameterCurveControlPoints", "a curve needs at least one point");
            controls.push_back(std::move(c));
        } else if (const core::JsonValue* pa = entry.find("Parameter")) {
            if (pa->kind != core::JsonValue::Kind::Object) throw core::InputError(source, pa->line, "Parameter", "must be an object");
            const std::string& id = require(*pa, "ParameterID", core::JsonValue::Kind::String, source).string;
            if (id != "HapticIntensityControl") {
                ++ignored;
                continue;
            }
            Control c;
            c.start = numberOr(*pa, "Time", 0.0, source);
            c.points.emplace_back(c.start, std::clamp(numberOr(*pa, "ParameterValue", 1.0, source), 0.0, 1.0));
            controls.push_back(std::move(c));
        } else {
            throw core::InputError(source, entry.line, "Pattern", "an entry is an Event, a Parameter or a ParameterCurve");
        }
    }
    if (events.empty()) throw core::InputError(source, root.line, "Pattern", "no haptic events");
    std::stable_sort(controls.begin(), controls.end(), [](const Control& a, const Control& b) { return a.start < b.start; });
    // The intensity control at t: the latest control started at or before t (1 before any).
    const auto controlIndex = [&](double t) {
        int k = -1;
        for (std::size_t i = 0; i < controls.size(); ++i)
            if (controls[i].start <= t) k = static_cast<int>(i);
        return k;
    };
    std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
    std::string text = header(source, "AHAP");
    text += "# one actuator -> motors " + scoretext::motorSet(o.motors) +
            "; level = 15 x HapticIntensity x HapticIntensityControl; sharpness is not felt on an ERM motor.\n";
    for (const Event& e : events) {
        if (e.transient) {
            const int k = controlIndex(e.time);
            const double c = k < 0 ? 1.0 : controls[static_cast<std::size_t>(k)].at(e.time);
            const double level = kFullScale * std::clamp(e.intensity * c, 0.0, 1.0);
            if (level > 0.0) {
                text += noteLine(e.time, e.duration, o.motors, level, level);
                ++report.notes;
            }
            continue;
        }
        // Breakpoints: the event's ends, every control's start and every curve point inside.
        std::vector<double> cuts {e.time, e.time + e.duration};
        for (const Control& c : controls) {
            cuts.push_back(c.start);
            for (const auto& p : c.points) cuts.push_back(p.first);
        }
        std::sort(cuts.begin(), cuts.end());
        cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            const double a = cuts[i], b = cuts[i + 1];
            if (a < e.time || b > e.time + e.duration || !(b > a)) continue;
            const int k = controlIndex(a);   // constant over [a, b): every start is a cut
            const double ca = k < 0 ? 1.0 : controls[static_cast<std::size_t>(k)].at(a);
            const double cb = k < 0 ? 1.0 : controls[static_cast<std::size_t>(k)].at(b);
            const double la = kFullScale * std::clamp(e.intensity * ca, 0.0, 1.0), lb = kFullScale * std::clamp(e.intensity * cb, 0.0, 1.0);
            if (la <= 0.0 && lb <= 0.0) continue;
            text += noteLine(a, b - a, o.motors, la, lb);
            ++report.notes;
        }
    }
    if (ignored > 0) report.warnings.push_back(std::to_string(ignored) + " audio events or non-intensity parameters ignored");
    return finish(std::move(text), source, std::move(report));
}

ImportedScore importMetaHaptic(std::string_view json, const std::string& source, const HapticImportOptions& o)
{
    const core::JsonValue root = armadillo::core::parseJson(json, source);
    if (root.kind != core::JsonValue::Kind::Object) throw core::InputError(source, root.line, "", "a .haptic file is a JSON object");
    const core::JsonValue& version = require(root, "version", core::JsonValue::Kind::Object, source);
    const double major = numberOr(version, "major", -1.0, source);
    if (major != 1.0) throw core::InputError(source, version.line, "version", "only version 1 of the .haptic data model is known");
    const core::JsonValue& envelopes = require(require(require(root, "signals", core::JsonValue::Kind::Object, source), "continuous", core::JsonValue::Kind::Object, source),
                                         "envelopes", core::JsonValue::Kind::Object, source);
    const core::JsonValue& amplitude = require(envelopes, "amplitude", core::JsonValue::Kind::Array, source);
    if (amplitude.array.empty()) throw core::InputError(source, amplitude.line, "amplitude", "the amplitude envelope is empty");
    if (o.motors == 0) throw core::InputError(source, 0, "motors", "no motors for the actuator");
    struct Point {
        double time, amplitude, emphasis;   // emphasis < 0: none
    };
    std::vector<Point> points;
    for (const core::JsonValue& p : amplitude.array) {
        if (p.kind != core::JsonValue::Kind::Object) throw core::InputError(source, p.line, "amplitude", "each breakpoint is an object");
        const double t = require(p, "time", core::JsonValue::Kind::Number, source).number;
        const double a = require(p, "amplitude", core::JsonValue::Kind::Number, source).number;
        if (!(a >= 0.0 && a <= 1.0)) throw core::InputError(source, p.line, "amplitude", "out of 0..1");
        if (!(t >= 0.0) || (!points.empty() && t < points.back().time)) throw core::InputError(source, p.line, "time", "breakpoint times must not decrease");
        double emphasis = -1.0;
        if (const core::JsonValue* e = p.find("emphasis")) {
            if (e->kind != core::JsonValue::Kind::Object) throw core::InputError(source, e->line, "emphasis", "must be an object");
            emphasis = require(*e, "amplitude", core::JsonValue::Kind::Number, source).number;
            if (!(emphasis >= 0.0 && emphasis <= 1.0)) throw core::InputError(source, e->line, "emphasis", "amplitude out of 0..1");
            if (emphasis < a) throw core::InputError(source, e->line, "emphasis", "the emphasis amplitude is below the breakpoint's");
        }
        points.push_back({t, a, emphasis});
    }
    ImportReport report;
    report.format = "haptic";
    if (envelopes.find("frequency")) report.warnings.push_back("the frequency envelope is not felt on an ERM motor (dropped)");
    std::string text = header(source, "Meta .haptic");
    text += "# one actuator -> motors " + scoretext::motorSet(o.motors) + "; level = 15 x amplitude; emphasis held " +
            scoretext::number(o.emphasisSeconds * 1e3, 3) + " ms at 15 x its amplitude.\n";
    struct Line {
        double time;
        std::string text;
    };
    std::vector<Line> lines;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const Point &a = points[i], &b = points[i + 1];
        if (!(b.time > a.time) || (a.amplitude <= 0.0 && b.amplitude <= 0.0)) continue;
        lines.push_back({a.time, noteLine(a.time, b.time - a.time, o.motors, kFullScale * a.amplitude, kFullScale * b.amplitude)});
        ++report.notes;
    }
    for (const Point& p : points)
        if (p.emphasis > 0.0) {
            lines.push_back({p.time, noteLine(p.time, o.emphasisSeconds, o.motors, kFullScale * p.emphasis, kFullScale * p.emphasis)});
            ++report.notes;
        }
    std::stable_sort(lines.begin(), lines.end(), [](const Line& x, const Line& y) { return x.time < y.time; });
    for (const Line& l : lines) text += l.text;
    if (report.notes == 0) throw core::InputError(source, amplitude.line, "amplitude", "nothing to feel (every amplitude is 0)");
    return finish(std::move(text), source, std::move(report));
}

void writeTactileWav(const std::string& path, const std::vector<core::TactileRow>& rows, int motors, double sampleRate, double carrierHz, bool float32)
{
    if (motors < 1 || motors > core::kMaxMotors) throw core::InputError(path, 0, "motors", "1..16 motors");
    if (!(carrierHz > 0.0 && carrierHz < sampleRate / 2.0)) throw core::InputError(path, 0, "carrier", "the carrier must lie below half the sample rate");
    // The file's carrier is a plain sine of the level's amplitude: the voice-coil model.
    tactors::TactorParams params;
    params.model = tactors::TactorModel::VoiceCoil;
    params.voiceCoilHz = carrierHz;
    writeTactileWav(path, rows, params, tactors::ChannelMap::identity(motors), tactors::TactorGains {}, sampleRate, float32);
}

void writeTactileWav(const std::string& path, const std::vector<core::TactileRow>& rows, const tactors::TactorParams& params,
                     const tactors::ChannelMap& map, const tactors::TactorGains& gains, double sampleRate, bool float32,
                     const std::vector<float>* sound)
{
    // The live tactor output's renderer, fed row by row (one code path: Tests/Tactors compares them).
    tactors::TactorRenderer renderer;
    renderer.prepare(params, map, gains, sampleRate);
    writeWav(path, tactors::renderTactileRows(rows, renderer, sound), float32);
}

// ---- out: AHAP and .haptic ---------------------------------------------------------------

std::vector<ActuatorRun> actuatorRuns(const std::vector<core::TactileRow>& rows, std::uint16_t motors)
{
    std::vector<ActuatorRun> runs;
    if (rows.empty()) return runs;
    const double t0 = rows.front().t;
    const auto levelAt = [&](std::size_t i) {
        int l = 0;
        for (int m = 0; m < core::kMaxMotors; ++m)
            if (motors & (1u << m)) l = std::max(l, static_cast<int>(rows[i].levels[static_cast<std::size_t>(m)]));
        return std::min(l, static_cast<int>(kFullScale));
    };
    int current = 0;
    double from = 0.0;
    for (std::size_t i = 0; i <= rows.size(); ++i) {
        // Past the last row: its level ends 5 ms later (the packet period) unless it is all-off.
        const double t = i < rows.size() ? rows[i].t - t0 : rows.back().t - t0 + 0.005;
        const int level = i < rows.size() ? levelAt(i) : 0;
        if (level == current) continue;
        if (current > 0 && t > from) runs.push_back({from, t - from, current});
        current = level;
        from = t;
    }
    return runs;
}

namespace {
std::string jsonNumber(double v) { return scoretext::number(v, 6); }
} // namespace

std::string exportAhap(const std::vector<core::TactileRow>& rows, std::uint16_t motors, const std::string& project)
{
    constexpr double kMaxContinuous = 30.0;   // Core Haptics: a continuous event lasts at most 30 s
    std::string s = "{\n  \"Version\": 1.0,\n  \"Metadata\": {\"Project\": ";
    armadillo::core::appendJsonString(s, project);
    s += ", \"Description\": ";
    armadillo::core::appendJsonString(s, "ARMadillo motors " + scoretext::motorSet(motors) + " as one actuator: level = 15 x HapticIntensity (docs/FORMATS.md)");
    s += "},\n  \"Pattern\": [";
    bool first = true;
    for (const ActuatorRun& r : actuatorRuns(rows, motors)) {
        for (double a = 0.0; a < r.duration - 1e-9; a += kMaxContinuous) {
            const double d = std::min(kMaxContinuous, r.duration - a);
            s += first ? "\n" : ",\n";
            first = false;
            s += "    {\"Event\": {\"Time\": " + jsonNumber(r.start + a) + ", \"EventType\": \"HapticContinuous\", \"EventDuration\": " +
                 jsonNumber(d) + ", \"EventParameters\": [{\"ParameterID\": \"HapticIntensity\", \"ParameterValue\": " +
                 jsonNumber(r.level / kFullScale) + "}]}}";
        }
    }
    return s + "\n  ]\n}\n";
}

std::string exportMetaHaptic(const std::vector<core::TactileRow>& rows, std::uint16_t motors, const std::string& project)
{
    // Steps: the envelope is linear between breakpoints, so each change of level is two
    // breakpoints at the same time (v1.rs allows equal times: only a decreasing time is invalid).
    std::vector<std::pair<double, double>> points {{0.0, 0.0}};
    for (const ActuatorRun& r : actuatorRuns(rows, motors)) {
        const double a = r.level / kFullScale;
        if (r.start > points.back().first) {   // a gap: down to 0 where the last run ended, 0 until this one
            if (points.back().second != 0.0) points.emplace_back(points.back().first, 0.0);
            points.emplace_back(r.start, 0.0);
        }
        points.emplace_back(r.start, a);
        points.emplace_back(r.start + r.duration, a);
    }
    if (points.back().second != 0.0) points.emplace_back(points.back().first, 0.0);
    std::string s = "{\n  \"version\": {\"major\": 1, \"minor\": 0, \"patch\": 0},\n  \"metadata\": {\"editor\": \"armadillo\", \"project\": ";
    armadillo::core::appendJsonString(s, project);
    s += ", \"description\": ";
    armadillo::core::appendJsonString(s, "ARMadillo motors " + scoretext::motorSet(motors) + " as one actuator: level = 15 x amplitude (docs/FORMATS.md)");
    s += "},\n  \"signals\": {\"continuous\": {\"envelopes\": {\"amplitude\": [";
    for (std::size_t i = 0; i < points.size(); ++i)
        s += std::string(i ? ",\n" : "\n") + "    {\"time\": " + jsonNumber(points[i].first) + ", \"amplitude\": " + jsonNumber(points[i].second) + "}";
    return s + "\n  ]}}}\n}\n";
}

namespace {
std::string lowerExtension(const std::string& path)
{
    std::string e = std::filesystem::path(path).extension().string();
    for (char& c : e) c = static_cast<char>((c >= 'A' && c <= 'Z') ? c - 'A' + 'a' : c);
    return e;
}
std::string readText(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw core::IoError("cannot read " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}
} // namespace

bool isImportableScorePath(const std::string& path) noexcept
{
    const std::string e = lowerExtension(path);
    return e == ".mid" || e == ".midi" || e == ".wav" || e == ".ahap" || e == ".haptic" || e == ".tact" || e == ".hjif";
}

ImportedScore importScoreFile(const std::string& path, const MidiImportOptions& midi, const HapticImportOptions& haptic)
{
    const std::string e = lowerExtension(path);
    if (!std::filesystem::exists(path)) throw core::InputError(path, 0, "", "no such file");
    if (e == ".mid" || e == ".midi") return importMidi(readMidiFile(path), midi, path);
    if (e == ".wav") return importTactileWav(path, haptic);
    if (e == ".ahap") return importAhap(readText(path), path, haptic);
    if (e == ".haptic") return importMetaHaptic(readText(path), path, haptic);
    if (e == ".tact") return importTact(readText(path), path, haptic);
    if (e == ".hjif") return importHjif(readText(path), path, haptic);
    if (e == ".score") {
        ImportedScore s;
        s.text = readText(path);
        s.score = tactile::parseScore(s.text, path);
        s.report.format = "score";
        s.report.notes = static_cast<int>(s.score.notes.size());
        return s;
    }
    throw core::InputError(path, 0, "", "unknown score format '" + e + "' (known: .score .mid .midi .wav .ahap .haptic .tact .hjif)");
}

tactile::Score loadAnyScore(const std::string& path) { return importScoreFile(path).score; }

} // namespace armadillo::formats
