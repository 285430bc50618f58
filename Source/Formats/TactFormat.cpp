// bHaptics `.tact` (bHaptics Designer's export) in and out, for the forearm device (Tactosy:
// ForearmL / ForearmR, six motors in a 3 × 2 grid). bHaptics publishes no definition of the
// format; docs/FORMATS.md ("bHaptics .tact") lists every public file this reading is taken from
// and says which parts are an interpretation. In short:
//  - structure, from bHaptics' own sample files (github.com/bhaptics/tact-python `CenterX.tact`;
//    github.com/bhaptics/TactUnrealEngine4 `Content/HapticsManager/Feedback/PistolFire_Left.tact`)
//    and the Tactosy2 forearm layout as a third-party reader documents it: a JSON object whose
//    `project` holds `tracks[]` {enable, effects[]}; an effect {name, startTime, offsetTime (its
//    length), modes{<device>: {mode DOT_MODE|PATH_MODE, dotMode.feedback[{startTime, endTime,
//    playbackType, pointList[{index, intensity}]}], pathMode.feedback[{movingPattern,
//    playbackType, visible, pointList[{time, x, y, intensity}]}]}}}; times in ms, intensity 0..1
//    (older files write numbers as strings: "1.000"); the forearm layout: index i at
//    x = (i mod 3)/2, y = ⌊i/3⌋;
//  - interpretation (ours, documented): level = 15 × intensity; fades linear; a path point spread
//    bilinearly over the 3 × 3 grid; overlapping effects on one motor: the louder.
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Formats/ScoreImport.h"
#include "Formats/ScoreText.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>

namespace armadillo::formats {

namespace {

using armadillo::core::JsonValue;
constexpr double kFullScale = 15.0;

/// A number, or a string holding one (the Designer's older exports write "1.000").
double tactNumber(const core::JsonValue& object, std::string_view key, const std::string& source, const double* fallback = nullptr)
{
    const core::JsonValue* v = object.find(key);
    if (!v) {
        if (fallback) return *fallback;
        throw core::InputError(source, object.line, std::string(key), "missing");
    }
    double x = 0.0;
    if (v->kind == core::JsonValue::Kind::Number) {
        x = v->number;
    } else if (v->kind == core::JsonValue::Kind::String) {
        std::size_t used = 0;
        try {
            x = std::stod(v->string, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != v->string.size()) throw core::InputError(source, v->line, std::string(key), "'" + v->string + "' is not a number");
    } else {
        throw core::InputError(source, v->line, std::string(key), std::string("must be a number, not ") + core::JsonValue::kindName(v->kind));
    }
    if (!std::isfinite(x)) throw core::InputError(source, v->line, std::string(key), "must be a finite number");
    return x;
}

const core::JsonValue& member(const core::JsonValue& object, std::string_view key, core::JsonValue::Kind kind, const std::string& source)
{
    const core::JsonValue* v = object.find(key);
    if (!v) throw core::InputError(source, object.line, std::string(key), "missing");
    if (v->kind != kind)
        throw core::InputError(source, v->line, std::string(key), std::string("must be ") + core::JsonValue::kindName(kind) + ", not " + core::JsonValue::kindName(v->kind));
    return *v;
}

constexpr double kMaxMillis = 3600.0 * 1000.0;   // an effect file's times: at most an hour
constexpr std::size_t kMaxOverlap = 256;         // pieces sounding at once on one motor

/// A time in ms (0 .. one hour), in seconds.
double seconds(const core::JsonValue& object, std::string_view key, const std::string& source, bool optional = false)
{
    const double zero = 0.0;
    const double ms = tactNumber(object, key, source, optional ? &zero : nullptr);
    if (ms < 0.0 || ms > kMaxMillis) throw core::InputError(source, object.line, std::string(key), "a time in ms must lie in 0..3600000 (one hour)");
    return ms / 1000.0;
}

double intensityOf(const core::JsonValue& point, const std::string& source)
{
    const double i = tactNumber(point, "intensity", source);
    if (i < 0.0 || i > 1.0) throw core::InputError(source, point.line, "intensity", "out of 0..1 (a .tact intensity is a fraction of full strength)");
    return i;
}

/// One motor's level, linear from `a` at `start` to `b` at `end` (s).
struct Piece {
    int motor;
    double start, end, a, b;
    double at(double t) const noexcept { return end > start ? a + (b - a) * (t - start) / (end - start) : a; }
};

/// The fade of a playbackType at fraction u of the feedback (0..1): linear (our reading).
double fade(const std::string& type, double u) noexcept
{
    u = std::clamp(u, 0.0, 1.0);
    if (type == "FADE_IN") return u;
    if (type == "FADE_OUT") return 1.0 - u;
    if (type == "FADE_IN_OUT") return u <= 0.5 ? 2.0 * u : 2.0 * (1.0 - u);
    return 1.0;
}

void checkPlayback(const core::JsonValue& fb, const std::string& source, std::string& type)
{
    type = "NONE";
    if (const core::JsonValue* p = fb.find("playbackType")) {
        if (p->kind != core::JsonValue::Kind::String) throw core::InputError(source, p->line, "playbackType", "must be a string");
        type = p->string;
    }
    if (type != "NONE" && type != "FADE_IN" && type != "FADE_OUT" && type != "FADE_IN_OUT")
        throw core::InputError(source, fb.line, "playbackType", "'" + type + "' is not NONE, FADE_IN, FADE_OUT or FADE_IN_OUT");
}

/// Our motor index (right-arm layout, row 0 = wrist, column 0 = left) at grid position
/// (column c, row r), both 0..2.
int motorAt(int row, int column) noexcept { return 3 * row + column; }

/// The bilinear weights of a path point at (x, y) in the device's unit square on our 3 × 3:
/// column = 2x, row = 2y, the four surrounding motors weighted by their nearness.
std::array<double, 9> spread(double x, double y) noexcept
{
    std::array<double, 9> w {};
    const double c = 2.0 * std::clamp(x, 0.0, 1.0), r = 2.0 * std::clamp(y, 0.0, 1.0);
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) {
            const double wc = std::max(0.0, 1.0 - std::fabs(c - col)), wr = std::max(0.0, 1.0 - std::fabs(r - row));
            w[static_cast<std::size_t>(motorAt(row, col))] = wc * wr;
        }
    return w;
}

/// Whether a device's selected mode has anything to play.
bool hasContent(const core::JsonValue& mode)
{
    const core::JsonValue* m = mode.find("mode");
    if (!m || m->kind != core::JsonValue::Kind::String) return false;
    const char* key = m->string == "PATH_MODE" ? "pathMode" : "dotMode";
    const core::JsonValue* sub = mode.find(key);
    const core::JsonValue* feedback = sub && sub->kind == core::JsonValue::Kind::Object ? sub->find("feedback") : nullptr;
    if (!feedback || feedback->kind != core::JsonValue::Kind::Array) return false;
    for (const core::JsonValue& fb : feedback->array) {
        const core::JsonValue* points = fb.kind == core::JsonValue::Kind::Object ? fb.find("pointList") : nullptr;
        if (points && points->kind == core::JsonValue::Kind::Array && !points->array.empty()) return true;
    }
    return false;
}

/// Which device: the one asked for, else the forearm that has something to play (ForearmR when
/// both do). The other devices with content are named in the report's warnings.
std::string chooseTactDevice(const core::JsonValue& project, const core::JsonValue& tracks, const HapticImportOptions& o, const std::string& source,
                             ImportReport& report)
{
    std::map<std::string, int> contentByDevice;   // device name → effects with content
    for (const core::JsonValue& track : tracks.array) {
        if (track.kind != core::JsonValue::Kind::Object) throw core::InputError(source, track.line, "tracks", "each track is an object");
        const core::JsonValue* effects = track.find("effects");
        if (!effects) continue;
        if (effects->kind != core::JsonValue::Kind::Array) throw core::InputError(source, effects->line, "effects", "must be an array");
        for (const core::JsonValue& effect : effects->array) {
            if (effect.kind != core::JsonValue::Kind::Object) throw core::InputError(source, effect.line, "effects", "each effect is an object");
            const core::JsonValue& modes = member(effect, "modes", core::JsonValue::Kind::Object, source);
            for (const auto& [name, mode] : modes.object)
                if (mode.kind == core::JsonValue::Kind::Object && hasContent(mode)) ++contentByDevice[name];
        }
    }
    std::string deviceName = o.tactDevice;
    if (!deviceName.empty() && deviceName != "ForearmL" && deviceName != "ForearmR")
        throw core::InputError(source, 0, "device", "'" + deviceName + "' is not a forearm device (ForearmL or ForearmR)");
    if (deviceName.empty()) deviceName = contentByDevice.count("ForearmR") ? "ForearmR" : contentByDevice.count("ForearmL") ? "ForearmL" : "";
    if (deviceName.empty() || !contentByDevice.count(deviceName)) {
        std::string others;
        for (const auto& [name, n] : contentByDevice) others += (others.empty() ? "" : ", ") + name;
        throw core::InputError(source, project.line, "modes",
                         "nothing to feel on " + (deviceName.empty() ? std::string("ForearmL or ForearmR") : deviceName) +
                             (others.empty() ? std::string(" (no device has any points)") : " (the file plays on: " + others + ")") +
                             ": only the forearm (Tactosy) layout maps onto the arm");
    }
    for (const auto& [name, n] : contentByDevice)
        if (name != deviceName)
            report.warnings.push_back(name + " (" + std::to_string(n) + " effects) left out: " +
                                      (name == "ForearmL" || name == "ForearmR" ? "choose it with --device " + name : "not the forearm layout"));
    return deviceName;
}

/// One effect's device mode as pieces: where it starts, how long it may run, and which columns
/// are mirrored (ForearmL in the right-arm layout).
struct TactEffect {
    const core::JsonValue* mode = nullptr;
    double start = 0.0, limit = 1e9, length = 0.0;
    bool mirror = false;
};

/// DOT_MODE: each point a motor, with the feedback's fade.
void dotPieces(const TactEffect& effect, const std::string& source, std::vector<Piece>& pieces, int& clipped)
{
    const core::JsonValue* mode = effect.mode;
    const double start = effect.start, limit = effect.limit;
    const bool mirror = effect.mirror;
    const core::JsonValue& feedback = member(member(*mode, "dotMode", core::JsonValue::Kind::Object, source), "feedback", core::JsonValue::Kind::Array, source);
    for (const core::JsonValue& fb : feedback.array) {
        if (fb.kind != core::JsonValue::Kind::Object) throw core::InputError(source, fb.line, "feedback", "each feedback is an object");
        std::string playback;
        checkPlayback(fb, source, playback);
        const double s = seconds(fb, "startTime", source);
        double e = seconds(fb, "endTime", source);
        if (e < s) throw core::InputError(source, fb.line, "endTime", "a feedback ends before it starts");
        const double fullEnd = e;
        if (e > limit) {
            e = limit;
            ++clipped;
        }
        if (!(e > s)) continue;
        for (const core::JsonValue& p : member(fb, "pointList", core::JsonValue::Kind::Array, source).array) {
            if (p.kind != core::JsonValue::Kind::Object) throw core::InputError(source, p.line, "pointList", "each point is an object");
            const double index = tactNumber(p, "index", source);
            if (index != std::floor(index) || index < 0.0 || index > 5.0)
                throw core::InputError(source, p.line, "index", "a forearm motor index is 0..5 (three across, two rows)");
            const int i = static_cast<int>(index);
            const int col = mirror ? 2 - i % 3 : i % 3;
            const int motor = motorAt(i < 3 ? 0 : 2, col);
            const double level = kFullScale * intensityOf(p, source);
            // A fade over the whole feedback [s, fullEnd]: one piece per linear part.
            std::vector<double> cuts {s, e};
            if (playback == "FADE_IN_OUT" && 0.5 * (s + fullEnd) < e) cuts.insert(cuts.begin() + 1, 0.5 * (s + fullEnd));
            for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
                const double ua = (cuts[k] - s) / (fullEnd - s), ub = (cuts[k + 1] - s) / (fullEnd - s);
                pieces.push_back({motor, start + cuts[k], start + cuts[k + 1], level * fade(playback, ua), level * fade(playback, ub)});
            }
        }
    }
}

/// PATH_MODE: a moving point spread bilinearly over the grid, sampled every tactPathStep.
void pathPieces(const TactEffect& effect, const std::string& source, const HapticImportOptions& o, std::vector<Piece>& pieces, int& clipped)
{
    const core::JsonValue* mode = effect.mode;
    const double start = effect.start, limit = effect.limit, length = effect.length;
    const bool mirror = effect.mirror;
    const core::JsonValue& feedback = member(member(*mode, "pathMode", core::JsonValue::Kind::Object, source), "feedback", core::JsonValue::Kind::Array, source);
    for (const core::JsonValue& fb : feedback.array) {
        if (fb.kind != core::JsonValue::Kind::Object) throw core::InputError(source, fb.line, "feedback", "each feedback is an object");
        std::string playback;
        checkPlayback(fb, source, playback);
        struct Key {
            double t, x, y, intensity;
        };
        std::vector<Key> keys;
        for (const core::JsonValue& p : member(fb, "pointList", core::JsonValue::Kind::Array, source).array) {
            if (p.kind != core::JsonValue::Kind::Object) throw core::InputError(source, p.line, "pointList", "each point is an object");
            Key k {seconds(p, "time", source), tactNumber(p, "x", source), tactNumber(p, "y", source), intensityOf(p, source)};
            if (k.x < 0.0 || k.x > 1.0 || k.y < 0.0 || k.y > 1.0) throw core::InputError(source, p.line, "x", "a path point lies in 0..1 × 0..1");
            if (!keys.empty() && k.t < keys.back().t) throw core::InputError(source, p.line, "time", "path point times must not decrease");
            if (mirror) k.x = 1.0 - k.x;
            keys.push_back(k);
        }
        if (keys.empty()) continue;
        if (keys.size() == 1) keys.push_back({std::max(keys[0].t, length), keys[0].x, keys[0].y, keys[0].intensity});   // held to the effect's end
        const double t0 = keys.front().t, t1 = keys.back().t;
        const auto sample = [&](double t) {   // position and intensity × fade at t (between keys: linear)
            std::size_t j = 1;
            while (j + 1 < keys.size() && keys[j].t < t) ++j;
            const Key &a = keys[j - 1], &b = keys[j];
            const double u = b.t > a.t ? std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0) : 1.0;
            const double f = fade(playback, t1 > t0 ? (t - t0) / (t1 - t0) : 0.0);
            return Key {t, a.x + (b.x - a.x) * u, a.y + (b.y - a.y) * u, (a.intensity + (b.intensity - a.intensity) * u) * f};
        };
        for (std::size_t j = 0; j + 1 < keys.size(); ++j) {
            const double a = keys[j].t, b = std::min(keys[j + 1].t, limit);
            if (keys[j + 1].t > limit) ++clipped;
            if (!(b > a)) continue;
            const int steps = std::max(1, static_cast<int>(std::ceil((b - a) / o.tactPathStep - 1e-9)));
            for (int k = 0; k < steps; ++k) {
                const double ta = a + (b - a) * k / steps, tb = a + (b - a) * (k + 1) / steps;
                Key ka = sample(ta), kb = sample(tb);
                if (j + 1 < keys.size() && k + 1 == steps && tb == keys[j + 1].t) kb = Key {tb, keys[j + 1].x, keys[j + 1].y, keys[j + 1].intensity * fade(playback, t1 > t0 ? (tb - t0) / (t1 - t0) : 0.0)};
                if (k == 0) ka = Key {ta, keys[j].x, keys[j].y, keys[j].intensity * fade(playback, t1 > t0 ? (ta - t0) / (t1 - t0) : 0.0)};
                const auto wa = spread(ka.x, ka.y), wb = spread(kb.x, kb.y);
                for (int m = 0; m < 9; ++m) {
                    const double la = kFullScale * ka.intensity * wa[static_cast<std::size_t>(m)], lb = kFullScale * kb.intensity * wb[static_cast<std::size_t>(m)];
                    if (la > 0.0 || lb > 0.0) pieces.push_back({m, start + ta, start + tb, la, lb});
                }
            }
        }
    }
}

/// Per motor: cut at every piece boundary; on each part the louder of the pieces that cover it
/// at each end, joined linearly. The score's note lines in time order, and where the last ends.
struct TactLine {
    double t;
    std::string text;
};
std::vector<TactLine> motorLines(std::vector<Piece>& pieces, const core::JsonValue& project, const std::string& source, ImportReport& report, double& end)
{
    std::vector<TactLine> lines;
    end = 0.0;
    // A sweep over each motor's pieces in time order: the pieces sounding in each part are the
    // active ones (bounded: a file with more than kMaxOverlap at once on a motor is refused).
    std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& x, const Piece& y) { return x.start < y.start; });
    for (int m = 0; m < 9; ++m) {
        std::vector<const Piece*> mine;
        std::vector<double> cuts;
        for (const Piece& p : pieces)
            if (p.motor == m) {
                mine.push_back(&p);
                cuts.push_back(p.start);
                cuts.push_back(p.end);
            }
        std::sort(cuts.begin(), cuts.end());
        cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double x, double y) { return std::fabs(x - y) < 1e-9; }), cuts.end());
        std::vector<const Piece*> active;
        std::size_t next = 0;
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            const double a = cuts[i], b = cuts[i + 1];
            while (next < mine.size() && mine[next]->start <= a + 1e-9) active.push_back(mine[next++]);
            active.erase(std::remove_if(active.begin(), active.end(), [&](const Piece* p) { return p->end < b - 1e-9; }), active.end());
            if (active.size() > kMaxOverlap)
                throw core::InputError(source, project.line, "tracks", "more than " + std::to_string(kMaxOverlap) + " effects at once on one motor");
            double la = 0.0, lb = 0.0;
            for (const Piece* p : active) {
                la = std::max(la, p->at(a));
                lb = std::max(lb, p->at(b));
            }
            if (la <= 0.0 && lb <= 0.0) continue;
            std::string s = scoretext::number(a) + " note m=" + scoretext::motorSet(static_cast<std::uint16_t>(1u << m)) +
                            " dur=" + scoretext::number(std::max(1e-6, b - a - 1e-6)) + " level=" + scoretext::number(std::clamp(la, 0.0, kFullScale), 3);
            if (std::fabs(la - lb) > 1e-9) s += "->" + scoretext::number(std::clamp(lb, 0.0, kFullScale), 3);
            lines.push_back({a, s + " start=soft\n"});
            ++report.notes;
            end = std::max(end, b);
        }
    }
    std::stable_sort(lines.begin(), lines.end(), [](const TactLine& x, const TactLine& y) { return x.t < y.t; });
    return lines;
}

} // namespace

ImportedScore importTact(std::string_view json, const std::string& source, const HapticImportOptions& o)
{
    const core::JsonValue root = armadillo::core::parseJson(json, source);
    if (root.kind != core::JsonValue::Kind::Object) throw core::InputError(source, root.line, "", "a .tact file is a JSON object");
    const core::JsonValue& project = member(root, "project", core::JsonValue::Kind::Object, source);
    const core::JsonValue& tracks = member(project, "tracks", core::JsonValue::Kind::Array, source);
    if (!(o.tactPathStep >= 0.001 && o.tactPathStep <= 0.1)) throw core::InputError(source, 0, "step", "the path step must be 1..100 ms");
    ImportReport report;
    report.format = "tact";
    const std::string deviceName = chooseTactDevice(project, tracks, o, source, report);
    const bool mirror = deviceName == "ForearmL";

    std::vector<Piece> pieces;
    int clipped = 0;
    for (const core::JsonValue& track : tracks.array) {
        if (const core::JsonValue* enable = track.find("enable"); enable && enable->kind == core::JsonValue::Kind::Bool && !enable->boolean) continue;
        const core::JsonValue* effects = track.find("effects");
        if (!effects) continue;
        for (const core::JsonValue& effect : effects->array) {
            TactEffect e;
            e.mode = member(effect, "modes", core::JsonValue::Kind::Object, source).find(deviceName);
            if (!e.mode) continue;
            if (e.mode->kind != core::JsonValue::Kind::Object) throw core::InputError(source, e.mode->line, deviceName, "must be an object");
            e.start = seconds(effect, "startTime", source, true);
            e.length = seconds(effect, "offsetTime", source, true);
            e.limit = e.length > 0.0 ? e.length : 1e9;   // a feedback past the effect's length is cut there
            e.mirror = mirror;
            const std::string& kind = member(*e.mode, "mode", core::JsonValue::Kind::String, source).string;
            if (kind == "DOT_MODE") dotPieces(e, source, pieces, clipped);
            else if (kind == "PATH_MODE") pathPieces(e, source, o, pieces, clipped);
            else throw core::InputError(source, e.mode->line, "mode", "'" + kind + "' is not DOT_MODE or PATH_MODE");
        }
    }
    if (clipped > 0) report.warnings.push_back(std::to_string(clipped) + " feedback parts past their effect's length (offsetTime) cut there");

    std::string text = "armadillo-score 2\n# Imported from " + scoretext::oneLine(std::filesystem::path(source).filename().string()) +
                       " by `armadillo score import` (docs/FORMATS.md, \"bHaptics .tact\").\n";
    const std::string title = scoretext::oneLine(std::filesystem::path(source).stem().string());
    text += "title " + (title.empty() ? std::string("imported") : title) + "\nunits seconds\n";
    text += "# " + deviceName + (mirror ? " (columns mirrored into the right-arm layout)" : "") +
            ": Tactosy row y=0 -> wrist motors 1-3, y=1 -> elbow motors 7-9; level = 15 x intensity; fades linear;"
            " path points spread bilinearly over the 3x3.\n";
    double end = 0.0;
    const std::vector<TactLine> lines = motorLines(pieces, project, source, report, end);
    if (report.notes == 0) throw core::InputError(source, project.line, "tracks", "nothing to feel on " + deviceName + " (every intensity is 0)");
    for (const TactLine& l : lines) text += l.text;
    text += "length " + scoretext::lengthNumber(end) + "\n";
    ImportedScore out;
    out.text = std::move(text);
    out.report = std::move(report);
    out.score = tactile::parseScore(out.text, source);
    return out;
}

std::string exportTact(const std::vector<core::TactileRow>& rows, const std::string& project)
{
    // Runs of one whole packet (motors 1..9): each run with a motor on is one effect in dot mode
    // (wrist and elbow rows: the Tactosy's six motors) and, when a middle-row motor runs, one in
    // path mode (a still point at that motor's place, y = 0.5, which the importer's spread puts
    // on that motor alone).
    std::string effects;
    double total = 0.0;
    if (!rows.empty()) {
        const double t0 = rows.front().t;
        const auto ms = [&](double t) { return static_cast<long>(std::lround((t - t0) * 1000.0)); };
        std::size_t i = 0;
        while (i < rows.size()) {
            std::size_t j = i + 1;
            while (j < rows.size() && std::equal(rows[j].levels.begin(), rows[j].levels.begin() + 9, rows[i].levels.begin())) ++j;
            const double endT = j < rows.size() ? rows[j].t : rows.back().t + 0.005;   // the last row: one packet
            const auto& lv = rows[i].levels;
            const long from = ms(rows[i].t), to = ms(endT);
            total = std::max(total, endT - t0);
            const auto intensity = [&](int m) { return scoretext::number(std::min(15, static_cast<int>(lv[static_cast<std::size_t>(m)])) / kFullScale, 6); };
            std::string dots, paths;
            for (int m = 0; m < 9; ++m) {
                if (lv[static_cast<std::size_t>(m)] == 0) continue;
                const int row = m / 3, col = m % 3;
                if (row != 1) {
                    dots += std::string(dots.empty() ? "" : ",") + "{\"index\":" + std::to_string(row == 0 ? col : 3 + col) + ",\"intensity\":" + intensity(m) + "}";
                } else {
                    const std::string x = scoretext::number(col / 2.0, 3);
                    paths += std::string(paths.empty() ? "" : ",") + "{\"movingPattern\":\"CONST_SPEED\",\"playbackType\":\"NONE\",\"visible\":true,\"pointList\":[" +
                             "{\"time\":0,\"x\":" + x + ",\"y\":0.5,\"intensity\":" + intensity(m) + "},{\"time\":" + std::to_string(to - from) +
                             ",\"x\":" + x + ",\"y\":0.5,\"intensity\":" + intensity(m) + "}]}";
                }
            }
            const auto effect = [&](const std::string& kind, const std::string& dotFeedback, const std::string& pathFeedback) {
                effects += std::string(effects.empty() ? "\n" : ",\n") + "      {\"name\":\"" + std::to_string(from) + " ms\",\"startTime\":" + std::to_string(from) +
                           ",\"offsetTime\":" + std::to_string(to - from) + ",\"modes\":{\"ForearmR\":{\"mode\":\"" + kind + "\",\"dotMode\":{\"dotConnected\":false,\"feedback\":[" +
                           dotFeedback + "]},\"pathMode\":{\"feedback\":[" + pathFeedback + "]}}}}";
            };
            if (to > from) {
                if (!dots.empty())
                    effect("DOT_MODE", "{\"startTime\":0,\"endTime\":" + std::to_string(to - from) + ",\"playbackType\":\"NONE\",\"pointList\":[" + dots + "]}", "");
                if (!paths.empty()) effect("PATH_MODE", "", paths);
            }
            i = j;
        }
    }
    std::string layout;
    for (const char* side : {"ForearmL", "ForearmR"}) {
        layout += std::string(layout.empty() ? "" : ",") + "\"" + side + "\":[";
        for (int i = 0; i < 6; ++i)
            layout += std::string(i ? "," : "") + "{\"index\":" + std::to_string(i) + ",\"x\":" + scoretext::number((i % 3) / 2.0, 3) + ",\"y\":" + std::to_string(i / 3) + "}";
        layout += "]";
    }
    std::string s = "{\n  \"project\": {\n    \"name\": ";
    armadillo::core::appendJsonString(s, project);
    s += ",\n    \"description\": ";
    armadillo::core::appendJsonString(s, "ARMadillo motors as a bHaptics forearm (Tactosy) effect: wrist row = y 0, elbow row = y 1, middle row = path points at y 0.5 (docs/FORMATS.md)");
    s += ",\n    \"layout\": {\"name\":\"Tactosy2\",\"type\":\"Tactosy2\",\"layouts\":{" + layout + "}},\n    \"tracks\": [{\"enable\":true,\"effects\":[" + effects +
         "\n    ]}]\n  },\n  \"durationMillis\": " + std::to_string(std::lround(total * 1000.0)) + ",\n  \"intervalMillis\": 20,\n  \"size\": 20\n}\n";
    return s;
}

} // namespace armadillo::formats
