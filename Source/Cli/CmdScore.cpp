#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Formats/ScoreImport.h"
#include <iostream>

namespace armadillo::cli {

namespace {

/// `--track N=SET` or `--track N=off`.
formats::MidiTrackRule trackRule(const std::string& text)
{
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("--track takes N=MOTORS or N=off (e.g. 2=elbow), not '" + text + "'");
    formats::MidiTrackRule r;
    try {
        std::size_t used = 0;
        r.track = std::stoi(text.substr(0, eq), &used);
        if (used != eq) throw std::invalid_argument(text);
    } catch (const std::exception&) {
        throw UsageError("--track: '" + text.substr(0, eq) + "' is not a track number");
    }
    const std::string set = text.substr(eq + 1);
    if (set == "off") r.off = true;
    else if (!tactile::parseMotorSet(set, r.motors) || r.motors == 0) throw UsageError("--track: '" + set + "' is not a motor set (1-16, 1,3, 7-9, elbow, wrist, ...)");
    return r;
}

/// `--actuator-motors C=SET`: an .hjif channel on these motors.
std::pair<int, std::uint16_t> channelMotors(const std::string& text)
{
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("--actuator-motors takes C=MOTORS (e.g. 1=wrist or 2=7-9), not '" + text + "'");
    int channel = 0;
    try {
        std::size_t used = 0;
        channel = std::stoi(text.substr(0, eq), &used);
        if (used != eq || channel < 1) throw std::invalid_argument(text);
    } catch (const std::exception&) {
        throw UsageError("--actuator-motors: '" + text.substr(0, eq) + "' is not a channel number (1, 2, ...)");
    }
    std::uint16_t motors = 0;
    const std::string set = text.substr(eq + 1);
    if (!tactile::parseMotorSet(set, motors) || motors == 0) throw UsageError("--actuator-motors: '" + set + "' is not a motor set (1-16, 1,3, 7-9, elbow, wrist, ...)");
    return {channel, motors};
}

int runImport(const Arguments& args)
{
    CommandLine cl("score import", "FILE --out SCORE [options]",
                   "Turns a MIDI file or a haptic file into a tactile score (docs/FORMATS.md), by its extension:\n"
                   "  .mid .midi   notes -> motors: lowest pitch at the elbow, highest at the wrist; velocity -> level\n"
                   "               (capped at the rated level for long notes); at most --max-motors notes at once;\n"
                   "               tempo changes and markers become cues; the score follows a recording of the piece\n"
                   "  .wav         9 or 12 channels, channel k = motor k, level = 15 x peak amplitude per frame\n"
                   "  .ahap        Apple AHAP: transient and continuous events, intensity and its curves\n"
                   "  .haptic      Meta Haptics Studio: amplitude envelope and emphasis\n"
                   "  .tact        bHaptics Designer, the forearm (Tactosy) device: its 3x2 grid on the wrist and\n"
                   "               elbow rows, dot and path modes (an interpretation: docs/FORMATS.md)\n"
                   "  .hjif        MPEG haptics (ISO/IEC 23090-31) as its reference software synthesises it: the\n"
                   "               amplitude envelope of every Vibrotactile channel (Transient, Curve, VectorialWave\n"
                   "               bands; Basis, Reference, Composite effects); a channel's actuator_target picks its\n"
                   "               motors, else it plays on all nine (WaveletWave bands are refused: docs/FORMATS.md)\n"
                   "The score is written whole or not at all; one JSON line on stdout says what was imported.",
                   {{"--out", "SCORE", "the score file to write (armadillo-score 2)", true},
                    {"--max-motors", "N", "MIDI: at most N notes at once (1..9, default 4)"},
                    {"--track", "N=MOTORS", "MIDI: track N (1-based) on these motors, e.g. 2=elbow or 3=1,2,3;\n"
                                            "N=off leaves the track out (repeatable)"},
                    {"--no-follow", "", "MIDI: no pitch=, parts follow=none (the score plays by time only)"},
                    {"--motors", "SET", "AHAP, .haptic: the motors the one actuator drives (default all: 1-9)"},
                    {"--device", "ForearmR|ForearmL", ".tact: which forearm's effects (default: the one that plays, ForearmR\n"
                                                      "when both do; ForearmL is mirrored into the right-arm layout)"},
                    {"--actuator-motors", "C=MOTORS", ".hjif: the file's Vibrotactile channel C (1-based) on these motors,\n"
                                                      "e.g. 1=wrist or 2=7-9 (repeatable; the channels not named are left out)"},
                    {"--frame-ms", "MS", "WAV: the analysis frame (default 5 ms; the carrier must reach its peak\n"
                                         "within a frame: >= 100 Hz at 5 ms); .hjif: the frame the envelope is sampled at"}});
    if (args.empty() || args[0].rfind("--", 0) == 0) {
        if (!cl.parse(args)) return 0;
        throw UsageError("score import needs a FILE to import");
    }
    const std::string file = args[0];
    if (!cl.parse(Arguments(args.begin() + 1, args.end()))) return 0;
    formats::MidiImportOptions midi;
    midi.maxMotors = static_cast<int>(cl.integer("--max-motors", 4, 1, 9));
    for (const std::string& t : cl.values("--track")) midi.tracks.push_back(trackRule(t));
    midi.follow = !cl.has("--no-follow");
    formats::HapticImportOptions haptic;
    if (cl.has("--motors")) {
        haptic.motors = 0;
        if (!tactile::parseMotorSet(cl.value("--motors"), haptic.motors) || haptic.motors == 0)
            throw UsageError("--motors: '" + cl.value("--motors") + "' is not a motor set");
    }
    haptic.tactDevice = cl.value("--device");
    if (cl.has("--device") && haptic.tactDevice != "ForearmR" && haptic.tactDevice != "ForearmL")
        throw UsageError("--device: '" + haptic.tactDevice + "' is not ForearmR or ForearmL");
    const double frameMs = cl.number("--frame-ms", 5.0);
    if (!(frameMs >= 1.0 && frameMs <= 100.0)) throw UsageError("--frame-ms must lie in 1..100");
    haptic.frameSeconds = frameMs / 1000.0;
    for (const std::string& c : cl.values("--actuator-motors")) haptic.hjifChannels.push_back(channelMotors(c));
    const formats::ImportedScore s = importScoreFile(file, midi, haptic);
    core::writeFileAtomically(cl.value("--out"), s.text);
    std::string json = "{\"format\":";
    armadillo::core::appendJsonString(json, s.report.format);
    json += ",\"notes\":" + std::to_string(s.report.notes) + ",\"dropped\":" + std::to_string(s.report.dropped) +
            ",\"shortened\":" + std::to_string(s.report.shortened) + ",\"cues\":" + std::to_string(s.report.cues) +
            ",\"seconds\":" + std::to_string(s.score.length) + ",\"warnings\":[";
    for (std::size_t i = 0; i < s.report.warnings.size(); ++i) {
        if (i) json += ",";
        armadillo::core::appendJsonString(json, s.report.warnings[i]);
    }
    std::cout << json << "]}\n";
    return 0;
}

} // namespace

int runScore(const Arguments& args)
{
    return guarded("score", [&] {
        if (args.empty() || args[0] == "--help" || args[0] == "-h") {
            std::cout << "usage: armadillo score import FILE --out SCORE [options]\n\n"
                         "Tactile scores from other files (docs/FORMATS.md).\n\nsubcommands:\n"
                         "  import      a MIDI file (.mid), a multichannel WAV (.wav), an AHAP (.ahap), a Meta\n"
                         "              .haptic, a bHaptics .tact or an MPEG .hjif file -> a tactile score (see armadillo score import --help)\n";
            if (args.empty()) throw UsageError("score needs a subcommand (import)");
            return 0;
        }
        if (args[0] == "import") return runImport(Arguments(args.begin() + 1, args.end()));
        throw UsageError("unknown score subcommand '" + args[0] + "' (import)");
    });
}

} // namespace armadillo::cli
