// `armadillo score import` and `render --tactile-wav` / `--score FILE.mid` as a user runs them.
#include "CliRun.h"
#include "Common/MidiWriter.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "Tactile/Score.h"
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace armadillo::cli;
namespace fs = std::filesystem;

namespace {
std::string stillMotion(const std::string& name, double seconds)
{
    std::string rows = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) rows += std::to_string(i / 200.0) + ",0,0,0\n";
    return file(name, rows);
}
} // namespace

TEST_CASE("cli: score import turns a MIDI file into a score; bad usage 2, bad input 3, nothing written", "[cli][import]")
{
    using armadillo::test::WrittenNote;
    const std::string mid = path("tune.mid");
    armadillo::test::writeFile(mid, armadillo::test::midiBytes({{0, 1, 72, 90, 0, 0}, {1, 1, 76, 90, 0, 0}, {2, 2, 60, 90, 0, 0}, {2, 2, 64, 90, 0, 0}},
                                                              {{0, 100}}, 1));
    const std::string out = path("tune.score");
    const Run r = runArmadillo("score import '" + mid + "' --out '" + out + "' --max-motors 3");
    REQUIRE(r.code == 0);
    CHECK(r.out.find("\"format\":\"midi\"") != std::string::npos);
    CHECK(r.out.find("\"notes\":4") != std::string::npos);
    const armadillo::tactile::Score s = armadillo::tactile::loadScore(out);
    CHECK(s.notes.size() == 4);
    CHECK(s.version == 2);

    CHECK(runArmadillo("score").code == 2);
    CHECK(runArmadillo("score export x").code == 2);
    CHECK(runArmadillo("score import '" + mid + "'").code == 2);                                   // no --out
    CHECK(runArmadillo("score import '" + mid + "' --out '" + out + "' --track 1=nowhere").code == 2);
    CHECK(runArmadillo("score import '" + mid + "' --out '" + out + "' --max-motors 12").code == 2);
    const std::string never = path("never.score");
    const Run missing = runArmadillo("score import '" + path("missing.mid") + "' --out '" + never + "'");
    CHECK(missing.code == 3);
    CHECK(missing.err.find("missing.mid") != std::string::npos);
    CHECK(runArmadillo("score import '" + file("notes.txt", "hello") + "' --out '" + never + "'").code == 3);
    CHECK(runArmadillo("score import '" + file("broken.mid", "MThd\x00\x00") + "' --out '" + never + "'").code == 3);
    CHECK(runArmadillo("score import '" + mid + "' --out '" + never + "' --track 7=elbow").code == 3);   // no track 7
    CHECK_FALSE(fs::exists(never));
}

TEST_CASE("cli: render plays a MIDI file directly and writes the motors as a multichannel WAV", "[cli][import]")
{
    const std::string mid = path("direct.mid");
    armadillo::test::writeFile(mid, armadillo::test::midiBytes({{0, 1, 60, 100, 0, 0}, {1, 1, 67, 100, 0, 0}}, {{0, 120}}, 1));
    const std::string motion = stillMotion("still2.csv", 1.2);
    const std::string wav = path("direct.wav"), tactileWav = path("direct-tactile.wav"), csv = path("direct.csv");
    const Run r = runArmadillo("render --scene score --score '" + mid + "' --motion '" + motion + "' --out '" + wav + "' --tactile '" + csv +
                               "' --tactile-wav '" + tactileWav + "' --back-motors");
    REQUIRE(r.code == 0);
    const armadillo::core::AudioBuffer t = armadillo::core::readWav(tactileWav);
    CHECK(t.channels.size() == 12);
    float peak = 0.0f;
    for (const auto& c : t.channels)
        for (float x : c) peak = std::max(peak, std::fabs(x));
    CHECK(peak > 0.1f);   // the notes are there
    // The tactile WAV imports back as a score.
    CHECK(runArmadillo("score import '" + tactileWav + "' --out '" + path("back.score") + "'").code == 0);
}

TEST_CASE("cli: render writes the motors as AHAP and .haptic files that import back; bad actuator sets exit 2", "[cli][import][export]")
{
    const std::string mid = path("exported.mid");
    armadillo::test::writeFile(mid, armadillo::test::midiBytes({{0, 1, 60, 100, 0, 0}, {1, 1, 67, 100, 0, 0}}, {{0, 120}}, 1));
    const std::string motion = stillMotion("still4.csv", 1.2);
    const std::string ahap = path("exported.ahap"), haptic = path("exported.haptic");
    const Run r = runArmadillo("render --scene score --score '" + mid + "' --motion '" + motion + "' --out '" + path("exported.wav") +
                               "' --tactile-ahap '" + ahap + "' --tactile-haptic '" + haptic + "' --actuator-motors 1-9");
    REQUIRE(r.code == 0);
    const Run a = runArmadillo("score import '" + ahap + "' --out '" + path("from-ahap.score") + "' --motors wrist");
    CHECK(a.code == 0);
    CHECK(a.out.find("\"format\":\"ahap\"") != std::string::npos);
    const Run h = runArmadillo("score import '" + haptic + "' --out '" + path("from-haptic.score") + "'");
    CHECK(h.code == 0);
    CHECK(h.out.find("\"format\":\"haptic\"") != std::string::npos);
    const std::string never = path("never.ahap");
    const std::string base = "render --scene score --score '" + mid + "' --motion '" + motion + "' --out '" + path("x.wav") + "'";
    CHECK(runArmadillo(base + " --tactile-ahap '" + never + "' --actuator-motors nowhere").code == 2);
    CHECK(runArmadillo(base + " --tactile-ahap '" + never + "' --actuator-motors 11").code == 2);   // a back motor without --back-motors
    CHECK(runArmadillo(base + " --actuator-motors 1").code == 2);                                   // no AHAP or .haptic out
    CHECK(runArmadillo(base + " --tactile-ahap '" + path("no-such-dir/x.ahap") + "'").code == 4);   // checked before the render
    CHECK_FALSE(fs::exists(never));
}

TEST_CASE("cli: render takes stems for audio-touch; unknown stems and stems for other scenes are refused", "[cli][stems]")
{
    armadillo::core::AudioBuffer tone;
    tone.channels.assign(1, std::vector<float>(24000));
    for (std::size_t i = 0; i < tone.frames(); ++i) tone.channels[0][i] = static_cast<float>(0.4 * std::sin(2.0 * 3.14159265358979 * 55.0 * static_cast<double>(i) / 48000.0));
    const std::string bass = path("bass.wav"), drums = path("drums.wav");
    armadillo::core::writeWav(bass, tone);
    armadillo::core::writeWav(drums, tone);
    const std::string motion = stillMotion("still3.csv", 0.5);
    const std::string out = path("stems.wav"), csv = path("stems.csv");
    CHECK(runArmadillo("render --scene audio-touch --motion '" + motion + "' --out '" + out + "' --stem bass='" + bass + "' --stem drums='" + drums + "' --tactile '" + csv + "'").code == 0);
    CHECK(runArmadillo("render --scene audio-touch --motion '" + motion + "' --out '" + out + "' --audio-in '" + bass + "' --audio-in '" + drums + "'").code == 0);
    CHECK(runArmadillo("render --scene audio-touch --motion '" + motion + "' --out '" + out + "' --stem guitar='" + bass + "'").code == 3);
    CHECK(runArmadillo("render --scene audio-touch --motion '" + motion + "' --out '" + out + "' --stem bass").code == 2);
    CHECK(runArmadillo("render --scene monitor --motion '" + motion + "' --out '" + out + "' --stem bass='" + bass + "'").code == 2);
}

TEST_CASE("cli: play feels stems apart and plays them out together; bad stems are refused before the session", "[cli][stems][play]")
{
    // A bass line (55 Hz, 0.4) and a silent vocal stem: the bass's motors (7, 9: the elbow) run,
    // the vocals' (1, 3: the wrist) never do, and the output holds the bass as it was.
    const std::size_t n = 48000;
    armadillo::core::AudioBuffer bassTone, silence;
    bassTone.channels.assign(1, std::vector<float>(n));
    for (std::size_t i = 0; i < n; ++i) bassTone.channels[0][i] = static_cast<float>(0.4 * std::sin(2.0 * 3.14159265358979 * 55.0 * static_cast<double>(i) / 48000.0));
    silence.channels.assign(2, std::vector<float>(n / 2, 0.0f));   // stereo and shorter: mixed to mono, padded
    const std::string bass = path("play-bass.wav"), vocals = path("play-vocals.wav");
    armadillo::core::writeWav(bass, bassTone, true);
    armadillo::core::writeWav(vocals, silence);
    const std::string out = path("play-stems.wav"), csv = path("play-stems.csv");
    const Run r = runArmadillo("play --scene audio-touch --simulate --seconds 2 --stem bass='" + bass + "' --stem vocals='" + vocals + "' --out '" + out +
                               "' --tactile '" + csv + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto rows = armadillo::core::readTactile(armadillo::core::CsvTable::read(csv));
    int bassOn = 0, vocalsOn = 0;
    for (const auto& row : rows) {
        bassOn += row.levels[6] > 0 || row.levels[8] > 0;
        vocalsOn += row.levels[0] > 0 || row.levels[2] > 0;
    }
    CHECK(bassOn > 20);
    CHECK(vocalsOn == 0);
    const armadillo::core::AudioBuffer played = armadillo::core::readWav(out);
    REQUIRE(played.frames() > n / 2);
    double err = 0.0, energy = 0.0;
    for (std::size_t i = 0; i < n / 2; ++i) {
        const double d = played.channels[0][i] - bassTone.channels[0][i];
        err += d * d;
        energy += double(bassTone.channels[0][i]) * double(bassTone.channels[0][i]);
    }
    CHECK(err < 1e-3 * energy);   // the audio-touch scene is silent: the stems' sum, 16-bit rounding only

    // Two --audio-in files are stems too, named by their file names.
    const std::string drums = path("drums.wav");
    armadillo::core::writeWav(drums, bassTone);
    CHECK(runArmadillo("play --scene audio-touch --simulate --seconds 0.5 --audio-in '" + drums + "' --audio-in '" + bass + "' --out '" + out + "'").code == 3);   // "play-bass" is no stem
    const std::string bass2 = path("bass.wav");
    armadillo::core::writeWav(bass2, bassTone);
    CHECK(runArmadillo("play --scene audio-touch --simulate --seconds 0.5 --audio-in '" + drums + "' --audio-in '" + bass2 + "' --out '" + out + "'").code == 0);

    const std::string base = "play --simulate --seconds 0.5 --out '" + out + "' ";
    CHECK(runArmadillo(base + "--scene theremin --stem bass='" + bass + "'").code == 2);              // stems: audio-touch only
    CHECK(runArmadillo(base + "--scene audio-touch --stem bass").code == 2);                            // NAME=FILE
    CHECK(runArmadillo(base + "--scene audio-touch --stem bass='" + bass + "' --audio-in '" + bass + "'").code == 2);
    CHECK(runArmadillo("play --simulate --seconds 0.5 --no-audio --scene audio-touch --stem bass='" + bass + "'").code == 2);
    CHECK(runArmadillo(base + "--scene audio-touch --stem guitar='" + bass + "'").code == 3);          // no such stem preset
    CHECK(runArmadillo(base + "--scene audio-touch --stem bass='" + path("absent.wav") + "'").code == 4);
    armadillo::core::AudioBuffer other = bassTone;
    other.sampleRate = 44100.0;
    const std::string slow = path("vocals-44k.wav");
    armadillo::core::writeWav(slow, other);
    const Run rate = runArmadillo(base + "--scene audio-touch --stem bass='" + bass + "' --stem vocals='" + slow + "'");
    CHECK(rate.code == 3);
    CHECK(rate.err.find("vocals-44k.wav") != std::string::npos);
}

TEST_CASE("cli: render writes the motors as a bHaptics .tact that imports back; a malformed .tact exits 3", "[cli][import][export][tact]")
{
    const std::string mid = path("to-tact.mid");
    armadillo::test::writeFile(mid, armadillo::test::midiBytes({{0, 1, 60, 100, 0, 0}, {1, 1, 67, 100, 0, 0}}, {{0, 120}}, 1));
    const std::string motion = stillMotion("still-tact.csv", 1.2);
    const std::string tact = path("exported.tact"), csv = path("exported-tact.csv");
    const Run r = runArmadillo("render --scene score --score '" + mid + "' --motion '" + motion + "' --out '" + path("tact.wav") +
                               "' --tactile '" + csv + "' --tactile-tact '" + tact + "'");
    REQUIRE(r.code == 0);
    const Run t = runArmadillo("score import '" + tact + "' --out '" + path("from-tact.score") + "'");
    CHECK(t.code == 0);
    CHECK(t.out.find("\"format\":\"tact\"") != std::string::npos);
    // --score takes the .tact directly: the same motor levels as the render it came from.
    const std::string csv2 = path("replayed-tact.csv");
    REQUIRE(runArmadillo("render --scene score --score '" + tact + "' --motion '" + motion + "' --out '" + path("tact2.wav") + "' --tactile '" + csv2 + "'").code == 0);
    const auto first = armadillo::core::readTactile(armadillo::core::CsvTable::read(csv)), second = armadillo::core::readTactile(armadillo::core::CsvTable::read(csv2));
    REQUIRE(second.size() >= 200);
    int worst = 0;
    for (std::size_t i = 0; i < 200; ++i)
        for (std::size_t m = 0; m < 9; ++m) worst = std::max(worst, std::abs(int(first[i].levels[m]) - int(second[i].levels[m])));
    CHECK(worst <= 1);

    const std::string never = path("never-tact.score");
    const Run bad = runArmadillo("score import '" + file("bad.tact", R"({"project":{"tracks":[{"effects":[{"startTime":0,"offsetTime":100,"modes":{"ForearmR":{"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":9,"intensity":0.5}]}]}}}}]}]}})") + "' --out '" + never + "'");
    CHECK(bad.code == 3);
    CHECK(bad.err.find("bad.tact") != std::string::npos);
    CHECK(bad.err.find("index") != std::string::npos);
    CHECK(runArmadillo("score import '" + tact + "' --out '" + never + "' --device ForearmX").code == 2);
    CHECK(runArmadillo("score import '" + tact + "' --out '" + never + "' --device ForearmL").code == 3);   // nothing on the left
    CHECK_FALSE(fs::exists(never));
}

TEST_CASE("cli: score import and --score read MPEG .hjif; render writes --tactile-hjif that imports back; bad files exit 3", "[cli][import][export][hjif]")
{
    const std::string source = std::string(ARMADILLO_SOURCE_DIR) + "/Tests/Formats/data/hjif/";
    const std::string out = path("curves.score");
    const Run r = runArmadillo("score import '" + source + "curves_two_channels.hjif' --out '" + out + "'");
    REQUIRE(r.code == 0);
    CHECK(r.out.find("\"format\":\"hjif\"") != std::string::npos);
    // The two channels' actuator_target: the wrist row (1-3) and the elbow row (7-9), nothing else.
    const armadillo::tactile::Score s = armadillo::tactile::loadScore(out);
    REQUIRE(!s.notes.empty());
    for (const auto& n : s.notes) CHECK((n.motors == 0x0007 || n.motors == 0x01C0));
    // --actuator-motors: channel 1 on motor 5 only, channel 2 left out.
    REQUIRE(runArmadillo("score import '" + source + "curves_two_channels.hjif' --out '" + out + "' --actuator-motors 1=5").code == 0);
    for (const auto& n : armadillo::tactile::loadScore(out).notes) CHECK(n.motors == 0x0010);
    CHECK(runArmadillo("score import '" + source + "curves_two_channels.hjif' --out '" + out + "' --actuator-motors 1").code == 2);
    CHECK(runArmadillo("score import '" + source + "curves_two_channels.hjif' --out '" + out + "' --actuator-motors 0=5").code == 2);
    CHECK(runArmadillo("score import '" + source + "curves_two_channels.hjif' --out '" + out + "' --actuator-motors 1=nowhere").code == 2);

    // Render from the .hjif directly, export the motors as .hjif, play that: the same levels.
    const std::string motion = stillMotion("still-hjif.csv", 2.0);
    const std::string csv = path("hjif-1.csv"), hjif = path("exported.hjif"), csv2 = path("hjif-2.csv");
    REQUIRE(runArmadillo("render --scene score --score '" + source + "ten_seconds.hjif' --motion '" + motion + "' --out '" + path("hjif.wav") +
                         "' --tactile '" + csv + "' --tactile-hjif '" + hjif + "'").code == 0);
    const Run back = runArmadillo("score import '" + hjif + "' --out '" + path("from-hjif.score") + "'");
    CHECK(back.code == 0);
    REQUIRE(runArmadillo("render --scene score --score '" + hjif + "' --motion '" + motion + "' --out '" + path("hjif2.wav") + "' --tactile '" + csv2 + "'").code == 0);
    const auto first = armadillo::core::readTactile(armadillo::core::CsvTable::read(csv)), second = armadillo::core::readTactile(armadillo::core::CsvTable::read(csv2));
    REQUIRE(second.size() >= 380);
    int worst = 0, on = 0;
    for (std::size_t i = 0; i < 380; ++i)
        for (std::size_t m = 0; m < 9; ++m) {
            worst = std::max(worst, std::abs(int(first[i].levels[m]) - int(second[i].levels[m])));
            on += first[i].levels[m] > 0;
        }
    CHECK(on > 100);
    CHECK(worst <= 1);

    const std::string never = path("never-hjif.score");
    const Run truncated = runArmadillo("score import '" + file("cut.hjif", R"({"version": "2023", "profile": "Main", "perceptions": [)") + "' --out '" + never + "'");
    CHECK(truncated.code == 3);
    CHECK(truncated.err.find("cut.hjif") != std::string::npos);
    std::string text;
    {
        std::ifstream in(source + "library_vectorial.hjif");
        std::ostringstream ss;
        ss << in.rdbuf();
        text = ss.str();
    }
    text.replace(text.find("\"VectorialWave\""), 15, "\"Wobble\"");
    const Run unknown = runArmadillo("score import '" + file("wobble.hjif", text) + "' --out '" + never + "'");
    CHECK(unknown.code == 3);
    CHECK(unknown.err.find("wobble.hjif") != std::string::npos);
    CHECK(unknown.err.find("unknown band type 'Wobble'") != std::string::npos);
    CHECK(runArmadillo("render --scene score --score '" + path("wobble.hjif") + "' --motion '" + motion + "' --out '" + path("never.wav") + "'").code == 3);
    CHECK_FALSE(fs::exists(never));
}
