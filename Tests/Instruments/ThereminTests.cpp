// The fretted theremin through the Scene API: pitch and level measured on the rendered samples,
// frets measured on the recorded motor calls (thesis §3.5).
#include "Instruments/Frets.h"
#include "Instruments/Scenes.h"
#include "Instruments/Theremin.h"
#include "SceneHarness.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::instruments;
using namespace armadillo::test;

namespace {

/// The formula of the issue, written out independently of the scene's code: e linear in
/// sin(elevation), bottom → 0 semitones, top → range; f = base·2^(e/12).
double expectedHz(double elevationDeg, double base = 220.0, double range = 12.0, double bottom = -45.0, double top = 45.0)
{
    const double y = std::sin(elevationDeg * kPi / 180.0);
    const double y0 = std::sin(bottom * kPi / 180.0), y1 = std::sin(top * kPi / 180.0);
    return base * std::pow(2.0, range * (y - y0) / (y1 - y0) / 12.0);
}

/// Inverse: the elevation that sounds `hz`.
double elevationFor(double hz, double base = 220.0, double range = 12.0)
{
    const double y0 = std::sin(-kPi / 4.0), y1 = std::sin(kPi / 4.0);
    const double e = 12.0 * std::log2(hz / base);
    return std::asin(y0 + e / range * (y1 - y0)) * 180.0 / kPi;
}

double measureHeldPitch(SceneHarness& h, const Pose& pose)
{
    h.hold(pose, 0.3);   // settle: glide is 20 ms
    const std::size_t from = h.audio.left.size();
    h.hold(pose, 0.5);
    return estimateFrequency(h.audio.left, from, h.audio.left.size(), h.audio.sampleRate);
}

} // namespace

TEST_CASE("theremin pitch at held elevations is within 5 cents of f = 220·2^(e/12)", "[theremin]")
{
    SceneHarness h(makeThereminScene());
    REQUIRE(h.scene().producesAudio());
    for (double el : {-45.0, -30.0, -10.0, 0.0, 12.5, 30.0, 45.0, 60.0}) {
        const double f = measureHeldPitch(h, {el, 0.0, 0.0});
        INFO("elevation " << el << " measured " << f << " Hz, formula " << expectedHz(el));
        CHECK(std::fabs(cents(f, expectedHz(el))) < 5.0);
    }
    // The two anchor points the design card names.
    CHECK(std::fabs(cents(measureHeldPitch(h, {-45.0, 0.0, 0.0}), 220.0)) < 5.0);
    CHECK(std::fabs(cents(measureHeldPitch(h, {45.0, 0.0, 0.0}), 440.0)) < 5.0);
}

TEST_CASE("theremin base, range and elevation span are parameters", "[theremin]")
{
    SceneHarness h(makeThereminScene());
    h.set("theremin.base", 110.0f);
    h.set("theremin.range", 24.0f);
    for (double el : {-45.0, 0.0, 30.0, 45.0}) {
        const double f = measureHeldPitch(h, {el, 0.0, 0.0});
        INFO("elevation " << el << " measured " << f);
        CHECK(std::fabs(cents(f, expectedHz(el, 110.0, 24.0))) < 5.0);
    }
    h.set("theremin.bottom", -30.0f);
    h.set("theremin.top", 60.0f);
    const double f = measureHeldPitch(h, {10.0, 0.0, 0.0});
    CHECK(std::fabs(cents(f, expectedHz(10.0, 110.0, 24.0, -30.0, 60.0))) < 5.0);
}

TEST_CASE("theremin level follows azimuth: full where entered, silent 60 degrees either side", "[theremin]")
{
    SceneHarness h(makeThereminScene());
    const double entry = 350.0;   // across north: the wrap must not matter
    const double level = 0.5;     // theremin.level default
    std::vector<std::pair<double, double>> measured;
    for (double offset : {0.0, 15.0, -15.0, 30.0, -30.0, 45.0, -50.0, 59.0, 60.0, 75.0, -120.0}) {
        h.hold({0.0, entry + offset, 0.0}, 0.1);
        const std::size_t from = h.audio.left.size();
        h.hold({0.0, entry + offset, 0.0}, 0.2);
        const double r = rms(h.audio.left, from, h.audio.left.size());
        const double expected = level * thereminVolume(offset, 60.0) / std::sqrt(2.0);
        INFO("azimuth offset " << offset << ": rms " << r << ", expected " << expected);
        CHECK(std::fabs(r - expected) < 0.01 * level + 1e-4);
        measured.emplace_back(std::fabs(offset), r);
    }
    // Monotonic: farther from the entry heading is never louder.
    for (const auto& a : measured)
        for (const auto& b : measured)
            if (a.first < b.first) CHECK(a.second >= b.second - 1e-4);
    // The width is a parameter.
    h.set("theremin.volumeWidth", 30.0f);
    h.hold({0.0, entry + 30.0, 0.0}, 0.1);
    const std::size_t from = h.audio.left.size();
    h.hold({0.0, entry + 30.0, 0.0}, 0.2);
    CHECK(rms(h.audio.left, from, h.audio.left.size()) < 1e-4);
}

TEST_CASE("a slow sweep up and down makes each fret motor take over once per crossing at the ±1% frets", "[theremin][frets]")
{
    SceneHarness h(makeThereminScene());
    // A major from A3: A B C# D E F# G# A, in Hz (equal temperament, exact).
    std::vector<double> notes;
    for (int semis : {0, 2, 4, 5, 7, 9, 11, 12}) notes.push_back(220.0 * std::exp2(semis / 12.0));
    const std::vector<int> motors {motorIndex(2, 0), motorIndex(2, 1), motorIndex(2, 2), motorIndex(1, 0),
                                   motorIndex(1, 1), motorIndex(1, 2), motorIndex(0, 0), motorIndex(0, 1)};
    struct Takeover {
        int motor;
        double hz;      ///< controller frequency at the update that switched
        double prevHz;  ///< at the update before
    };
    std::vector<Takeover> up, down;
    double prevHz = 0.0;
    auto sweep = [&](double from, double to, std::vector<Takeover>& out) {
        const double rate = 8.0;   // deg/s: slow, 0.04° per control update
        const int n = static_cast<int>(std::fabs(to - from) / rate * SceneHarness::kControlRate);
        for (int i = 0; i <= n; ++i) {
            const double el = from + (to - from) * i / n;
            const std::size_t before = h.canvas.calls.size();
            h.step({el, 0.0, 0.0});
            const double hz = expectedHz(el);
            for (std::size_t c = before; c < h.canvas.calls.size(); ++c) {
                const auto& call = h.canvas.calls[c];
                if (call.kind == RecordingCanvas::Call::Level && call.level > 0.0f) out.push_back({call.motor, hz, prevHz});
            }
            prevHz = hz;
        }
    };
    sweep(-55.0, 55.0, up);
    sweep(55.0, -55.0, down);

    // Up: the start shows A (no crossing), then B … A each once, in order, at f·(1 − 1%).
    REQUIRE(up.size() == 8);
    CHECK(up[0].motor == motors[0]);
    for (std::size_t j = 1; j < 8; ++j) {
        INFO("up, fret " << j << " took over at " << up[j].hz << " Hz");
        CHECK(up[j].motor == motors[j]);
        const double threshold = notes[j] * 0.99;
        CHECK(up[j].hz >= threshold);
        CHECK(up[j].prevHz < threshold);
    }
    // Down: G# … A each once, at f·(1 + 1%).
    REQUIRE(down.size() == 7);
    for (std::size_t k = 0; k < 7; ++k) {
        const std::size_t j = 6 - k;
        INFO("down, fret " << j << " took over at " << down[k].hz << " Hz");
        CHECK(down[k].motor == motors[j]);
        const double threshold = notes[j] * 1.01;
        CHECK(down[k].hz <= threshold);
        CHECK(down[k].prevHz > threshold);
    }
    // The top-right (wrist row, right column) motor is never used.
    for (const auto& c : h.canvas.calls)
        if (c.kind == RecordingCanvas::Call::Level) CHECK(c.motor != motorIndex(0, 2));
}

TEST_CASE("fret hysteresis: wobbling around a fret changes the motor once, not on every wobble", "[theremin][frets]")
{
    SceneHarness h(makeThereminScene());
    const double dEl = elevationFor(293.66 * 0.99);   // D's fret from below
    h.hold({dEl - 3.0, 0.0, 0.0}, 0.1);                  // on C#
    int switches = 0;
    int lastMotor = -1;
    const std::size_t before = h.canvas.calls.size();
    for (int i = 0; i < 2000; ++i) {
        // ±0.3° noise around the fret (≈ ±0.6%: inside the ±1% band).
        const double el = dEl + 0.3 * std::sin(i * 0.7) + 0.05;
        h.step({el, 0.0, 0.0});
    }
    for (std::size_t c = before; c < h.canvas.calls.size(); ++c) {
        const auto& call = h.canvas.calls[c];
        if (call.kind == RecordingCanvas::Call::Level && call.level > 0.0f && call.motor != lastMotor) {
            ++switches;
            lastMotor = call.motor;
        }
    }
    CHECK(switches == 1);
    CHECK(lastMotor == motorIndex(1, 0));   // D
}

TEST_CASE("pitch snapping pulls toward the scale by the amount asked", "[theremin]")
{
    SceneHarness h(makeThereminScene());
    // Halfway (in semitones) between C# (4 semitones above A) and D (5): 4.4 semitones.
    const double el = elevationFor(220.0 * std::exp2(4.4 / 12.0));
    CHECK(std::fabs(cents(measureHeldPitch(h, {el, 0.0, 0.0}), 220.0 * std::exp2(4.4 / 12.0))) < 5.0);
    h.set("theremin.snap", 100.0f);
    CHECK(std::fabs(cents(measureHeldPitch(h, {el, 0.0, 0.0}), 277.18)) < 5.0);   // nearest: C#
    h.set("theremin.snap", 50.0f);
    CHECK(std::fabs(cents(measureHeldPitch(h, {el, 0.0, 0.0}), 220.0 * std::exp2(4.2 / 12.0))) < 5.0);
}

TEST_CASE("other scales and roots move the frets", "[theremin][frets]")
{
    // C major inside A3..A4: A B C D E F G A.
    const auto c = fretSemitones(kDefaultPitchMap, FretScale::Major, 3);
    REQUIRE(c.size() == 8);
    const std::vector<double> expectC {0, 2, 3, 5, 7, 8, 10, 12};
    for (std::size_t i = 0; i < 8; ++i) CHECK(c[i] == Approx(expectC[i]).margin(1e-9));
    // A minor pentatonic: A C D E G A (six frets).
    const auto p = fretSemitones(kDefaultPitchMap, FretScale::MinorPentatonic, 0);
    const std::vector<double> expectP {0, 3, 5, 7, 10, 12};
    REQUIRE(p.size() == expectP.size());
    for (std::size_t i = 0; i < p.size(); ++i) CHECK(p[i] == Approx(expectP[i]).margin(1e-9));

    // Through the scene: with root C the third fret (motor of C#'s slot) takes over at C.
    SceneHarness h(makeThereminScene());
    h.set("theremin.root", 3.0f);
    h.hold({elevationFor(250.0), 0.0, 0.0}, 0.05);   // on B
    const std::size_t before = h.canvas.calls.size();
    h.hold({elevationFor(261.63 * 0.995), 0.0, 0.0}, 0.05);   // above C·0.99, below C#·0.99
    bool tookOver = false;
    for (std::size_t i = before; i < h.canvas.calls.size(); ++i)
        if (h.canvas.calls[i].kind == RecordingCanvas::Call::Level && h.canvas.calls[i].level > 0.0f)
            tookOver = h.canvas.calls[i].motor == motorIndex(2, 2);
    CHECK(tookOver);
}

TEST_CASE("glide: control steps never reach the output as steps", "[theremin]")
{
    SceneHarness h(makeThereminScene());
    h.hold({0.0, 0.0, 0.0}, 0.2);
    const std::size_t from = h.audio.left.size();
    // A fast sweep of pitch and volume together: each 5 ms control update jumps ~0.6 semitone.
    h.move({0.0, 0.0, 0.0}, {40.0, 40.0, 0.0}, 0.3);
    const std::size_t to = h.audio.left.size();
    // A sine of peak A at frequency f moves at most 2πfA/fs per sample; a stepped amplitude or a
    // stepped phase would jump by far more. Allow 20% over the bound at the top frequency.
    const double fMax = expectedHz(40.0);
    const double bound = 1.2 * 2.0 * kPi * fMax * 0.5 / h.audio.sampleRate;
    double worst = 0.0;
    for (std::size_t i = from + 1; i < to; ++i)
        worst = std::max(worst, static_cast<double>(std::fabs(h.audio.left[i] - h.audio.left[i - 1])));
    INFO("largest sample step " << worst << ", bound " << bound);
    CHECK(worst < bound);
    CHECK(worst > 0.1 * bound);   // and the sound did play
}

TEST_CASE("theremin is silent and frets are off while the arm is unknown", "[theremin]")
{
    SceneHarness h(makeThereminScene());
    h.hold({0.0, 0.0, 0.0}, 0.2);
    REQUIRE(rms(h.audio.left, h.audio.left.size() - 4800, h.audio.left.size()) > 0.1);
    ControlInput in;   // arm.valid = false
    SceneOutput out {h.canvas, h.events};
    h.scene().control(in, out);
    std::vector<float> l(4800, 0.0f), r(4800, 0.0f);
    for (int block = 0; block < 3; ++block) {   // 300 ms: the 10 ms amplitude smoothing ends at 0
        std::fill(l.begin(), l.end(), 0.0f);
        std::fill(r.begin(), r.end(), 0.0f);
        h.scene().renderAudio(l.data(), r.data(), 4800);
    }
    // Silent means it adds nothing at all (the buffers are added to, never overwritten).
    CHECK(rms(l, 0, l.size()) == 0.0);
    CHECK(rms(r, 0, r.size()) == 0.0);
    float sum = 0.0f;
    for (float v : h.canvas.levels) sum += v;
    CHECK(sum == 0.0f);
}

TEST_CASE("after reset (entering again, a transport jump) only the new fret is felt", "[theremin][frets]")
{
    SceneHarness h(makeThereminScene());
    h.hold({0.0, 0.0, 0.0}, 0.1);
    h.scene().reset();
    h.hold({40.0, 0.0, 0.0}, 0.1);
    int lit = 0;
    for (int m = 0; m < kGridMotors; ++m) lit += h.canvas.levels[static_cast<std::size_t>(m)] > 0.0f ? 1 : 0;
    CHECK(lit == 1);
    CHECK(h.canvas.levels[static_cast<std::size_t>(motorIndex(0, 0))] > 0.0f);   // 40° plays ≈ 426 Hz: G#
}
