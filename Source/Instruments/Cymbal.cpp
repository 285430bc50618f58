// Cymbal gesture detection and the crash fragment bank (thesis §3.6.1, §3.6.2.1).
#include "Instruments/Cymbal.h"
#include "Instruments/Dsp.h"
#include "Core/Errors.h"
#include <samplerate.h>
#include <algorithm>
#include <cmath>

namespace armadillo::instruments {

void CymbalGesture::setParams(const CymbalGestureParams& p) noexcept
{
    p_ = p;
    inside_.setThresholds(p.surfaceDeg - p.surfaceBandDeg, p.surfaceDeg + p.surfaceBandDeg);
}

void CymbalGesture::reset() noexcept
{
    inside_.reset(false);
    armed_ = false;
    havePrevious_ = false;
    peakDownSpeed_ = 0.0;
}

CymbalGesture::Result CymbalGesture::update(double elevationDeg, double dt) noexcept
{
    Result r;
    if (!std::isfinite(elevationDeg)) {
        r.inside = inside_.on();
        return r;
    }
    if (!havePrevious_) {
        // First sample: take the side we are on without an event (entering the scene is no touch).
        inside_.reset(elevationDeg < p_.surfaceDeg);
        havePrevious_ = true;
        previousDeg_ = elevationDeg;
        armed_ = elevationDeg > p_.surfaceDeg + p_.armDeg;
        r.inside = inside_.on();
        return r;
    }
    // A repeated timestamp (dt = 0) carries no speed: keep the previous estimate rather than
    // dividing a jump by nothing.
    const bool timed = dt > 1e-5;
    const double step = timed ? dt : 1e-5;
    const double downSpeed = timed ? (previousDeg_ - elevationDeg) / step : 0.0;   // deg/s, + when falling
    previousDeg_ = elevationDeg;
    // Peak hold: the speed at the crossing is the fastest recent fall, so one slow sample
    // right at the surface (sensor noise, a filter's lag) does not turn a strike into a touch.
    const double hold = std::exp(-step / std::max(p_.speedHoldS, 1e-3));
    peakDownSpeed_ = std::max(std::max(downSpeed, 0.0), peakDownSpeed_ * hold);

    if (elevationDeg > p_.surfaceDeg + p_.armDeg) armed_ = true;
    const bool wasInside = inside_.on();
    const bool nowInside = inside_.update(elevationDeg);
    if (nowInside && !wasInside) {
        r.speedDegPerS = std::max(peakDownSpeed_, downSpeed);
        r.event = (armed_ && r.speedDegPerS >= p_.strikeSpeedDegPerS) ? Event::Strike : Event::Touch;
        armed_ = false;
    }
    r.inside = nowInside;
    return r;
}

double cymbalStrikeGain(double speedDegPerS, double strikeSpeedDegPerS) noexcept
{
    constexpr double kFullSpeedFactor = 4.0;   // 4× the slowest strike speed is full loudness
    const double lo = std::max(strikeSpeedDegPerS, 1.0);
    const double x = std::clamp((speedDegPerS - lo) / (lo * (kFullSpeedFactor - 1.0)), 0.0, 1.0);
    return 0.35 + 0.65 * x;
}

namespace {

void normaliseRms(std::vector<float>& v, double targetRms)
{
    double sum = 0.0;
    for (float x : v) sum += static_cast<double>(x) * static_cast<double>(x);
    const double rms = v.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(v.size()));
    if (rms < 1e-12) return;
    const auto g = static_cast<float>(targetRms / rms);
    for (float& x : v) x *= g;
}

constexpr double kFragmentRms = 0.25;

/// One fragment; brightness 0 = low wind-like gusts, 1 = high glass-like shimmer with pings.
std::vector<float> noiseFragment(double fs, double brightness, dsp::Random& rng)
{
    const auto n = static_cast<std::size_t>(CrashBank::kFragmentSeconds * fs);
    std::vector<float> out(n);
    const double nyquistGuard = 0.45 * fs;
    // Two band-passes whose centres drift: the wind "howls", the glass "glints".
    const double centre = std::min(150.0 * std::exp2(brightness * 6.3), nyquistGuard);
    const double q = 0.8 + 2.5 * brightness;
    dsp::StateVariableFilter bandA, bandB, highPass;
    highPass.setup(std::min(400.0 + 3000.0 * brightness, nyquistGuard), 0.7, fs);
    const double driftRateHz = rng.uniform(0.15, 0.6);
    const double driftPhase = rng.uniform();
    const double gustRateHz = rng.uniform(0.3, 1.2);
    const double gustPhase = rng.uniform();
    const double detune = rng.uniform(1.3, 1.9);
    double gust = 1.0;
    for (std::size_t i = 0; i < n; ++i) {
        if ((i & 63) == 0) {   // re-tune every 64 samples (1.3 ms): the drift and gusts are slow
            const double t = static_cast<double>(i) / fs;
            const double drift = std::exp2(0.5 * std::sin(dsp::kTwoPi * (driftRateHz * t + driftPhase)));
            bandA.setup(std::min(centre * drift, nyquistGuard), q, fs);
            bandB.setup(std::min(centre * detune / drift, nyquistGuard), q, fs);
            // Low fragments gust (slow amplitude swell); high ones stay even.
            gust = 1.0 - (1.0 - brightness) * 0.6 * (0.5 + 0.5 * std::sin(dsp::kTwoPi * (gustRateHz * t + gustPhase)));
        }
        const double white = rng.bipolar();
        const double band = bandA.process(white).band + 0.7 * bandB.process(white).band;
        const double hiss = highPass.process(white).high;
        out[i] = static_cast<float>(gust * (band + (0.15 + 0.5 * brightness) * hiss));
    }
    // Glass: sparse decaying high partials, more and brighter as brightness rises.
    const int pings = static_cast<int>(brightness * brightness * 60.0);
    for (int k = 0; k < pings; ++k) {
        const double f = std::min(rng.uniform(2000.0, 2000.0 + 8000.0 * brightness), nyquistGuard);
        const double decayS = rng.uniform(0.03, 0.15);
        const auto start = static_cast<std::size_t>(rng.uniform() * static_cast<double>(n));
        const double amp = rng.uniform(0.2, 0.8);
        const auto len = std::min(n - start, static_cast<std::size_t>(decayS * 6.0 * fs));
        const double phase = rng.uniform();
        // A decaying sinusoid as a rotating, shrinking phasor: one complex multiply per sample.
        const double w = dsp::kTwoPi * f / fs, shrink = std::exp(-1.0 / (decayS * fs));
        const double stepRe = shrink * std::cos(w), stepIm = shrink * std::sin(w);
        double re = amp * std::cos(dsp::kTwoPi * phase), im = amp * std::sin(dsp::kTwoPi * phase);
        for (std::size_t j = 0; j < len; ++j) {
            out[start + j] += static_cast<float>(im);
            const double nextRe = re * stepRe - im * stepIm;
            im = re * stepIm + im * stepRe;
            re = nextRe;
        }
    }
    normaliseRms(out, kFragmentRms);
    return out;
}

} // namespace

CrashBank buildCrashBank(double sampleRateHz, std::uint64_t seed, int fragmentCount)
{
    CrashBank bank;
    bank.sampleRate = sampleRateHz;
    dsp::Random rng(seed * 0x2545F4914F6CDD1Dull + 17);
    const int count = std::max(fragmentCount, 2);
    for (int i = 0; i < count; ++i)
        bank.fragments.push_back(noiseFragment(sampleRateHz, static_cast<double>(i) / (count - 1), rng));
    return bank;
}

std::vector<float> prepareUserAudio(const core::AudioBuffer& audio, double sampleRateHz)
{
    std::vector<float> out;
    const std::size_t frames = audio.frames();
    if (frames < 2 || audio.channels.empty() || !(audio.sampleRate > 0.0)) return out;
    std::vector<float> mono(frames, 0.0f);
    const auto channelGain = 1.0f / static_cast<float>(audio.channels.size());
    for (const auto& ch : audio.channels)
        for (std::size_t i = 0; i < frames && i < ch.size(); ++i) mono[i] += channelGain * (std::isfinite(ch[i]) ? ch[i] : 0.0f);
    if (std::abs(audio.sampleRate - sampleRateHz) < 1e-9) {
        out = std::move(mono);
    } else {
        // Band-limited resampling (libsamplerate's sinc converter): a 96 kHz recording played at
        // 48 kHz loses what lies above 24 kHz instead of folding it back as audible aliases, as
        // linear interpolation did. Not real-time: prepare() runs on the message thread.
        SRC_DATA d {};
        d.src_ratio = sampleRateHz / audio.sampleRate;   // output samples per input sample
        out.resize(static_cast<std::size_t>(std::ceil(static_cast<double>(frames) * d.src_ratio)) + 1);
        d.data_in = mono.data();
        d.input_frames = static_cast<long>(frames);
        d.data_out = out.data();
        d.output_frames = static_cast<long>(out.size());
        const int error = src_simple(&d, SRC_SINC_MEDIUM_QUALITY, 1);
        if (error != 0) throw core::InputError("", 0, "", std::string("cannot resample the recording: ") + src_strerror(error));
        out.resize(static_cast<std::size_t>(d.output_frames_gen));
    }
    normaliseRms(out, kFragmentRms);
    return out;
}

} // namespace armadillo::instruments
