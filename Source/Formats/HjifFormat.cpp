// MPEG haptics .hjif in and out (Formats/Hjif.h, docs/FORMATS.md "MPEG haptics .hjif").
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Formats/Hjif.h"
#include "Formats/ScoreImport.h"
#include "Formats/ScoreText.h"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

namespace armadillo::formats::hjif {

namespace {

using core::JsonValue;
using Kind = core::JsonValue::Kind;

constexpr double kTransientSeconds = 0.022;   // Band::TRANSIENT_DURATION_MS
constexpr unsigned kMaxTimescale = 48000;      // IOJson::MAX_TIMESCALE_MAIN
constexpr double kMaxSeconds = 3600.0;         // an imported score lasts at most an hour
constexpr int kMaxNesting = 16;                // references / composites inside each other
constexpr double kMaxHz = 100000.0;

/// Walks the JSON once: checks the structure and builds the model. In `collect` mode every
/// problem is listed and the walk goes on; otherwise the first one throws.
class Reader {
public:
    Reader(const std::string& source, bool collect) : source_(source), collect_(collect) {}
    std::vector<Problem> problems;
    File file;

    void read(const JsonValue& root)
    {
        if (root.kind != Kind::Object) return fail(root.line, "", "an .hjif file is a JSON object (version, profile, level, date, description, timescale, perceptions, avatars, syncs)");
        for (const char* k : {"version", "date", "description"}) get(root, k, Kind::String);
        if (const JsonValue* p = get(root, "profile", Kind::String)) {
            profile_ = p->string;
            if (profile_ != "Main" && profile_ != "Simple Parametric") fail(p->line, "profile", "'" + profile_ + "': the profiles are \"Main\" and \"Simple Parametric\"");
        }
        if (const JsonValue* l = get(root, "level", Kind::Number)) {
            if (l->number != 1.0 && l->number != 2.0) fail(l->line, "level", "must be 1 or 2");
            else level_ = static_cast<int>(l->number);
        }
        if (const JsonValue* ts = get(root, "timescale", Kind::Number)) {
            if (!(ts->number >= 1.0 && ts->number <= kMaxTimescale && std::floor(ts->number) == ts->number))
                fail(ts->line, "timescale", scoretext::number(ts->number) + " ticks per second: must be a whole number in 1..48000 (the Main profile's limit)");
            else {
                file.timescale = static_cast<unsigned>(ts->number);
                if (profile_ == "Simple Parametric" && file.timescale != 1000) fail(ts->line, "timescale", "the Simple Parametric profile has timescale 1000");
            }
        }
        if (const JsonValue* a = get(root, "avatars", Kind::Array))
            for (const JsonValue& av : a->array) {
                if (av.kind != Kind::Object) { fail(av.line, "avatars", "each avatar is an object"); continue; }
                get(av, "id", Kind::Number);
                get(av, "lod", Kind::Number);
                get(av, "type", Kind::String);
            }
        get(root, "syncs", Kind::Array);
        if (const JsonValue* ps = get(root, "perceptions", Kind::Array)) {
            std::set<long long> ids;
            // Modality "Other" is felt when nothing in the file is Vibrotactile: the reference's
            // encoder wrote "Other" on the vibration files it converted (its example outputs
            // Evaluation1_1/1_2), and its synthesizer (Synthesizer/src/Helper.cpp) renders every
            // perception whatever its modality.
            otherFelt_ = true;
            for (const JsonValue& p : ps->array)
                if (const JsonValue* m = p.kind == Kind::Object ? p.find("perception_modality") : nullptr)
                    if (m->kind == Kind::String && (m->string == "Vibrotactile" || m->string == "Vibration")) otherFelt_ = false;
            for (const JsonValue& p : ps->array) {
                if (p.kind != Kind::Object) { fail(p.line, "perceptions", "each perception is an object"); continue; }
                readPerception(p, ids);
            }
        }
    }

private:
    bool otherFelt_ = false;
    const std::string& source_;
    bool collect_;
    std::string profile_ = "Main";
    int level_ = 2;

    void fail(long line, const std::string& where, const std::string& what)
    {
        if (!collect_) throw core::InputError(source_, line, where, what);
        problems.push_back({line, where, what});
    }

    const JsonValue* get(const JsonValue& o, std::string_view key, Kind kind, bool required = true)
    {
        const JsonValue* v = o.find(key);
        if (!v) {
            if (required) fail(o.line, std::string(key), "missing");
            return nullptr;
        }
        if (v->kind != kind) {
            fail(v->line, std::string(key), std::string("must be ") + JsonValue::kindName(kind) + ", not " + JsonValue::kindName(v->kind));
            return nullptr;
        }
        return v;
    }

    /// A whole number in [lo, hi], or nothing (a problem noted).
    bool integer(const JsonValue& o, std::string_view key, long long lo, long long hi, long long& out, bool required = true)
    {
        const JsonValue* v = get(o, key, Kind::Number, required);
        if (!v) return false;
        if (std::floor(v->number) != v->number || v->number < static_cast<double>(lo) || v->number > static_cast<double>(hi)) {
            fail(v->line, std::string(key), scoretext::number(v->number) + ": must be a whole number in " + std::to_string(lo) + ".." + std::to_string(hi));
            return false;
        }
        out = static_cast<long long>(v->number);
        return true;
    }

    void readPerception(const JsonValue& p, std::set<long long>& ids)
    {
        long long id = 0, avatar = 0, unit = 0, perceptionUnit = 0;
        if (integer(p, "id", -2147483648LL, 2147483647LL, id) && !ids.insert(id).second) fail(p.line, "id", "perception id " + std::to_string(id) + " is not unique");
        integer(p, "avatar_id", -2147483648LL, 2147483647LL, avatar);
        get(p, "description", Kind::String);
        integer(p, "unit_exponent", -128, 127, unit, false);
        integer(p, "perception_unit_exponent", -128, 127, perceptionUnit, false);
        std::string modality;
        if (const JsonValue* m = get(p, "perception_modality", Kind::String)) {
            modality = m->string;
            static const std::set<std::string> known {"Other", "Pressure", "Acceleration", "Velocity", "Position", "Temperature", "Vibration", "Vibrotactile", "Water",
                                                      "Wind", "Kinesthetic", "Force", "Vibrotactile Texture", "Texture", "Stiffness", "Friction", "Electrotactile"};
            if (!known.count(modality)) fail(m->line, "perception_modality", "unknown modality '" + modality + "'");
        }
        const bool other = modality == "Other" && otherFelt_;
        const bool felt = modality == "Vibrotactile" || modality == "Vibration" || other;
        if (!felt) ++file.otherPerceptions;
        if (other) ++file.otherFelt;
        // The library: by id (unique); each entry stays JSON and is resolved where it is referenced.
        std::map<long long, const JsonValue*> library;
        if (const JsonValue* lib = get(p, "effect_library", Kind::Array))
            for (const JsonValue& e : lib->array) {
                if (e.kind != Kind::Object) { fail(e.line, "effect_library", "each effect is an object"); continue; }
                long long eid = 0;
                if (!integer(e, "id", -2147483648LL, 2147483647LL, eid)) continue;
                if (!library.emplace(eid, &e).second) fail(e.line, "id", "library effect id " + std::to_string(eid) + " is not unique");
            }
        // Every library effect is checked where it stands, referenced or not (its keyframes,
        // types, the references it holds); what it plays is added where it is referenced.
        {
            Band scratch;
            const double seconds = file.seconds;
            for (const auto& [eid, e] : library) readEffect(*e, 0.0, false, scratch, library, 0);
            file.seconds = seconds;
        }
        const JsonValue* channels = get(p, "channels", Kind::Array);
        if (!channels) return;
        const std::size_t maxChannels = level_ == 1 ? 127 : 65535;
        if (channels->array.size() > maxChannels)
            return fail(channels->line, "channels", std::to_string(channels->array.size()) + " channels: level " + std::to_string(level_) + " allows " + std::to_string(maxChannels));
        std::set<long long> channelIds;
        for (const JsonValue& c : channels->array) {
            if (c.kind != Kind::Object) { fail(c.line, "channels", "each channel is an object"); continue; }
            Channel ch;
            ch.perceptionId = static_cast<int>(id);
            ch.scale = std::pow(10.0, static_cast<double>(perceptionUnit));
            long long cid = 0, mask = 0;
            if (integer(c, "id", -2147483648LL, 2147483647LL, cid) && !channelIds.insert(cid).second) fail(c.line, "id", "channel id " + std::to_string(cid) + " is not unique");
            ch.id = static_cast<int>(cid);
            if (const JsonValue* d = get(c, "description", Kind::String)) ch.description = d->string;
            if (const JsonValue* g = get(c, "gain", Kind::Number)) ch.gain = g->number;
            // `mixing_weight` is the same field under the name the reference used until its commit
            // 1bf6166 (2023-12): every example output under scripts/RM_submission/out/ carries it.
            if (c.find("mixing_weight") == nullptr || c.find("mixing_coefficient") != nullptr) get(c, "mixing_coefficient", Kind::Number);
            else get(c, "mixing_weight", Kind::Number);
            if (integer(c, "body_part_mask", 0, 4294967295LL, mask)) ch.bodyPartMask = static_cast<std::uint32_t>(mask);
            readActuators(c, ch);
            if (const JsonValue* bands = get(c, "bands", Kind::Array)) {
                const std::size_t maxBands = level_ == 1 ? 7 : 63;
                if (bands->array.size() > maxBands)
                    fail(bands->line, "bands", std::to_string(bands->array.size()) + " bands: level " + std::to_string(level_) + " allows " + std::to_string(maxBands));
                else
                    for (const JsonValue& b : bands->array) readBand(b, ch, library);
            }
            if (felt) file.channels.push_back(std::move(ch));
        }
    }

    void readActuators(const JsonValue& c, Channel& ch)
    {
        const JsonValue* res = c.find("actuator_resolution");
        const JsonValue* targets = c.find("actuator_target");
        const auto vec = [&](const JsonValue& v, long long& x, long long& y, long long& z) {
            if (v.kind != Kind::Object) { fail(v.line, "actuator", "a vector is an object {X, Y, Z}"); return false; }
            return integer(v, "X", -128, 127, x) && integer(v, "Y", -128, 127, y) && integer(v, "Z", -128, 127, z);
        };
        long long rx = 0, ry = 0, rz = 0;
        if (res) {
            if (!vec(*res, rx, ry, rz)) return;
            if (rx < 0 || ry < 0 || rz < 0) return fail(res->line, "actuator_resolution", "negative");
            ch.resolutionX = static_cast<int>(rx);
            ch.resolutionY = static_cast<int>(ry);
        }
        if (!targets) return;
        if (!res) return fail(targets->line, "actuator_target", "given without actuator_resolution");
        if (targets->kind != Kind::Array) return fail(targets->line, "actuator_target", "must be an array of {X, Y, Z}");
        for (const JsonValue& t : targets->array) {
            long long x = 0, y = 0, z = 0;
            if (!vec(t, x, y, z)) continue;
            if (x < 0 || x > rx || y < 0 || y > ry || z < 0 || z > rz) { fail(t.line, "actuator_target", "outside the actuator_resolution"); continue; }
            ch.targets.emplace_back(static_cast<int>(x), static_cast<int>(y));
        }
    }

    void readBand(const JsonValue& b, Channel& ch, const std::map<long long, const JsonValue*>& library)
    {
        if (b.kind != Kind::Object) return fail(b.line, "bands", "each band is an object");
        Band band;
        const JsonValue* type = get(b, "band_type", Kind::String);
        if (!type) return;
        static const std::map<std::string, BandType> types {{"Transient", BandType::Transient}, {"Curve", BandType::Curve},
                                                            {"VectorialWave", BandType::VectorialWave}, {"WaveletWave", BandType::WaveletWave}};
        const auto t = types.find(type->string);
        if (t == types.end()) return fail(type->line, "band_type", "unknown band type '" + type->string + "' (Transient, Curve, VectorialWave, WaveletWave)");
        band.type = t->second;
        long long lo = 0, hi = 0;
        if (integer(b, "lower_frequency_limit", 0, 2147483647LL, lo) && integer(b, "upper_frequency_limit", 0, 2147483647LL, hi) && hi < lo)
            fail(b.line, "upper_frequency_limit", "below lower_frequency_limit");
        band.lowerHz = static_cast<double>(lo);
        band.upperHz = static_cast<double>(hi);
        if (const JsonValue* ct = get(b, "curve_type", Kind::String, false)) {
            static const std::map<std::string, CurveType> curves {{"Unknown", CurveType::Unknown}, {"Cubic", CurveType::Cubic}, {"Linear", CurveType::Linear},
                                                                  {"Akima", CurveType::Akima}, {"Bezier", CurveType::Bezier}, {"Bspline", CurveType::Bspline}};
            const auto c = curves.find(ct->string);
            // "Unknown" on another band says "no curve": the reference's writer put it on every band
            // before it wrote it on Curve bands only, and its example outputs carry it on VectorialWave bands.
            if (band.type != BandType::Curve && ct->string != "Unknown") fail(ct->line, "curve_type", "given on a " + type->string + " band (only Curve bands have one)");
            else if (c == curves.end()) fail(ct->line, "curve_type", "unknown curve type '" + ct->string + "'");
            else band.curve = c->second;
        }
        if (band.type == BandType::WaveletWave) {
            long long block = 0;
            if (integer(b, "block_length", 1, 1LL << 30, block) && (block & (block - 1)) != 0) fail(b.line, "block_length", "must be a power of two");
            if (profile_ == "Simple Parametric") fail(type->line, "band_type", "the Simple Parametric profile has no WaveletWave bands");
        }
        const JsonValue* effects = get(b, "effects", Kind::Array);
        if (!effects) return;
        for (const JsonValue& e : effects->array) readEffect(e, 0.0, false, band, library, 0);
        ch.bands.push_back(std::move(band));
    }

    /// An effect at `base` seconds (a composite's start); `atBase`: the position is `base` itself
    /// (a library effect copied to a reference's position, Perception::linearizeLibrary).
    void readEffect(const JsonValue& e, double base, bool atBase, Band& band, const std::map<long long, const JsonValue*>& library, int depth)
    {
        if (e.kind != Kind::Object) return fail(e.line, "effects", "each effect is an object");
        if (depth > kMaxNesting) return fail(e.line, "effects", "references and composites nest deeper than " + std::to_string(kMaxNesting) + " (a reference to itself?)");
        const JsonValue* type = get(e, "effect_type", Kind::String);
        if (!type) return;
        if (type->string != "Basis" && type->string != "Reference" && type->string != "Composite")
            return fail(type->line, "effect_type", "unknown effect type '" + type->string + "' (Basis, Reference, Composite)");
        long long position = 0;
        if (!atBase && !integer(e, "position", 0, 2147483647LL, position)) return;
        const double start = atBase ? base : base + static_cast<double>(position) / file.timescale;
        if (start > kMaxSeconds) return fail(e.line, "position", "the effect starts " + scoretext::number(start, 1) + " s in: longer than the hour an imported score may last");
        if (type->string == "Reference") {
            long long id = 0;
            if (!integer(e, "id", -2147483648LL, 2147483647LL, id)) return;
            const auto it = library.find(id);
            if (it == library.end()) return fail(e.line, "id", "a Reference to effect id " + std::to_string(id) + ", which the perception's effect_library does not have");
            return readEffect(*it->second, start, true, band, library, depth + 1);
        }
        if (type->string == "Composite") {
            if (profile_ == "Simple Parametric") return fail(type->line, "effect_type", "the Simple Parametric profile has no Composite effects");
            const JsonValue* timeline = get(e, "timeline", Kind::Array);
            if (!timeline) return;
            for (const JsonValue& sub : timeline->array) readEffect(sub, start, false, band, library, depth + 1);
            return;
        }
        Effect effect;
        effect.start = start;
        if (const JsonValue* s = get(e, "base_signal", Kind::String, false)) {
            if (s->string != "Sine" && s->string != "Square" && s->string != "Triangle" && s->string != "SawToothUp" && s->string != "SawToothDown")
                return fail(s->line, "base_signal", "unknown base signal '" + s->string + "'");
            effect.baseSignal = s->string;
        }
        if (band.type == BandType::WaveletWave) {
            if (!collect_)
                fail(e.line, "band_type",
                     "WaveletWave bands are not imported: their effects carry a SPIHT/arithmetic-coded wavelet bitstream (source/WaveletDecoder, "
                     "source/Spiht) that ARMadillo does not decode (docs/FORMATS.md)");
            return;
        }
        if (const JsonValue* kfs = get(e, "keyframes", Kind::Array, false)) {
            long long previous = 0;
            effect.keyframes.reserve(kfs->array.size());
            for (std::size_t i = 0; i < kfs->array.size(); ++i) {
                const JsonValue& k = kfs->array[i];
                if (k.kind != Kind::Object) { fail(k.line, "keyframes", "each keyframe is an object"); continue; }
                Keyframe kf;
                long long rel = previous;
                if (k.find("relative_position") && !integer(k, "relative_position", 0, 2147483647LL, rel)) continue;
                if (rel < previous) {
                    fail(k.line, "relative_position", "keyframe " + std::to_string(i + 1) + " at " + std::to_string(rel) + " comes after keyframe " + std::to_string(i) + " at " +
                                                          std::to_string(previous) + ": keyframes are in time order and the effect ends at its last");
                    continue;
                }
                previous = rel;
                kf.time = static_cast<double>(rel) / file.timescale;
                if (start + kf.time > kMaxSeconds) { fail(k.line, "relative_position", "past the hour an imported score may last"); continue; }
                if (const JsonValue* a = get(k, "amplitude_modulation", Kind::Number, false)) {
                    kf.hasAmplitude = true;
                    kf.amplitude = a->number;
                }
                if (const JsonValue* f = get(k, "frequency_modulation", Kind::Number, false)) {
                    if (!(f->number >= 0.0 && f->number <= kMaxHz)) { fail(f->line, "frequency_modulation", "must lie in 0..100000 Hz"); continue; }
                    kf.hasFrequency = true;
                    kf.frequency = f->number;
                }
                effect.keyframes.push_back(kf);
            }
        }
        if (effect.keyframes.empty()) return;   // nothing to feel (Effect::getEffectTimeLength is 0)
        double end = effect.start + effect.keyframes.back().time + (band.type == BandType::Transient ? kTransientSeconds : 0.0);
        file.seconds = std::max(file.seconds, end);
        band.effects.push_back(std::move(effect));
    }
};

// ---- evaluation -----------------------------------------------------------------------------

/// The reference's Akima slopes (source/Tools/src/Tools.cpp, akimaInterpolation): secant
/// slopes extended by two on each side, weights |m(i+1) − m(i)|, the mean when both are flat.
std::vector<double> akimaSlopes(const std::vector<std::pair<double, double>>& p)
{
    const std::size_t n = p.size();
    std::vector<double> m(n + 3);   // m[i + 2] = slope of segment i
    for (std::size_t i = 0; i + 1 < n; ++i) m[i + 2] = (p[i + 1].second - p[i].second) / (p[i + 1].first - p[i].first);
    m[1] = 2 * m[2] - m[3];
    m[0] = 3 * m[2] - 2 * m[3];
    m[n + 1] = 2 * m[n] - m[n - 1];
    m[n + 2] = 3 * m[n] - 2 * m[n - 1];
    std::vector<double> b(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double w1 = std::fabs(m[i + 3] - m[i + 2]), w2 = std::fabs(m[i + 1] - m[i]);
        b[i] = (w1 + w2) > 1e-12 ? (w1 * m[i + 1] + w2 * m[i + 2]) / (w1 + w2) : 0.5 * (m[i + 1] + m[i + 2]);
    }
    return b;
}

/// Bezier (Tools.cpp, bezierInterpolation): keyframes taken three at a time, each triple one
/// quadratic Bezier from the first to the third with the second as its control point, in time as
/// in value (the time solved for its parameter); with an even count the last keyframe is left out.
double bezierValue(const std::vector<std::pair<double, double>>& p, double t)
{
    const std::size_t used = p.size() % 2 == 0 ? p.size() - 1 : p.size();
    for (std::size_t i = 0; i + 2 < used; i += 2) {
        const auto& [x0, y0] = p[i];
        const auto& [x1, y1] = p[i + 1];
        const auto& [x2, y2] = p[i + 2];
        if (t > x2 || x2 <= x0) continue;
        const double a = x0 - 2 * x1 + x2, b = 2 * (x1 - x0), c = x0 - t;
        double u = 0.0;
        if (std::fabs(a) < 1e-15) u = b != 0.0 ? -c / b : 0.0;
        else u = (-b + std::sqrt(std::max(0.0, b * b - 4 * a * c))) / (2 * a);
        u = std::clamp(u, 0.0, 1.0);
        return (1 - u) * (1 - u) * y0 + 2 * u * (1 - u) * y1 + u * u * y2;
    }
    return 0.0;   // past the last keyframe used
}

/// Bspline (Tools.cpp, bsplineInterpolation): the quadratic B-spline of the keyframes as control
/// points, clamped, uniform knots 0, 0, 0, 1/(n−2), …, 1, 1, 1, in time as in value (the time
/// solved for its parameter by bisection: time rises with the parameter).
struct Bspline {
    const std::vector<std::pair<double, double>>& p;
    std::vector<double> knots;
    explicit Bspline(const std::vector<std::pair<double, double>>& points) : p(points)
    {
        const std::size_t n = p.size();
        if (n < 3) return;   // (two keyframes are linear)
        knots = {0.0, 0.0};
        for (std::size_t i = 0; i + 1 < n; ++i) knots.push_back(static_cast<double>(i) / static_cast<double>(n - 2));
        knots.push_back(1.0);
        knots.push_back(1.0);
    }
    std::pair<double, double> at(double u) const   // de Boor, degree 2
    {
        std::size_t k = 2;
        while (k + 1 < p.size() && u >= knots[k + 1]) ++k;   // knots[k] <= u < knots[k + 1]
        std::pair<double, double> d[3] = {p[k - 2], p[k - 1], p[k]};
        for (int r = 1; r <= 2; ++r)
            for (int j = 2; j >= r; --j) {
                const std::size_t i = k - 2 + static_cast<std::size_t>(j);
                const double span = knots[i + 3 - static_cast<std::size_t>(r)] - knots[i];
                const double w = span > 0.0 ? (u - knots[i]) / span : 0.0;
                d[j].first = (1 - w) * d[j - 1].first + w * d[j].first;
                d[j].second = (1 - w) * d[j - 1].second + w * d[j].second;
            }
        return d[2];
    }
    double value(double t) const
    {
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < 48; ++i) {
            const double mid = 0.5 * (lo + hi);
            (at(mid).first < t ? lo : hi) = mid;
        }
        return at(0.5 * (lo + hi)).second;
    }
};

double curveValue(CurveType type, const std::vector<std::pair<double, double>>& p, const std::vector<double>& slopes, std::size_t i, double t)
{
    const auto& [t0, f0] = p[i];
    const auto& [t1, f1] = p[i + 1];
    const double h = t1 - t0, u = t - t0;
    if (p.size() == 2 || type == CurveType::Linear) return f0 + (f1 - f0) * u / h;
    if (type == CurveType::Akima) {
        const double m = (f1 - f0) / h, b0 = slopes[i], b1 = slopes[i + 1];
        const double c = (3 * m - 2 * b0 - b1) / h, d = (b0 + b1 - 2 * m) / (h * h);
        return ((d * u + c) * u + b0) * u + f0;
    }
    // Cubic, and Unknown as the synthesizer's default: Hermite with flat ends (Effect::EvaluateKeyframes).
    return f0 + (f1 - f0) * (3 * h - 2 * u) * u * u / (h * h * h);
}

} // namespace

std::vector<Problem> checkStructure(std::string_view json, const std::string& source)
{
    const JsonValue root = core::parseJson(json, source);
    Reader r(source, true);
    r.read(root);
    return r.problems;
}

File parse(std::string_view json, const std::string& source)
{
    const JsonValue root = core::parseJson(json, source);
    Reader r(source, false);
    r.read(root);
    return std::move(r.file);
}

std::vector<Envelope> evaluate(const File& file, double step, const std::string& source)
{
    const auto frames = static_cast<std::size_t>(std::ceil(file.seconds / step)) + 1;
    if (static_cast<double>(frames) * static_cast<double>(file.channels.size()) > 3.0e7)
        throw core::InputError(source, 0, "channels", std::to_string(file.channels.size()) + " channels over " + scoretext::number(file.seconds, 1) +
                                                          " s: more than the 30 million frames an import evaluates");
    std::vector<Envelope> out(file.channels.size());
    double work = 0.0;
    constexpr double kMaxWork = 2.0e8;
    const auto overBudget = [&] {
        throw core::InputError(source, 0, "effects", "the effects overlap so much that evaluating them exceeds the import's budget (200 million frame evaluations)");
    };
    // Frames k whose time (k + 0.5)·step lies in [a, b] (b inclusive).
    const auto frameRange = [&](double a, double b) {
        const double first = std::max(0.0, std::ceil(a / step - 0.5 - 1e-9));
        const double last = std::min(static_cast<double>(frames) - 1.0, std::floor(b / step - 0.5 + 1e-9));
        return std::pair<std::size_t, std::size_t> {static_cast<std::size_t>(first), last < first ? 0 : static_cast<std::size_t>(last) + 1};
    };
    for (std::size_t c = 0; c < file.channels.size(); ++c) {
        const Channel& ch = file.channels[c];
        std::vector<double> sum(frames, 0.0);
        double minHz = 0.0, maxHz = 0.0;
        const auto carrier = [&](double hz) {
            if (!(hz > 0.0)) return;
            minHz = minHz > 0.0 ? std::min(minHz, hz) : hz;
            maxHz = std::max(maxHz, hz);
        };
        for (const Band& band : ch.bands)
            for (const Effect& e : band.effects) {
                const auto& kfs = e.keyframes;
                if (band.type == BandType::Transient) {
                    // Each keyframe: a 22 ms burst sin(4π τ / 22 ms) at its amplitude (Effect::EvaluateTransient).
                    for (const Keyframe& k : kfs) {
                        if (!k.hasAmplitude) continue;
                        const auto [f0, f1] = frameRange(e.start + k.time, e.start + k.time + kTransientSeconds);
                        for (std::size_t f = f0; f < f1; ++f) sum[f] += std::fabs(k.amplitude);
                        work += static_cast<double>(f1 > f0 ? f1 - f0 : 0) + 1.0;
                        if (k.amplitude != 0.0) carrier(2.0 / kTransientSeconds);
                    }
                    if (work > kMaxWork) overBudget();
                    continue;
                }
                std::vector<std::pair<double, double>> amps, freqs;
                for (const Keyframe& k : kfs) {
                    if (k.hasAmplitude) amps.emplace_back(k.time, k.amplitude);
                    if (k.hasFrequency) freqs.emplace_back(k.time, k.frequency);
                }
                const double length = kfs.back().time;
                const auto [f0, f1] = frameRange(e.start, e.start + length);
                work += static_cast<double>(f1 > f0 ? f1 - f0 : 0) + static_cast<double>(kfs.size());
                if (work > kMaxWork) overBudget();
                if (band.type == BandType::Curve) {
                    if (amps.empty()) continue;
                    const std::vector<double> slopes = band.curve == CurveType::Akima && amps.size() > 2 ? akimaSlopes(amps) : std::vector<double> {};
                    const bool spline = amps.size() > 2 && (band.curve == CurveType::Bezier || band.curve == CurveType::Bspline);
                    const Bspline bspline(amps);
                    std::size_t i = 0;
                    for (std::size_t f = f0; f < f1; ++f) {
                        const double t = (static_cast<double>(f) + 0.5) * step - e.start;
                        if (t >= amps.back().first) break;   // at and after the last keyframe: 0
                        if (t < amps.front().first) { sum[f] += std::fabs(amps.front().second); continue; }
                        if (spline) {
                            sum[f] += std::fabs(band.curve == CurveType::Bezier ? bezierValue(amps, t) : bspline.value(t));
                            continue;
                        }
                        while (i + 2 < amps.size() && t >= amps[i + 1].first) ++i;
                        if (amps[i + 1].first <= amps[i].first) continue;
                        sum[f] += std::fabs(curveValue(band.curve, amps, slopes, i, t));
                    }
                    continue;
                }
                // VectorialWave (Effect::EvaluateVectorial): amplitude linear between amplitude
                // keyframes, held before the first and after the last (1 without any); the carrier
                // sweeps linearly between frequency keyframes (a chirp), clamped to the band's limits.
                // A sine at 0 Hz is silent (no frequency keyframe); a square at 0 Hz is its amplitude.
                const bool dcAtZero = e.baseSignal == "Square";
                std::size_t ia = 0, jf = 0;
                for (std::size_t f = f0; f < f1; ++f) {
                    const double t = (static_cast<double>(f) + 0.5) * step - e.start;
                    double a = 1.0;
                    if (!amps.empty()) {
                        while (ia < amps.size() && amps[ia].first < t) ++ia;
                        if (ia == 0) a = amps.front().second;
                        else if (ia == amps.size()) a = amps.back().second;
                        else {
                            const auto& [t0, a0] = amps[ia - 1];
                            const auto& [t1, a1] = amps[ia];
                            a = t1 > t0 ? a0 + (a1 - a0) * (t - t0) / (t1 - t0) : a1;
                        }
                    }
                    double hz = 0.0;
                    if (!freqs.empty()) {
                        while (jf < freqs.size() && freqs[jf].first < t) ++jf;
                        if (jf == 0) hz = freqs.front().second;
                        else if (jf == freqs.size()) hz = freqs.back().second;
                        else {
                            const auto& [t0, h0] = freqs[jf - 1];
                            const auto& [t1, h1] = freqs[jf];
                            hz = std::clamp(t1 > t0 ? h0 + (h1 - h0) * (t - t0) / (t1 - t0) : h1, band.lowerHz, std::max(band.lowerHz, band.upperHz));
                        }
                    }
                    if (hz <= 0.0 && !dcAtZero) continue;
                    sum[f] += std::fabs(a);
                    if (a != 0.0) carrier(hz);
                }
            }
        Envelope& env = out[c];
        env.amplitude.resize(frames);
        const double scale = std::fabs(ch.gain) * ch.scale;
        for (std::size_t f = 0; f < frames; ++f) env.amplitude[f] = static_cast<float>(std::clamp(std::min(1.0, sum[f]) * scale, 0.0, 1.0));
        env.minHz = minHz;
        env.maxHz = maxHz;
    }
    return out;
}

std::string write(const std::vector<core::TactileRow>& rows, int motors, const std::string& project, double carrierHz)
{
    const int rowsOfMotors = (motors + 2) / 3;
    std::string s = "{\n  \"version\": \"2023\",\n  \"profile\": \"Main\",\n  \"level\": 2,\n  \"date\": \"\",\n  \"description\": ";
    core::appendJsonString(s, "ARMadillo motors of " + project + ": one channel per motor, amplitude = level/15 (docs/FORMATS.md)");
    s += ",\n  \"timescale\": 1000,\n  \"avatars\": [{\"id\": 1, \"lod\": 0, \"type\": \"Vibration\"}],\n  \"syncs\": [],\n  \"perceptions\": [{\n"
         "    \"id\": 0, \"avatar_id\": 1, \"description\": \"the forearm's motor grid\", \"perception_modality\": \"Vibrotactile\",\n"
         "    \"effect_library\": [],\n    \"channels\": [";
    const double t0 = rows.empty() ? 0.0 : rows.front().t;
    for (int m = 0; m < motors; ++m) {
        // (tick, amplitude) keyframes: a step is a 1 ms ramp ending at the packet's tick.
        std::vector<std::pair<long long, int>> kf {{0, 0}};
        int current = 0;
        for (std::size_t i = 0; i <= rows.size(); ++i) {
            const bool past = i == rows.size();
            if (past && rows.empty()) break;
            const long long tick = past ? std::llround((rows.back().t - t0) * 1000.0) + 5 : std::llround((rows[i].t - t0) * 1000.0);
            const int level = past ? 0 : std::min(15, static_cast<int>(rows[i].levels[static_cast<std::size_t>(m)]));
            if (level == current) continue;
            if (tick - 1 > kf.back().first) kf.emplace_back(tick - 1, current);
            if (tick > kf.back().first) kf.emplace_back(tick, level);
            else kf.back().second = level;
            current = level;
        }
        s += m ? ",\n" : "\n";
        s += "      {\"id\": " + std::to_string(m) + ", \"description\": \"motor m" + std::to_string(m + 1) +
             "\", \"gain\": 1, \"mixing_coefficient\": 1, \"body_part_mask\": 0,\n"
             "       \"actuator_resolution\": {\"X\": 3, \"Y\": " + std::to_string(rowsOfMotors) + ", \"Z\": 1}, \"actuator_target\": [{\"X\": " +
             std::to_string(m % 3) + ", \"Y\": " + std::to_string(m / 3) + ", \"Z\": 0}],\n"
             "       \"bands\": [{\"band_type\": \"VectorialWave\", \"lower_frequency_limit\": 40, \"upper_frequency_limit\": 400, \"effects\": [\n"
             "         {\"effect_type\": \"Basis\", \"position\": 0, \"base_signal\": \"Sine\", \"keyframes\": [";
        for (std::size_t i = 0; i < kf.size(); ++i) {
            s += i ? ", " : "";
            if (i % 4 == 0) s += "\n           ";
            s += "{\"relative_position\": " + std::to_string(kf[i].first) + ", \"amplitude_modulation\": " + scoretext::number(kf[i].second / 15.0, 6);
            if (i == 0) s += ", \"frequency_modulation\": " + scoretext::number(carrierHz, 0);
            s += "}";
        }
        s += "]}]}]}";
    }
    return s + "\n    ]\n  }]\n}\n";
}

} // namespace armadillo::formats::hjif

namespace armadillo::formats {

namespace {
constexpr std::size_t kMaxHjifBytes = 64u << 20;
} // namespace

std::uint16_t hjifDefaultMotors(const hjif::Channel& ch, int gridMotors) noexcept
{
    const auto all = static_cast<std::uint16_t>((1u << std::clamp(gridMotors, 1, core::kMaxMotors)) - 1u);
    if (ch.targets.empty() || ch.resolutionX <= 0 || ch.resolutionY <= 0) return all;
    std::uint16_t mask = 0;
    for (const auto& [x, y] : ch.targets) {
        int column = 1, row = 1;
        if (ch.resolutionX == 3 && (ch.resolutionY == 3 || ch.resolutionY == 4)) {   // our own grid (and its back row): as written
            column = std::min(x, 2);
            row = std::min(y, ch.resolutionY - 1);
        } else {   // another grid: spread over our 3 x 3 in proportion
            if (ch.resolutionX > 1) column = static_cast<int>(std::lround(2.0 * std::min(x, ch.resolutionX - 1) / (ch.resolutionX - 1)));
            if (ch.resolutionY > 1) row = static_cast<int>(std::lround(2.0 * std::min(y, ch.resolutionY - 1) / (ch.resolutionY - 1)));
        }
        const int motor = 3 * row + column;
        if (motor < std::max(gridMotors, ch.resolutionX == 3 && ch.resolutionY == 4 ? 12 : 0)) mask = static_cast<std::uint16_t>(mask | (1u << motor));
    }
    return mask ? mask : all;
}

ImportedScore importHjif(std::string_view json, const std::string& source, const HapticImportOptions& o)
{
    if (json.size() > kMaxHjifBytes)
        throw core::InputError(source, 0, "", std::to_string(json.size() / 1000000) + " MB: an .hjif file imported here is at most 64 MB");
    const hjif::File file = hjif::parse(json, source);
    ImportReport report;
    report.format = "hjif";
    if (file.otherPerceptions > 0)
        report.warnings.push_back(std::to_string(file.otherPerceptions) + " perception(s) of another modality than Vibrotactile: not felt, left out");
    if (file.otherFelt > 0)
        report.warnings.push_back(std::to_string(file.otherFelt) + " perception(s) of modality Other felt as vibration: the file has no Vibrotactile perception");
    if (file.channels.empty()) throw core::InputError(source, 0, "perceptions", "no Vibrotactile channel: nothing for the motors");
    // Channel -> motors.
    std::vector<std::uint16_t> motorsOf(file.channels.size(), 0);
    if (o.hjifChannels.empty()) {
        for (std::size_t c = 0; c < file.channels.size(); ++c) motorsOf[c] = hjifDefaultMotors(file.channels[c], o.hjifGridMotors);
    } else {
        for (const auto& [channel, motors] : o.hjifChannels) {
            if (channel < 1 || static_cast<std::size_t>(channel) > file.channels.size())
                throw core::InputError(source, 0, "channels", "--actuator-motors names channel " + std::to_string(channel) + " but the file has " +
                                                                  std::to_string(file.channels.size()) + " Vibrotactile channel(s)");
            motorsOf[static_cast<std::size_t>(channel - 1)] = static_cast<std::uint16_t>(motorsOf[static_cast<std::size_t>(channel - 1)] | motors);
        }
    }
    const double step = o.frameSeconds;
    const std::vector<hjif::Envelope> env = hjif::evaluate(file, step, source);
    const std::size_t frames = env.empty() ? 0 : env.front().amplitude.size();
    std::string text = "armadillo-score 2\n# Imported from " + scoretext::oneLine(std::filesystem::path(source).filename().string()) +
                       " by `armadillo score import` (docs/FORMATS.md, \"MPEG haptics .hjif\").\n";
    const std::string title = scoretext::oneLine(std::filesystem::path(source).stem().string());
    text += "title " + (title.empty() ? std::string("imported") : title) + "\nunits seconds\n";
    text += "# level = 15 x the channel's amplitude envelope (gain and 10^perception_unit_exponent applied), per " + scoretext::number(step * 1e3, 3) +
            " ms frame; a motor on several channels: the loudest.\n";
    for (std::size_t c = 0; c < file.channels.size(); ++c) {
        const hjif::Channel& ch = file.channels[c];
        text += "# channel " + std::to_string(c + 1) + " (perception " + std::to_string(ch.perceptionId) + ", id " + std::to_string(ch.id) + ", " +
                scoretext::oneLine(ch.description) + "): motors " + (motorsOf[c] ? scoretext::motorSet(motorsOf[c]) : std::string("none"));
        if (env[c].maxHz > 0.0)
            text += ", carrier " + scoretext::number(env[c].minHz, 0) + (env[c].maxHz > env[c].minHz ? ".." + scoretext::number(env[c].maxHz, 0) : std::string()) + " Hz";
        text += "\n";
    }
    // Motors driven by the same channels play the same levels: one note for all of them.
    std::map<std::vector<bool>, std::uint16_t> groups;
    for (int m = 0; m < core::kMaxMotors; ++m) {
        std::vector<bool> set(file.channels.size());
        bool any = false;
        for (std::size_t c = 0; c < file.channels.size(); ++c) any |= (set[c] = (motorsOf[c] >> m) & 1u);
        if (any) groups[set] = static_cast<std::uint16_t>(groups[set] | (1u << m));
    }
    struct Run {
        std::size_t from, frames;
        double level;
        std::uint16_t motors;
    };
    std::vector<Run> runs;
    for (const auto& [set, motors] : groups) {
        double current = 0.0;
        std::size_t from = 0;
        for (std::size_t f = 0; f <= frames; ++f) {
            double level = 0.0;
            if (f < frames)
                for (std::size_t c = 0; c < set.size(); ++c)
                    if (set[c]) level = std::max(level, std::round(1500.0 * static_cast<double>(env[c].amplitude[f])) / 100.0);
            if (level == current) continue;
            if (current > 0.0) runs.push_back({from, f - from, current, motors});
            current = level;
            from = f;
        }
    }
    std::stable_sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.from < b.from; });
    for (const Run& r : runs) {
        const double start = static_cast<double>(r.from) * step, duration = static_cast<double>(r.frames) * step;
        text += scoretext::number(start) + " note m=" + scoretext::motorSet(r.motors) + " dur=" + scoretext::number(std::max(1e-6, duration - 1e-6)) +
                " level=" + scoretext::number(r.level, 3) + " start=soft\n";
        ++report.notes;
    }
    text += "length " + scoretext::lengthNumber(std::max(step, static_cast<double>(frames) * step)) + "\n";
    ImportedScore out;
    out.text = std::move(text);
    out.report = std::move(report);
    out.score = tactile::parseScore(out.text, source);
    return out;
}

std::string exportHjif(const std::vector<core::TactileRow>& rows, int motors, const std::string& project)
{
    return hjif::write(rows, motors, project);
}

} // namespace armadillo::formats
