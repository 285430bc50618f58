#include "Tactors/TactorRenderer.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace armadillo::tactors {

namespace {
constexpr double kTwoPi = 6.28318530717958647692;
constexpr double kFullScale = 15.0;   // the level of a full-scale signal (docs/FORMATS.md)

std::string num(double v)
{
    std::ostringstream s;
    s << v;
    return s.str();
}
} // namespace

const char* modelName(TactorModel m) noexcept
{
    switch (m) {
    case TactorModel::Erm: return "erm";
    case TactorModel::Lra: return "lra";
    case TactorModel::VoiceCoil: return "voice-coil";
    }
    return "?";
}

bool parseModel(std::string_view text, TactorModel& out) noexcept
{
    for (TactorModel m : {TactorModel::Erm, TactorModel::Lra, TactorModel::VoiceCoil})
        if (text == modelName(m)) {
            out = m;
            return true;
        }
    return false;
}

void validate(const TactorParams& p, double sampleRate, const std::string& source)
{
    const auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
    if (!in(sampleRate, 8000.0, 384000.0)) throw core::InputError(source, 0, "sample rate", "sample rate " + num(sampleRate) + " Hz is outside 8000…384000");
    if (!in(p.ermStartHz, 40.0, 400.0)) throw core::InputError(source, 0, "erm start", "the ERM's start frequency must lie in 40…400 Hz (got " + num(p.ermStartHz) + ")");
    if (!in(p.ermFullHz, p.ermStartHz, 400.0))
        throw core::InputError(source, 0, "erm full", "the ERM's full-drive frequency must lie in " + num(p.ermStartHz) + "…400 Hz (got " + num(p.ermFullHz) + ")");
    if (!in(p.ermSpinTime, 0.0, 0.2)) throw core::InputError(source, 0, "erm spin", "the ERM's spin-up time must lie in 0…0.2 s (got " + num(p.ermSpinTime) + ")");
    if (!in(p.lraHz, 40.0, 400.0)) throw core::InputError(source, 0, "lra", "the LRA's resonance must lie in 40…400 Hz (got " + num(p.lraHz) + ")");
    if (!in(p.lraBrakeTime, 0.0, 0.02)) throw core::InputError(source, 0, "lra brake", "the LRA's braking pulse must last 0…0.02 s (got " + num(p.lraBrakeTime) + ")");
    if (!in(p.voiceCoilHz, 40.0, 400.0)) throw core::InputError(source, 0, "voice-coil", "the voice coil's carrier must lie in 40…400 Hz (got " + num(p.voiceCoilHz) + ")");
    if (!in(p.soundLowHz, 20.0, 1000.0) || !in(p.soundHighHz, p.soundLowHz, 1000.0))
        throw core::InputError(source, 0, "sound band", "the sound's band must lie within 20…1000 Hz, low before high (got " + num(p.soundLowHz) + "…" + num(p.soundHighHz) + ")");
    if (p.voiceCoilSound && p.model != TactorModel::VoiceCoil)
        throw core::InputError(source, 0, "sound", "a scene's sound can be handed over to the voice-coil model only");
    if (p.voiceCoilSound && !(p.soundHighHz < sampleRate / 2.0)) throw core::InputError(source, 0, "sound band", "the sound's band must lie below half the sample rate");
    const double highest = p.model == TactorModel::Erm ? p.ermFullHz : p.model == TactorModel::Lra ? p.lraHz : p.voiceCoilHz;
    if (!(highest < sampleRate / 2.0)) throw core::InputError(source, 0, "carrier", "the carrier must lie below half the sample rate");
}

double carrierHz(const TactorParams& p, double level) noexcept
{
    switch (p.model) {
    case TactorModel::Erm: {
        // A DC motor's speed follows its drive voltage (back-EMF ∝ speed; docs/TACTORS.md), and an
        // eccentric mass vibrates once per turn: the frequency rises linearly with the level.
        const double x = std::clamp(level, 0.0, kFullScale) / kFullScale;
        return p.ermStartHz + (p.ermFullHz - p.ermStartHz) * x;
    }
    case TactorModel::Lra: return p.lraHz;
    case TactorModel::VoiceCoil: return p.voiceCoilHz;
    }
    return p.voiceCoilHz;
}

ChannelMap ChannelMap::identity(int motors) noexcept
{
    ChannelMap m;
    m.channels = std::clamp(motors, 0, kMaxChannels);
    for (int c = 0; c < kMaxChannels; ++c) m.motor[static_cast<std::size_t>(c)] = c < m.channels ? c : -1;
    return m;
}

ChannelMap parseChannelMap(std::string_view text, int motors)
{
    const std::string src = "--tactor-map";
    ChannelMap map;
    map.motor.fill(-1);
    if (text.empty()) throw core::InputError(src, 0, "", "empty map: give one motor per channel, e.g. 1,2,3,4,5,6,7,8,9 (- for a silent channel)");
    std::size_t at = 0;
    while (true) {
        const std::size_t comma = text.find(',', at);
        const std::string_view item = text.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at);
        const auto motorNumber = [&](std::string_view s) {
            if (s.empty() || s.size() > 2 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
                throw core::InputError(src, 0, "", "'" + std::string(item) + "' is not a motor number (1.." + std::to_string(motors) + ") or -");
            const int k = std::stoi(std::string(s));
            if (k < 1 || k > motors)
                throw core::InputError(src, 0, "", "motor " + std::to_string(k) + " does not exist: this rig has motors 1.." + std::to_string(motors) +
                                                 (motors < 12 && k <= 12 ? " (m10..m12 are the back motors: render and tactors test take --back-motors)" : ""));
            return k;
        };
        int from = -1, to = -1;
        if (item == "-") {
            from = to = 0;
        } else if (const std::size_t dash = item.find('-'); dash != std::string_view::npos) {
            from = motorNumber(item.substr(0, dash));
            to = motorNumber(item.substr(dash + 1));
            if (to < from) throw core::InputError(src, 0, "", "range '" + std::string(item) + "' runs backwards");
        } else {
            from = to = motorNumber(item);
        }
        for (int k = from; k <= to; ++k) {
            if (map.channels == kMaxChannels) throw core::InputError(src, 0, "", "at most " + std::to_string(kMaxChannels) + " channels");
            map.motor[static_cast<std::size_t>(map.channels++)] = k - 1;   // "-" → -1
        }
        if (comma == std::string_view::npos) break;
        at = comma + 1;
    }
    return map;
}

std::string channelMapText(const ChannelMap& map)
{
    std::string s;
    for (int c = 0; c < map.channels; ++c) {
        if (c) s += ',';
        const int m = map.motor[static_cast<std::size_t>(c)];
        s += m < 0 ? std::string("-") : std::to_string(m + 1);
    }
    return s;
}

TactorGains parseTactorGains(std::string_view json, const std::string& source)
{
    const armadillo::core::JsonValue root = armadillo::core::parseJson(json, source); // InputError with the line of a syntax error
    if (root.kind != armadillo::core::JsonValue::Kind::Object) throw core::InputError(source, root.line, "", "a tactor gain file is a JSON object");
    for (const auto& [key, value] : root.object)
        if (key != "armadillo" && key != "version" && key != "gain" && key != "comment")
            throw core::InputError(source, value.line, key, "unknown key (known: armadillo, version, gain, comment)");
    const armadillo::core::JsonValue* kind = root.find("armadillo");
    if (!kind || kind->kind != armadillo::core::JsonValue::Kind::String || kind->string != "tactor-gains")
        throw core::InputError(source, kind ? kind->line : root.line, "armadillo", "not a tactor gain file: \"armadillo\": \"tactor-gains\" is missing");
    const armadillo::core::JsonValue* version = root.find("version");
    if (!version || version->kind != armadillo::core::JsonValue::Kind::Number || version->number != 1.0)
        throw core::InputError(source, version ? version->line : root.line, "version", "version 1 is the only one known");
    const armadillo::core::JsonValue* gain = root.find("gain");
    if (!gain || gain->kind != armadillo::core::JsonValue::Kind::Array)
        throw core::InputError(source, gain ? gain->line : root.line, "gain", "\"gain\" must be an array of 1..16 numbers in 0..1, channel 1 first");
    if (gain->array.empty() || gain->array.size() > static_cast<std::size_t>(kMaxChannels))
        throw core::InputError(source, gain->line, "gain", "\"gain\" holds " + std::to_string(gain->array.size()) + " numbers: 1..16 (one per channel)");
    TactorGains g;
    g.source = source;
    for (const armadillo::core::JsonValue& v : gain->array) {
        const std::string channel = "gain[" + std::to_string(g.count + 1) + "]";
        if (v.kind != armadillo::core::JsonValue::Kind::Number) throw core::InputError(source, v.line, channel, "channel " + std::to_string(g.count + 1) + ": a number in 0..1");
        if (!(std::isfinite(v.number) && v.number >= 0.0 && v.number <= 1.0))
            throw core::InputError(source, v.line, channel,
                             "channel " + std::to_string(g.count + 1) + ": gain " + num(v.number) +
                                 " is outside 0..1 (gains only attenuate: turn the amplifier up for the weakest tactor)");
        g.gain[static_cast<std::size_t>(g.count++)] = static_cast<float>(v.number);
    }
    return g;
}

TactorGains loadTactorGains(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw core::IoError("tactor gain file '" + path + "': cannot be read");
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw core::IoError("tactor gain file '" + path + "': read error");
    return parseTactorGains(s.str(), path);
}

void TactorRenderer::prepare(const TactorParams& params, const ChannelMap& map, const TactorGains& gains, double sampleRate,
                             const tactile::SafetyParams& safety)
{
    validate(params, sampleRate, "tactor settings");
    if (map.channels < 1 || map.channels > kMaxChannels) throw core::InputError("--tactor-map", 0, "", "1..16 channels");
    if (gains.count > map.channels)
        throw core::InputError(gains.source.empty() ? std::string("tactor gains") : gains.source, 0, "gain",
                         "the file gives " + std::to_string(gains.count) + " gains but the map has " + std::to_string(map.channels) + " channels");
    params_ = params;
    map_ = map;
    gains_ = gains;
    sampleRate_ = sampleRate;
    slew_ = params.model == TactorModel::Erm && params.ermSpinTime > 0.0 ? 1.0 - std::exp(-1.0 / (params.ermSpinTime * sampleRate)) : 1.0;
    brakeSamples_ = params.model == TactorModel::Lra ? static_cast<int>(std::lround(params.lraBrakeTime * sampleRate)) : 0;
    ratedLevel_ = safety.ratedLevel;
    guard_.prepare(safety, map.channels);
    limited_ = 0;
    for (Channel& c : ch_) {
        c = Channel {};
        c.hz = c.targetHz = carrierHz(params, 0.0);
    }
    // The sound's band: 2nd-order Butterworth high-pass and low-pass (Core/Biquad.h).
    highPass_ = core::Biquad::make(true, params.soundLowHz, sampleRate);
    lowPass_ = core::Biquad::make(false, params.soundHighHz, sampleRate);
    envelope_ = 0.0;
    release_ = std::exp(-1.0 / (0.05 * sampleRate));   // the envelope falls 1/e in 50 ms
    powerSlew_ = 1.0 - std::exp(-1.0 / (0.02 * sampleRate));
    fastRelease_ = std::exp(-1.0 / (0.005 * sampleRate));
    recent_ = 0.0;
    meanSquare_ = 0.0;
    fallbackPhase_ = 0.0;
    sound_ = nullptr;
    soundLeft_ = 0;
}

void TactorRenderer::setLevels(const core::MotorLevels& levels, double dt) noexcept
{
    core::MotorLevels want {};
    const int n = map_.channels;
    for (int c = 0; c < n; ++c) {
        Channel& s = ch_[static_cast<std::size_t>(c)];
        const int m = map_.motor[static_cast<std::size_t>(c)];
        const std::uint8_t level = m >= 0 ? std::min<std::uint8_t>(levels[static_cast<std::size_t>(m)], 15) : 0;
        // An LRA that stops is braked: the drive in antiphase for about one period, at most at the
        // rated level, so the mass stops instead of ringing down for tens of ms. The pulse is
        // asked of the guard like any level, for as long as it plays.
        const bool stopping = level == 0 && brakeSamples_ > 0 && (s.level > 0 || s.brakeLeft > 0);
        if (stopping && s.level > 0) {
            s.brakeLeft = brakeSamples_;
            s.brakeAmplitude = static_cast<float>(std::min<int>(guard_.lastOutput()[static_cast<std::size_t>(c)], ratedLevel_));
        }
        if (level > 0) s.brakeLeft = 0;
        want[static_cast<std::size_t>(c)] = s.brakeLeft > 0 ? static_cast<std::uint8_t>(s.brakeAmplitude) : level;
        s.level = level;
    }
    const core::MotorLevels got = guard_.process(want, dt);
    for (int c = 0; c < n; ++c) {
        Channel& s = ch_[static_cast<std::size_t>(c)];
        const std::size_t i = static_cast<std::size_t>(c);
        if (got[i] < want[i]) ++limited_;
        const float scale = gains_.gain[i] / static_cast<float>(kFullScale);
        if (s.brakeLeft > 0) {
            s.brakeAmplitude = static_cast<float>(got[i]);   // levels until it plays, then scaled below
            if (got[i] == 0) s.brakeLeft = 0;
            s.amplitude = 0.0f;
        } else {
            s.amplitude = static_cast<float>(got[i]) * scale;
        }
        s.targetHz = carrierHz(params_, s.level > 0 ? static_cast<double>(got[i]) : 0.0);
        if (params_.model != TactorModel::Erm || params_.ermSpinTime <= 0.0) s.hz = s.targetHz;
    }
}

void TactorRenderer::allOff() noexcept
{
    guard_.allOff();
    mute();
}

void TactorRenderer::mute() noexcept
{
    for (int c = 0; c < map_.channels; ++c) {
        Channel& s = ch_[static_cast<std::size_t>(c)];
        s.amplitude = 0.0f;
        s.brakeLeft = 0;
        s.level = 0;
        s.targetHz = carrierHz(params_, 0.0);
    }
}

void TactorRenderer::renderWithSound(float* const* out, int n) noexcept
{
    constexpr double kFloor = 1.0e-4;   // −80 dBFS: below it the sound is silence
    const double fallbackStep = kTwoPi * params_.voiceCoilHz / sampleRate_;
    for (int done = 0; done < n;) {
        const int len = std::min(kCarrierBlock, n - done);
        for (int i = 0; i < len; ++i) {
            double x = 0.0;
            if (soundLeft_ > 0) {
                x = static_cast<double>(*sound_++);
                --soundLeft_;
                if (!std::isfinite(x)) x = 0.0;
            }
            const double y = lowPass_(highPass_(x));
            envelope_ = std::max(std::abs(y), envelope_ * release_);
            recent_ = std::max(std::abs(y), recent_ * fastRelease_);   // has it just stopped?
            const float fallback = static_cast<float>(std::sin(fallbackPhase_));
            fallbackPhase_ += fallbackStep;
            if (fallbackPhase_ >= kTwoPi) fallbackPhase_ -= kTwoPi;
            double c = recent_ > kFloor ? std::clamp(y / envelope_, -1.0, 1.0) : static_cast<double>(fallback);
            // No more power than a sine of the same peak (mean square ½), whatever the waveform
            // (a band-limited square would carry more): the safety stage's power bound is a
            // sine's, so the signal is held to it (20 ms mean square).
            meanSquare_ += (c * c - meanSquare_) * powerSlew_;
            if (meanSquare_ > 0.5) c *= std::sqrt(0.5 / meanSquare_);
            carrier_[static_cast<std::size_t>(i)] = static_cast<float>(c);
        }
        for (int c = 0; c < map_.channels; ++c) {
            const float a = ch_[static_cast<std::size_t>(c)].amplitude;
            float* o = out[c] + done;
            for (int i = 0; i < len; ++i) o[i] = a * carrier_[static_cast<std::size_t>(i)];
        }
        done += len;
    }
    sound_ = nullptr;
    soundLeft_ = 0;
}

void TactorRenderer::render(float* const* out, int n) noexcept
{
    if (n <= 0) return;
    if (usesSound()) {
        renderWithSound(out, n);
        return;
    }
    const double toStep = kTwoPi / sampleRate_;
    const bool erm = params_.model == TactorModel::Erm;
    for (int c = 0; c < map_.channels; ++c) {
        Channel& s = ch_[static_cast<std::size_t>(c)];
        float* o = out[c];
        const float brake = -s.brakeAmplitude * gains_.gain[static_cast<std::size_t>(c)] / static_cast<float>(kFullScale);
        for (int i = 0; i < n; ++i) {
            const float x = static_cast<float>(std::sin(s.phase));
            if (s.brakeLeft > 0) {
                o[i] = brake * x;   // antiphase
                --s.brakeLeft;
            } else {
                o[i] = s.amplitude * x;
            }
            if (erm) s.hz += (s.targetHz - s.hz) * slew_;
            s.phase += toStep * s.hz;
            if (s.phase >= kTwoPi) s.phase -= kTwoPi;
        }
    }
}

core::AudioBuffer renderTactileRows(const std::vector<core::TactileRow>& rows, TactorRenderer& renderer, const std::vector<float>* sound)
{
    core::AudioBuffer out;
    out.sampleRate = renderer.sampleRate();
    const auto channels = static_cast<std::size_t>(renderer.channels());
    if (rows.empty()) {
        out.channels.assign(channels, {});
        return out;
    }
    const double sr = renderer.sampleRate();
    const double t0 = rows.front().t;
    const double lastHold = rows.size() > 1 ? rows.back().t - rows[rows.size() - 2].t : 0.005;
    const double total = rows.back().t + std::max(0.0, lastHold) - t0;
    const auto frames = static_cast<std::size_t>(std::ceil(total * sr - 1e-9));
    out.channels.assign(channels, std::vector<float>(frames, 0.0f));
    std::array<float*, kMaxChannels> ptr {};
    // Row r starts at the first sample n with t0 + n/sr ≥ t_r (within 1 ns).
    const auto startOf = [&](std::size_t r) {
        const double n = std::ceil((rows[r].t - t0 - 1e-9) * sr);
        return static_cast<std::size_t>(std::clamp(n, 0.0, static_cast<double>(frames)));
    };
    std::size_t at = 0;
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const std::size_t end = r + 1 < rows.size() ? std::max(startOf(r + 1), at) : frames;
        renderer.setLevels(rows[r].levels, r == 0 ? 0.0 : rows[r].t - rows[r - 1].t);
        if (end > at) {
            for (std::size_t c = 0; c < channels; ++c) ptr[c] = out.channels[c].data() + at;
            if (sound != nullptr && at < sound->size())
                renderer.setSound(sound->data() + at, static_cast<int>(std::min(end, sound->size()) - at));
            renderer.render(ptr.data(), static_cast<int>(end - at));
            at = end;
        }
    }
    return out;
}

TactorSetup resolveTactorSetup(std::string_view model, std::string_view mapText, const std::string& gainFile, int motors, int channels)
{
    TactorSetup s;
    if (!parseModel(model, s.params.model))
        throw core::InputError("tactor model", 0, "", "unknown model '" + std::string(model) + "' (one of " + kModelNames + ")");
    s.map = mapText.empty() ? ChannelMap::identity(channels > 0 ? std::min(motors, channels) : motors) : parseChannelMap(mapText, motors);
    if (channels > 0 && s.map.channels > channels)
        throw core::InputError("--tactor-map", 0, "",
                         "the map has " + std::to_string(s.map.channels) + " channels but the output " + std::to_string(channels));
    if (!gainFile.empty()) s.gains = loadTactorGains(gainFile);
    if (s.gains.count > s.map.channels)
        throw core::InputError(s.gains.source, 0, "gain",
                         "the file gives " + std::to_string(s.gains.count) + " gains but the map has " + std::to_string(s.map.channels) + " channels");
    return s;
}

} // namespace armadillo::tactors
