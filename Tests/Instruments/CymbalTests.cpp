// The virtual crash cymbal through the Scene API (thesis §3.6): gestures on scripted motions,
// crashes and damping measured on the rendered samples, the tactile environment on the canvas.
#include "Core/Wav.h"
#include "Instruments/Cymbal.h"
#include "Instruments/Scenes.h"
#include "SceneHarness.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
using namespace armadillo::instruments;
using namespace armadillo::test;

namespace {

/// Raise the arm to +30°, pause, then bring it down to −20° at `speedDegPerS`.
void strikeAt(SceneHarness& h, double speedDegPerS, double azimuth = 0.0)
{
    const Pose up {30.0, azimuth, 0.0}, down {-20.0, azimuth, 0.0};
    h.move(h.lastPose, up, 0.3);
    h.hold(up, 0.1);
    h.move(up, down, 50.0 / speedDegPerS);
}

/// Lift gently out of the cymbal to +8° and lower back through the surface at 15°/s.
void gentleTouch(SceneHarness& h)
{
    const Pose above {8.0, h.lastPose.azimuthDeg, 0.0}, below {-5.0, h.lastPose.azimuthDeg, 0.0};
    h.move(h.lastPose, above, 0.5);
    h.move(above, below, 13.0 / 15.0);
}

/// Short-time RMS envelope in dB (50 ms windows, stereo sum).
std::vector<double> envelopeDb(const RenderedAudio& a, double windowS = 0.05)
{
    const auto w = static_cast<std::size_t>(windowS * a.sampleRate);
    std::vector<double> out;
    for (std::size_t i = 0; i + w <= a.left.size(); i += w) {
        const double r = std::hypot(rms(a.left, i, i + w), rms(a.right, i, i + w));
        out.push_back(20.0 * std::log10(r + 1e-12));
    }
    return out;
}

/// Seconds from `startS` until the envelope stays 40 dB below its peak after `startS`.
double decayTime40(const RenderedAudio& a, double startS)
{
    const auto env = envelopeDb(a);
    const auto first = static_cast<std::size_t>(startS / 0.05);
    double peak = -300.0;
    for (std::size_t i = first; i < env.size(); ++i) peak = std::max(peak, env[i]);
    std::size_t lastLoud = first;
    for (std::size_t i = first; i < env.size(); ++i)
        if (env[i] > peak - 40.0) lastLoud = i;
    return (static_cast<double>(lastLoud + 1) - static_cast<double>(first)) * 0.05;
}

/// Normalised correlation of two equally long stretches (max over lags up to ±maxLag samples).
double maxCorrelation(const std::vector<float>& x, std::size_t a, const std::vector<float>& y, std::size_t b, std::size_t n, int maxLag)
{
    double best = 0.0;
    for (int lag = -maxLag; lag <= maxLag; lag += 1) {
        double sxy = 0, sxx = 0, syy = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double u = x[a + i];
            const auto j = static_cast<std::ptrdiff_t>(b + i) + lag;
            const double v = y[static_cast<std::size_t>(j)];
            sxy += u * v;
            sxx += u * u;
            syy += v * v;
        }
        best = std::max(best, std::fabs(sxy) / std::sqrt(sxx * syy + 1e-30));
    }
    return best;
}

} // namespace

TEST_CASE("a fast downward stroke from above strikes: crash, jolt and a strike event", "[cymbal]")
{
    SceneHarness h(makeCymbalScene());
    h.hold({30.0, 0.0, 0.0}, 0.2);
    REQUIRE(rms(h.audio.left, 0, h.audio.left.size()) == 0.0);
    strikeAt(h, 400.0);
    h.hold({-20.0, 0.0, 0.0}, 1.0);

    REQUIRE(h.events.count("strike") == 1);
    CHECK(h.events.events.front().value == Approx(400.0).epsilon(0.1));   // the speed, deg/s
    const auto jolts = h.canvas.triggers(PatternKind::Jolt);
    REQUIRE(jolts.size() == 1);
    CHECK(jolts[0].t == Approx(h.events.events.front().t));
    // Sound from the strike on, none before it.
    const std::size_t at = h.audio.sampleAt(h.events.events.front().t);
    CHECK(rms(h.audio.left, 0, at) == 0.0);
    CHECK(rms(h.audio.left, at, at + 24000) > 0.02);
}

TEST_CASE("gentle touches, slow descents and strokes that never rose above do not strike", "[cymbal]")
{
    SceneHarness h(makeCymbalScene());
    h.hold({30.0, 0.0, 0.0}, 0.2);
    h.move({30.0, 0.0, 0.0}, {-20.0, 0.0, 0.0}, 50.0 / 40.0);   // 40 °/s: a slow lowering
    h.hold({-20.0, 0.0, 0.0}, 0.2);
    gentleTouch(h);
    // Hovering just above the surface (+3°, under the 5° arming height), then a fast drop.
    h.move(h.lastPose, {3.0, 0.0, 0.0}, 0.5);
    h.hold({3.0, 0.0, 0.0}, 0.2);
    h.move({3.0, 0.0, 0.0}, {-20.0, 0.0, 0.0}, 0.05);
    h.hold({-20.0, 0.0, 0.0}, 0.5);
    CHECK(h.events.count("strike") == 0);
    CHECK(h.canvas.triggers(PatternKind::Jolt).empty());
    CHECK(rms(h.audio.left, 0, h.audio.left.size()) == 0.0);
    // Nothing was ringing, so nothing was damped either.
    CHECK(h.events.count("damp") == 0);
}

TEST_CASE("the strike threshold is a parameter and loudness follows speed", "[cymbal]")
{
    auto loudness = [](double speed) {
        SceneHarness h(makeCymbalScene(), 7);
        h.hold({30.0, 0.0, 0.0}, 0.1);
        strikeAt(h, speed);
        const std::size_t at = h.audio.left.size();
        h.hold({-20.0, 0.0, 0.0}, 0.5);
        return std::make_pair(h.events.count("strike"), rms(h.audio.left, at - 2400, h.audio.left.size()));
    };
    const auto slow = loudness(180.0), fast = loudness(700.0);
    {
        // The hardest strike at the default level stays below full scale (the engine would clip).
        SceneHarness h(makeCymbalScene(), 7);
        h.hold({30.0, 0.0, 0.0}, 0.1);
        strikeAt(h, 2000.0);
        h.hold({-20.0, 0.0, 0.0}, 1.0);
        float peak = 0.0f;
        for (std::size_t i = 0; i < h.audio.left.size(); ++i)
            peak = std::max({peak, std::fabs(h.audio.left[i]), std::fabs(h.audio.right[i])});
        INFO("peak " << peak);
        CHECK(peak < 0.95f);
        CHECK(peak > 0.2f);
    }
    REQUIRE(slow.first == 1);
    REQUIRE(fast.first == 1);
    // Same seed, same fragments: only the speed differs.
    CHECK(dB(fast.second / slow.second) > 4.0);

    SceneHarness h(makeCymbalScene());
    h.set("cymbal.strikeSpeed", 500.0f);
    h.hold({30.0, 0.0, 0.0}, 0.1);
    strikeAt(h, 300.0);
    CHECK(h.events.count("strike") == 0);
    strikeAt(h, 800.0);
    CHECK(h.events.count("strike") == 1);
}

TEST_CASE("every crash is different, and the same seed renders the same", "[cymbal]")
{
    auto render = [](std::uint64_t seed) {
        SceneHarness h(makeCymbalScene(), seed);
        h.hold({30.0, 0.0, 0.0}, 0.1);
        std::vector<double> strikes;
        for (int i = 0; i < 3; ++i) {
            strikeAt(h, 400.0);
            strikes.push_back(h.events.events.back().t);
            h.hold({-20.0, 0.0, 0.0}, 1.2);
        }
        REQUIRE(h.events.count("strike") == 3);
        return std::make_pair(h.audio, strikes);
    };
    const auto [a, times] = render(11);
    // Compare 200 ms from 50 ms after each onset: fragments, offsets and rates all differ.
    const std::size_t n = 9600;
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j) {
            const double c = maxCorrelation(a.left, a.sampleAt(times[static_cast<std::size_t>(i)] + 0.05), a.left,
                                            a.sampleAt(times[static_cast<std::size_t>(j)] + 0.05), n, 48);
            INFO("crash " << i << " vs " << j << ": correlation " << c);
            CHECK(c < 0.3);
        }
    const auto [b, timesB] = render(11);
    CHECK(a.left == b.left);
    CHECK(a.right == b.right);
    const auto [c, timesC] = render(12);
    CHECK(maxCorrelation(a.left, a.sampleAt(times[0] + 0.05), c.left, c.sampleAt(timesC[0] + 0.05), n, 48) < 0.3);
    // (and a stretch correlated with itself reads 1: the measure can fail)
    CHECK(maxCorrelation(a.left, a.sampleAt(times[0] + 0.05), b.left, b.sampleAt(timesB[0] + 0.05), n, 48) > 0.999);
}

TEST_CASE("a gentle touch while it rings damps it: sound and a soft vibration fade together", "[cymbal]")
{
    auto render = [](bool touch) {
        SceneHarness h(makeCymbalScene(), 3);
        h.hold({30.0, 0.0, 0.0}, 0.1);
        strikeAt(h, 400.0);
        const double strikeT = h.events.events.back().t;
        h.hold({-20.0, 0.0, 0.0}, 1.0);
        if (touch) gentleTouch(h);
        else h.hold({-5.0, 0.0, 0.0}, 1.0 + 13.0 / 15.0);   // same duration, still inside
        const double touchT = h.time();
        h.hold({-5.0, 0.0, 0.0}, 6.0);
        return std::make_tuple(std::move(h), strikeT, touchT);
    };
    auto [ringing, strikeA, touchA] = render(false);
    auto [damped, strikeB, touchB] = render(true);
    REQUIRE(damped.events.count("strike") == 1);
    REQUIRE(damped.events.count("damp") == 1);
    CHECK(ringing.events.count("damp") == 0);

    const double decayRinging = decayTime40(ringing.audio, strikeA);
    const double decayDamped = decayTime40(damped.audio, strikeB);
    INFO("decay to -40 dB: ringing " << decayRinging << " s, damped " << decayDamped << " s");
    CHECK(decayDamped < touchB - strikeB + 0.6);   // gone within the damping time (0.4 s) after the touch
    CHECK(decayDamped < 0.5 * decayRinging);

    // 0.5 s after the touch the damped one is at least 40 dB quieter than the undamped.
    const auto from = ringing.audio.sampleAt(touchA + 0.5), to = ringing.audio.sampleAt(touchA + 2.5);
    CHECK(dB(rms(damped.audio.left, from, to) / rms(ringing.audio.left, from, to)) < -40.0);

    // The soft vibration: a fade-out pulse on every grid motor, as long as the sound's fade.
    const auto fades = damped.canvas.triggers(PatternKind::FadeOutPulse);
    REQUIRE(fades.size() == 1);
    CHECK(fades[0].request.motors == 0x01FF);
    CHECK(fades[0].request.level <= 5.0f);
    CHECK(fades[0].request.duration == Approx(0.4).margin(1e-6));
}

TEST_CASE("inside the cymbal: idle vibration, |ω| on the leading side, the gear pull moving up", "[cymbal][tactile]")
{
    SceneHarness h(makeCymbalScene());
    h.hold({30.0, 0.0, 0.0}, 0.1);
    for (int m = 0; m < kGridMotors; ++m) CHECK(h.canvas.levels[static_cast<std::size_t>(m)] == 0.0f);   // above: nothing
    h.move({30.0, 0.0, 0.0}, {-30.0, 0.0, 0.0}, 1.0);   // slow: no strike
    h.hold({-30.0, 0.0, 0.0}, 0.3);
    for (int m = 0; m < kGridMotors; ++m) CHECK(h.canvas.levels[static_cast<std::size_t>(m)] == Approx(1.0f));   // idle

    auto strongest = [&] {
        int best = 0;
        for (int m = 1; m < kGridMotors; ++m)
            if (h.canvas.levels[static_cast<std::size_t>(m)] > h.canvas.levels[static_cast<std::size_t>(best)]) best = m;
        return best;
    };
    // Palm down, sweeping left (azimuth decreasing): the thumb leads → left column (right arm).
    h.move({-30.0, 0.0, 0.0}, {-30.0, -40.0, 0.0}, 0.4);   // 100 °/s = 1.75 rad/s
    CHECK(strongest() == motorIndex(1, 0));
    const float thumbLevel = h.canvas.levels[static_cast<std::size_t>(motorIndex(1, 0))];
    CHECK(thumbLevel == Approx(1.0 + 3.0 * degToRad(100.0)).epsilon(0.05));   // idle + 3 levels per rad/s
    // Sweeping right: the fifth finger leads → right column.
    h.move({-30.0, -40.0, 0.0}, {-30.0, 20.0, 0.0}, 0.4);
    CHECK(strongest() == motorIndex(1, 2));
    // Faster movement, stronger vibration.
    h.move({-30.0, 20.0, 0.0}, {-30.0, 80.0, 0.0}, 0.2);
    CHECK(h.canvas.levels[static_cast<std::size_t>(motorIndex(1, 2))] > thumbLevel + 1.5f);
    // Pitching down: the palm leads → underside column.
    h.move({-30.0, 80.0, 0.0}, {-60.0, 80.0, 0.0}, 0.3);
    CHECK(strongest() == motorIndex(1, 1));
    // Moving up inside: the pulling alternation.
    const std::size_t before = h.canvas.triggers(PatternKind::GearPull).size();
    h.move({-60.0, 80.0, 0.0}, {-30.0, 80.0, 0.0}, 0.3);
    CHECK(h.canvas.triggers(PatternKind::GearPull).size() > before);
    // Still again: the gear pull stops, idle stays.
    h.hold({-30.0, 80.0, 0.0}, 0.3);
    bool stopped = false;
    for (const auto& c : h.canvas.calls)
        if (c.kind == RecordingCanvas::Call::Stop && c.t > h.time() - 0.3) stopped = true;
    CHECK(stopped);
    // Leaving the cymbal upward: every motor off.
    h.move({-30.0, 80.0, 0.0}, {20.0, 80.0, 0.0}, 1.0);
    for (int m = 0; m < kGridMotors; ++m) CHECK(h.canvas.levels[static_cast<std::size_t>(m)] == 0.0f);
    CHECK(h.events.count("strike") == 0);
}

TEST_CASE("the side choice agrees with the fusion module's leading side", "[cymbal][tactile]")
{
    // For each movement, the column the scene vibrates must be the one Fusion's leadingSide names.
    struct Case {
        Pose from, to;
        FluxSide side;
    };
    const std::vector<Case> cases {
        {{-30.0, 0.0, 0.0}, {-30.0, -30.0, 0.0}, FluxSide::Thumb},
        {{-30.0, 0.0, 0.0}, {-30.0, 30.0, 0.0}, FluxSide::FifthFinger},
        {{-30.0, 0.0, 0.0}, {-50.0, 0.0, 0.0}, FluxSide::Palm},
        {{-30.0, 0.0, 180.0}, {-30.0, -30.0, 180.0}, FluxSide::FifthFinger},   // palm up: reversed
    };
    for (const auto& c : cases) {
        SceneHarness h(makeCymbalScene());
        h.hold(c.from, 0.2);
        h.move(c.from, c.to, 0.25);
        const Eigen::Quaterniond q0 = poseToQuaternion({c.to.elevationDeg - (c.to.elevationDeg - c.from.elevationDeg) / 50.0,
                                                        c.to.azimuthDeg - (c.to.azimuthDeg - c.from.azimuthDeg) / 50.0, c.to.rollDeg});
        const ArmState last = armStateFromPose(c.to, &q0, 0.005, 0.0);
        REQUIRE(leadingSide(last.features) == c.side);
        const int column = c.side == FluxSide::Thumb ? 0 : c.side == FluxSide::Palm ? 1 : 2;
        int best = 0;
        for (int m = 1; m < kGridMotors; ++m)
            if (h.canvas.levels[static_cast<std::size_t>(m)] > h.canvas.levels[static_cast<std::size_t>(best)]) best = m;
        CHECK(best == motorIndex(1, column));
    }
}

TEST_CASE("movement inside the cymbal modulates the FM tail", "[cymbal]")
{
    // Brightness = energy of the first difference relative to the signal's: more FM sidebands,
    // more high-frequency energy.
    auto tailBrightness = [](bool moving) {
        SceneHarness h(makeCymbalScene(), 5);
        h.hold({30.0, 0.0, 0.0}, 0.1);
        strikeAt(h, 400.0);
        h.hold({-20.0, 0.0, 0.0}, 4.5);   // the crash is over: only the tail sounds
        const std::size_t from = h.audio.left.size();
        if (moving) {
            for (int i = 0; i < 4; ++i) {
                h.move({-20.0, 0.0, 0.0}, {-20.0, 60.0, 0.0}, 0.25);
                h.move({-20.0, 60.0, 0.0}, {-20.0, 0.0, 0.0}, 0.25);
            }
        } else {
            h.hold({-20.0, 0.0, 0.0}, 2.0);
        }
        const std::size_t to = h.audio.left.size();
        double d = 0.0, e = 0.0;
        for (std::size_t i = from + 1; i < to; ++i) {
            const double diff = static_cast<double>(h.audio.left[i]) - static_cast<double>(h.audio.left[i - 1]);
            d += diff * diff;
            e += static_cast<double>(h.audio.left[i]) * static_cast<double>(h.audio.left[i]);
        }
        REQUIRE(e > 0.0);
        return d / e;
    };
    const double still = tailBrightness(false), moving = tailBrightness(true);
    INFO("brightness still " << still << ", moving " << moving);
    CHECK(moving > 1.5 * still);
}

TEST_CASE("a user recording is cut into the crashes", "[cymbal]")
{
    // A 1 kHz tone at 44.1 kHz as the "recording": with the user share at 100% every crash
    // carries it, and without the file no crash does.
    AudioBuffer tone;
    tone.sampleRate = 44100.0;
    tone.channels.assign(2, std::vector<float>(static_cast<std::size_t>(44100 * 12)));
    for (std::size_t i = 0; i < tone.channels[0].size(); ++i)
        tone.channels[0][i] = tone.channels[1][i] = static_cast<float>(0.5 * std::sin(2.0 * kPi * 1000.0 * static_cast<double>(i) / 44100.0));
    const auto path = std::filesystem::temp_directory_path() / "armadillo_instruments_user.wav";
    writeWav(path.string(), tone);

    auto toneShare = [&](bool withFile) {
        auto cymbal = makeCymbalInstrument();
        if (withFile) cymbal->loadUserAudio(path.string());
        SceneHarness h(std::move(cymbal), 9);
        h.set("cymbal.fileMix", 100.0f);
        h.hold({30.0, 0.0, 0.0}, 0.1);
        strikeAt(h, 400.0);
        const std::size_t from = h.audio.left.size();
        h.hold({-20.0, 0.0, 0.0}, 0.5);
        // Goertzel-style correlation with 1 kHz, relative to the total energy.
        double c = 0.0, s = 0.0, e = 0.0;
        for (std::size_t i = from; i < h.audio.left.size(); ++i) {
            const double x = h.audio.left[i] + h.audio.right[i];
            const double ph = 2.0 * kPi * 1000.0 * static_cast<double>(i) / 48000.0;
            c += x * std::cos(ph);
            s += x * std::sin(ph);
            e += x * x;
        }
        const double n = static_cast<double>(h.audio.left.size() - from);
        return 2.0 * (c * c + s * s) / n / e;   // share of the energy at 1 kHz
    };
    const double with = toneShare(true), without = toneShare(false);
    INFO("1 kHz share with file " << with << ", without " << without);
    CHECK(with > 0.1);
    CHECK(without < 0.01);
    std::filesystem::remove(path);
}

TEST_CASE("strike gesture detector: strike, touch and the first sample", "[cymbal]")
{
    CymbalGesture g;
    g.setParams(kDefaultCymbalGesture);
    // Starting inside is no event.
    CHECK(g.update(-10.0, 0.005).event == CymbalGesture::Event::None);
    CHECK(g.inside());
    // Out and back in slowly: a touch.
    for (double e = -10.0; e <= 10.0; e += 0.1) g.update(e, 0.005);
    CymbalGesture::Result r;
    bool touched = false;
    for (double e = 10.0; e >= -10.0; e -= 0.1) {
        r = g.update(e, 0.005);
        touched = touched || r.event == CymbalGesture::Event::Touch;
        CHECK(r.event != CymbalGesture::Event::Strike);
    }
    CHECK(touched);
    // Out and back in fast: a strike with its speed.
    for (double e = -10.0; e <= 20.0; e += 0.5) g.update(e, 0.005);
    bool struck = false;
    for (double e = 20.0; e >= -10.0; e -= 2.0) {
        r = g.update(e, 0.005);
        if (r.event == CymbalGesture::Event::Strike) {
            struck = true;
            CHECK(r.speedDegPerS == Approx(400.0).epsilon(0.01));
        }
    }
    CHECK(struck);
    // A repeated timestamp (dt = 0) with a jump is no strike.
    CymbalGesture g2;
    g2.setParams(kDefaultCymbalGesture);
    g2.update(20.0, 0.005);
    g2.update(20.0, 0.005);
    CHECK(g2.update(-10.0, 0.0).event == CymbalGesture::Event::Touch);
    // Loudness rises with speed from a floor to 1.
    CHECK(cymbalStrikeGain(150.0, 150.0) == Approx(0.35));
    CHECK(cymbalStrikeGain(300.0, 150.0) > cymbalStrikeGain(200.0, 150.0));
    CHECK(cymbalStrikeGain(5000.0, 150.0) == Approx(1.0));
}

TEST_CASE("a 96 kHz recording is resampled without aliasing (libsamplerate)", "[cymbal]")
{
    // 1 kHz plus 30 kHz, equal amplitude, at 96 kHz. At 48 kHz the 30 kHz tone cannot exist:
    // a band-limited resampler removes it; linear interpolation (the old way) folds it to
    // 48 − 30 = 18 kHz at a level close to the 1 kHz tone's.
    AudioBuffer rec;
    rec.sampleRate = 96000.0;
    rec.channels.assign(1, std::vector<float>(96000));
    for (std::size_t i = 0; i < rec.channels[0].size(); ++i) {
        const double t = static_cast<double>(i) / 96000.0;
        rec.channels[0][i] = static_cast<float>(0.4 * std::sin(2.0 * kPi * 1000.0 * t) + 0.4 * std::sin(2.0 * kPi * 30000.0 * t));
    }
    const std::vector<float> out = prepareUserAudio(rec, 48000.0);
    CHECK(static_cast<double>(out.size()) == Approx(48000.0).margin(2.0));   // the same second at the new rate
    auto amplitude = [&](double hz) {
        double c = 0.0, s = 0.0;
        const std::size_t from = 2000, to = out.size() - 2000;   // away from the filter's edges
        for (std::size_t i = from; i < to; ++i) {
            const double ph = 2.0 * kPi * hz * static_cast<double>(i) / 48000.0;
            c += static_cast<double>(out[i]) * std::cos(ph);
            s += static_cast<double>(out[i]) * std::sin(ph);
        }
        return 2.0 * std::sqrt(c * c + s * s) / static_cast<double>(to - from);
    };
    const double wanted = amplitude(1000.0), alias = amplitude(18000.0);
    INFO("1 kHz amplitude " << wanted << ", 18 kHz alias " << alias);
    CHECK(wanted > 0.1);
    CHECK(alias < wanted * 1e-3);   // below −60 dB
}
