// The adaptive training session on the device, for a reader alone:
//   1. the planner (Access/AdaptivePlan.h) picks the trial from the reader's whole history;
//   2. the "next" cue (the underside line swept wrist → elbow), the cells drawn on the arm
//      (passive drawing, §4.2.1 timings, the chosen method) through the tactile engine, then
//      the "your turn" cue (the underside line tapped twice);
//   3. the prompt is written / spoken / shown on the braille display; the answer comes from
//      stdin or the display's keys, as letters or Perkins chords (--chords);
//   4. feedback: written / spoken / shown, and always on the arm — "right": all nine motors hum
//      softly together (0.4 s); "wrong": the two outer columns buzz three times — then, when
//      wrong, the right cell again and, when the answer was another letter, that letter's cell
//      next to it (the confused pair side by side);
//   5. every answer goes into the reader profile (saved at the end, and after every answer so a
//      crash loses nothing) and the session log (the §4.4.1 log's columns; events trial, row,
//      word-gap, cue, answer, feedback, end).
//   A session may stop early — the answers end (stdin closed), Ctrl-C, the braille display goes
//   away: what was answered is kept in every file asked for (profile and --log; the log's `end`
//   row then says `stopped`); the first two are a normal end (exit 0), the display's loss still
//   exit 4.
#include "Cli/GuidedTraining.h"
#include "Access/ArmGestures.h"
#include "Access/Chords.h"
#include "Access/Report.h"
#include "Braille/Sensations.h"
#include "Braille/Training.h"
#include "Cli/ReaderIo.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Link/TouchProfile.h"
#include "Live/Sources/GuidedDevice.h"
#include "Procedures/AdaptiveTraining.h"
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <iostream>
#include <sstream>

#include "Cli/LiveOptions.h"

namespace armadillo::cli {

using namespace armadillo::braille;

std::vector<OptionSpec> guidedTrainingOptionSpecs()
{
    std::vector<OptionSpec> o {
        {"--adaptive", "", "with --train: the adaptive training on the device, answers typed or chorded (--reader)"},
        {"--reader", "READER.json", "the reader's profile: every answer of every session (created if missing)"},
        {"--report", "READER.json", "print the reader's progress: accuracy per stage and session, letters/min,\n"
                                    "confusions, and the published figures to compare with"},
        {"--simulate", "", "--adaptive: the built-in simulated device"},
        {"--unpaced", "", "--adaptive: count display time by packets (simulated readers)"},
        {"--profile", "PROFILE.json", "the reader's touch profile (armadillo touch-profile): motors evened out"},
        {"--arm", "right|left", "arm wearing the device (default right)"},
        {"--level", "L", "level of the cells (1..15; default 5 = the motors' rating, or the comfortable level of\n"
                         "--profile when it has one)"},
        {"--chords", "", "answers are Perkins chords: S D F J K L = dots 3 2 1 4 5 6, a group per cell, e.g. 'fd' = b"},
        {"--arm-only", "", "nothing on the screen: the arm gives every cue and feedback (deafblind readers)"},
        {"--calibration", "CAL.json", "--adaptive: the device calibration (for the arm gestures: a quick twist of the\n"
                                      "forearm and back shows the trial again, two twists skip it)"},
        {"--no-gestures", "", "--adaptive: ignore arm gestures"},
    };
    const auto io = readerIoOptionSpecs();
    const auto device = pickOptions(sourceOptionSpecs(), {"--port", "--baud"});   // the source group (Cli/LiveOptions.h)
    o.insert(o.end(), device.begin(), device.end());
    o.insert(o.end(), io.begin(), io.end());
    return o;
}

int printProgressReport(const CommandLine& cl)
{
    const std::string path = cl.value("--report");
    if (path.empty()) throw UsageError("--report needs a reader profile");
    if (!std::ifstream(path)) throw core::IoError("cannot read " + path);
    std::cout << access::progressReport(access::parseReaderProfile(core::readWholeFile(path), path));
    return core::kExitOk;
}

int runGuidedTraining(const CommandLine& cl)
{
    const std::string readerPath = cl.value("--reader");
    if (readerPath.empty()) throw UsageError("--adaptive needs --reader READER.json (created if it does not exist)");
    const DeviceChoice choice = readDeviceOptions(cl, "--adaptive draws on the arm: choose --port NAME or --simulate");   // Cli/LiveOptions.h
    for (const char* o : {"--motion", "--answers"})
        if (cl.has(o)) throw UsageError(std::string(o) + " is for the replayed training; --adaptive takes answers live");
    const bool armOnly = cl.has("--arm-only");
    ReaderIo io(cl, armOnly);
    (void) access::loadReaderProfile(readerPath);   // InputError (exit 3) for a bad file, before anything else
    // Refuse an unwritable profile or log now, not after the reader has answered.
    for (const std::string& out : {readerPath, cl.value("--log")}) {
        if (out.empty()) continue;
        const std::filesystem::path dir = std::filesystem::absolute(out).parent_path();
        if (!std::filesystem::is_directory(dir) || ::access(dir.c_str(), W_OK) != 0) throw core::IoError("cannot write into " + dir.string());
    }

    procedures::AdaptiveTraining::Options o;
    o.profilePath = readerPath;
    o.logPath = cl.value("--log");
    if (cl.has("--seed")) o.seed = cl.integer("--seed", 0, 0, 2147483647L);
    DisplayMethod method = DisplayMethod::Rows;
    if (cl.has("--method") && !parseDisplayMethod(cl.value("--method"), method)) throw UsageError("--method is one of rows, whole, columns, dots");
    o.method = displayMethodName(method);
    if (cl.has("--stages")) {
        o.stages.clear();
        std::istringstream names(cl.value("--stages"));
        for (std::string n; std::getline(names, n, ',');) {
            if (n != "letters" && n != "words" && n != "signs" && n != "contractions")
                throw UsageError("--adaptive trains the stages letters, words, signs, contractions (not '" + n + "')");
            o.stages.push_back(n);
        }
    }
    if (cl.has("--words")) o.signWords = readWordList(cl.value("--words"));
    o.trials = static_cast<int>(cl.integer("--trials", 30, 1, 10000));
    o.level = static_cast<float>(cl.integer("--level", 5, 1, 15));

    tactile::TactileConfig tc;
    const std::string arm = cl.value("--arm", "right");
    if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
    tc.side = arm == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    if (cl.has("--profile")) {
        const link::TouchProfile touch = link::loadTouchProfile(cl.value("--profile"));
        tc.motorGain = link::touchProfileGains(touch);
        // Without --level the cells come at the reader's comfortable level: the level that, after
        // the profile's gain, gives the comfort motor what the reader chose as comfortable.
        const std::size_t cm = static_cast<std::size_t>(touch.comfortMotor - 1);
        if (!cl.has("--level") && touch.comfort > 0 && tc.motorGain[cm] > 0.0f)
            o.level = std::clamp(static_cast<float>(touch.comfort) / tc.motorGain[cm], 1.0f, 15.0f);
    }
    const int baud = choice.baud;
    const bool unpaced = cl.has("--unpaced");
    access::TactilePlayer player(tc, unpaced ? 1.0 / link::lockStepRate(baud) : 0.0);
    installInterruptHandlers();
    // Arm gestures: a twist of the forearm and back = '?' (again), two = '-' (skip). Detected on
    // the control thread from the calibrated roll rate; handed over in atomics.
    const link::Calibration calibration = cl.has("--calibration") ? link::loadCalibration(cl.value("--calibration")) : link::defaultCalibration();
    access::TwistDetector twist;
    std::atomic<int> repeats {0}, skips {0};
    auto onSensor = [&](const link::SensorCounts& counts, double t) {
        const double rollRate = calibration.apply(t, counts).gyro.x();
        const access::ArmGesture g = twist.update(t, rollRate);
        if (g == access::ArmGesture::Repeat) repeats.fetch_add(1);
        if (g == access::ArmGesture::Skip) skips.fetch_add(1);
    };
    live::GuidedDevice device(choice.port, baud, choice.simulate, unpaced, player,
                              cl.has("--no-gestures") ? live::GuidedDevice::SensorHook {} : live::GuidedDevice::SensorHook(onSensor));
    device.setInterruptCheck(interrupted);
    using Training = procedures::AdaptiveTraining;
    Training training(player);
    int repeatsTaken = 0, skipsTaken = 0;
    Training::Gesture armGesture = Training::Gesture::None;   // the gesture behind the last "?" / "-" (the log's gesture row)
    io.setExtraInput([&]() -> std::string {
        device.checkAlive();   // a device that stopped sending ends the wait (exit 4)
        if (skips.load() > skipsTaken) {
            skipsTaken = skips.load();
            armGesture = Training::Gesture::Skip;
            return "-";
        }
        if (repeats.load() > repeatsTaken) {
            repeatsTaken = repeats.load();
            armGesture = Training::Gesture::Repeat;
            return "?";
        }
        return "";
    });
    const bool perkinsKeys = cl.has("--chords") && io.enableChordKeys();
    training.start(o);   // draws the first trial
    io.status("braille training, session " + std::to_string(training.session()) + ": " + std::to_string(o.trials) + " trials. '?' repeats, '-' skips" +
              (cl.has("--chords") ? "; answer in chords: S D F J K L = dots 3 2 1 4 5 6" : "") +
              (perkinsKeys ? ", Space after each cell, Space again or Enter to answer" : ""));
    const auto start = std::chrono::steady_clock::now();
    auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };   // the reader's own time
    // Whatever ends the session, the files asked for keep what was answered (the procedure saves
    // after every answer; stop() adds the `end` row that says `stopped`).
    bool stopped = false;
    try {
        while (training.state() != Training::State::Done) {
            device.waitUntil([&] { return training.poll() || training.state() == Training::State::Answering; });
            const std::string header = std::to_string(training.trial()) + "/" + std::to_string(training.trials());
            io.prompt("trial " + header + ": " + training.question(), header + " " + training.question());
            const double shownAt = wall();
            std::string answer = io.readLine();
            if (armGesture != Training::Gesture::None && (answer == "?" || answer == "-")) training.noteGesture(armGesture);   // it came from the arm
            armGesture = Training::Gesture::None;
            if (answer == "?") {   // show it again
                training.again();
                continue;
            }
            if (answer != "-" && cl.has("--chords")) {
                std::string letters, why;
                if (!access::chordsToLetters(answer, letters, why)) {
                    io.note("not understood: " + why + "; the letter again");
                    training.again();
                    continue;
                }
                answer = letters;
            }
            if (answer.empty()) {
                training.again();
                continue;
            }
            if (answer == "-") training.skip(wall() - shownAt);
            else training.answer(answer, wall() - shownAt);
            io.note(training.lastVerdict().text);
            if (!training.lastError().empty()) throw core::IoError(training.lastError());
        }
        device.waitUntil([&] { return training.settled(); });   // the last feedback felt to its end
    } catch (const AnswersEnded&) {
        stopped = true;   // the reader stopped answering: a normal end
    } catch (const core::IoError&) {
        if (!interrupted()) {   // the display went away, the device failed: keep the answers, then say so
            training.stop();
            throw;
        }
        stopped = true;   // Ctrl-C
    }
    if (stopped) training.stop();
    if (!training.lastError().empty()) throw core::IoError(training.lastError());
    if (stopped) io.status("training stopped after " + std::to_string(training.answered()) + " of " + std::to_string(training.trials()) + " trials: " +
                           std::to_string(training.right()) + " right; the answers are kept");
    else io.status("training complete: " + std::to_string(training.right()) + " of " + std::to_string(training.trials()) + " right");
    std::cout << training.summaryJson(stopped) << "\n";
    return core::kExitOk;
}

} // namespace armadillo::cli
