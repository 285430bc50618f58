// The score player: its own clock without a transport; with one, seeks, loops and tempo changes
// land on the right event.
#include "Tactile/ScorePlayer.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {

// Records what the player asks of the canvas.
struct RecordingCanvas final : MotorCanvas {
    std::array<float, kMaxMotors> level {};
    std::array<PatternRequest, kPatternVoices> voice {};
    std::array<bool, kPatternVoices> running {};
    int triggers = 0, stops = 0;
    void setLevel(int m, float l) override { level[static_cast<std::size_t>(m)] = l; }
    void clearLevels() override { level.fill(0.0f); }
    void trigger(const PatternRequest& r) override
    {
        voice[static_cast<std::size_t>(r.voice)] = r;
        running[static_cast<std::size_t>(r.voice)] = true;
        ++triggers;
    }
    void stopVoice(int v) override
    {
        running[static_cast<std::size_t>(v)] = false;
        ++stops;
    }
    int soundingMotor() const   // the one motor with a level, -1 for none, -2 for several
    {
        int found = -1;
        for (int m = 0; m < kMaxMotors; ++m)
            if (level[static_cast<std::size_t>(m)] > 0.0f) found = found == -1 ? m : -2;
        return found;
    }
};

// Beat 0–3 at 60 bpm (1 s a beat), from beat 4 at 120 bpm (0.5 s a beat).
const char* kScore = R"(armadillo-score 1
units beats
tempo 60
0  note m=1 dur=1 level=5
1  note m=2 dur=1 level=6
2  note m=3 dur=1 level=7
4  tempo 120
4  note m=4 dur=1 level=8
6  note m=5 dur=1 level=9
8  pattern breathing m=all level=5 voice=1 dur=4
length 12
)";

ScorePlayer makePlayer()
{
    ScorePlayer p;
    p.setScore(parseScore(kScore, "test"));
    return p;
}

Transport at(double seconds, double ppq = 0.0, double bpm = 120.0)
{
    Transport t;
    t.valid = true;
    t.playing = true;
    t.seconds = seconds;
    t.ppq = ppq;
    t.bpm = bpm;
    return t;
}

} // namespace

TEST_CASE("Score player: without a transport it runs on its own clock", "[player]")
{
    ScorePlayer p = makePlayer();
    RecordingCanvas c;
    // Score seconds: m1 0–1, m2 1–2, m3 2–3, (gap), m4 4–4.5, m5 5–5.5, breathing 6–8.
    const struct {
        double t;
        int motor;
    } expected[] = {{0.5, 0}, {1.5, 1}, {2.5, 2}, {3.5, -1}, {4.25, 3}, {4.75, -1}, {5.25, 4}, {5.75, -1}};
    std::size_t next = 0;
    for (int i = 0; i <= 620; ++i) {   // 0 .. 6.2 s at 100 Hz
        p.control(Transport {}, i == 0 ? 0.0 : 0.01, c);   // the first step comes at 0
        const double t = i * 0.01;
        if (next < std::size(expected) && std::fabs(t - expected[next].t) < 1e-9) {
            INFO("t = " << t);
            CHECK(c.soundingMotor() == expected[next].motor);
            ++next;
        }
    }
    CHECK(next == std::size(expected));
    CHECK(c.running[1]);   // the breathing started at 6 s
    CHECK(c.voice[1].duration <= 2.0);
    CHECK(c.voice[1].duration >= 1.98);
}

TEST_CASE("Score player: a seek lands on the event at the new position", "[player]")
{
    ScorePlayer p = makePlayer();
    RecordingCanvas c;
    p.control(at(0.2), 0.01, c);
    CHECK(c.soundingMotor() == 0);
    p.control(at(5.2), 0.01, c);   // beat 6.4: after the tempo change, inside the m5 note
    CHECK(c.soundingMotor() == 4);
    CHECK(c.level[4] == Approx(9.0f));
    p.control(at(1.5), 0.01, c);   // back
    CHECK(c.soundingMotor() == 1);
    // Into the middle of the breathing: it starts with what is left of it.
    p.control(at(7.0), 0.01, c);
    CHECK(c.running[1]);
    CHECK(c.voice[1].duration == Approx(1.0));
    CHECK(c.soundingMotor() == -1);
    p.control(at(2.5), 0.01, c);   // back before it: stopped
    CHECK_FALSE(c.running[1]);
    CHECK(c.soundingMotor() == 2);
}

TEST_CASE("Score player: a loop restarts what the loop start holds", "[player]")
{
    ScorePlayer p = makePlayer();
    RecordingCanvas c;
    // Loop 5.5 s .. 7.0 s, three times: the breathing (6 s) starts on each pass.
    int startsSeen = 0;
    for (int pass = 0; pass < 3; ++pass) {
        for (double t = 5.5; t < 7.0 - 1e-9; t += 0.01) {
            const int before = c.triggers;
            Transport tr = at(t);
            tr.looping = true;
            p.control(tr, 0.01, c);
            if (c.triggers > before) {
                ++startsSeen;
                CHECK(t >= 6.0 - 1e-9);
                CHECK(t < 6.0 + 0.011);
            }
            if (t < 6.0 - 1e-9) CHECK_FALSE(c.running[1]);
        }
    }
    CHECK(startsSeen == 3);
}

TEST_CASE("Score player: tempo changes land on the right event", "[player]")
{
    ScorePlayer p = makePlayer();
    RecordingCanvas c;
    // Seconds sync: the score's tempo map puts beat 6 at 5 s (4 s + 2 beats at 120 bpm); without
    // the change it would be at 6 s.
    p.control(at(5.01), 0.01, c);
    CHECK(c.soundingMotor() == 4);
    p.control(at(6.01), 0.01, c);
    CHECK(c.soundingMotor() == -1);

    // Beat sync: the host's beats are the score's beats, whatever the host's tempo.
    ScorePlayer b = makePlayer();
    b.setSync(ScorePlayer::Sync::Beats);
    RecordingCanvas cb;
    b.control(at(100.0, 6.2, 90.0), 0.01, cb);
    CHECK(cb.soundingMotor() == 4);
    b.control(at(100.0, 2.5, 90.0), 0.01, cb);
    CHECK(cb.soundingMotor() == 2);
    // A pattern started at beat 8 runs to beat 12: 4 beats at the host's 90 bpm = 2.667 s.
    b.control(at(0.0, 8.0, 90.0), 0.01, cb);
    CHECK(cb.running[1]);
    CHECK(cb.voice[1].duration == Approx(4.0 * 60.0 / 90.0));
}

TEST_CASE("Score player: a stopped transport is silent; intensity scales", "[player]")
{
    ScorePlayer p = makePlayer();
    RecordingCanvas c;
    p.control(at(7.0), 0.01, c);
    CHECK(c.running[1]);
    Transport stopped = at(7.0);
    stopped.playing = false;
    p.control(stopped, 0.01, c);
    CHECK_FALSE(c.running[1]);
    CHECK(c.soundingMotor() == -1);
    p.setIntensity(0.5f);
    p.control(at(1.5), 0.01, c);
    CHECK(c.level[1] == Approx(3.0f));
    // Past the end: silence.
    p.control(at(20.0), 0.01, c);
    CHECK(c.soundingMotor() == -1);
    CHECK(p.finished());
}

TEST_CASE("Score player: block-quantised host positions are not seeks", "[player]")
{
    // A host reporting its position once per 1024-sample block at 48 kHz (21.3 ms) while the
    // control runs at 200 Hz: the position stands, leaps, and sometimes wobbles back 1 ms.
    ScorePlayer p = makePlayer();
    RecordingCanvas c;
    const double block = 1024.0 / 48000.0;
    int triggers = 0;
    for (int i = 0; i < 500; ++i) {   // 5.5 .. 8 s
        const double t = 5.5 + i * 0.005;
        double reported = std::floor(t / block) * block;
        if (i % 37 == 0) reported -= 0.001;
        const int before = c.triggers;
        p.control(at(reported), 0.005, c);
        triggers += c.triggers - before;
    }
    CHECK(triggers == 1);   // the breathing started once, never restarted
    CHECK(c.stops <= 1);
}
