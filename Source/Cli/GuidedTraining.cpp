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
#include "Access/AdaptivePlan.h"
#include "Access/ArmGestures.h"
#include "Access/Feedback.h"
#include "Access/Chords.h"
#include "Access/Report.h"
#include "Access/SessionLog.h"
#include "Braille/Reading.h"
#include "Braille/Training.h"
#include "Cli/ReaderIo.h"
#include "Cli/GuidedDevice.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Link/TouchProfile.h"
#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <iostream>
#include <sstream>

namespace armadillo::cli {

using namespace armadillo::braille;

std::vector<OptionSpec> guidedTrainingOptionSpecs()
{
    std::vector<OptionSpec> o {
        {"--adaptive", "", "with --train: the adaptive training on the device, answers typed or chorded (--reader)"},
        {"--reader", "READER.json", "the reader's profile: every answer of every session (created if missing)"},
        {"--report", "READER.json", "print the reader's progress: accuracy per stage and session, letters/min,\n"
                                    "confusions, and the published figures to compare with"},
        {"--port", "NAME", "--adaptive: serial port of the device"},
        {"--simulate", "", "--adaptive: the built-in simulated device"},
        {"--baud", "B", "serial speed (default 57600)"},
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
    o.insert(o.end(), io.begin(), io.end());
    return o;
}

namespace {

constexpr MotorSet kUnderside = motorBit(0, 1) | motorBit(1, 1) | motorBit(2, 1);
constexpr MotorSet kAllNine = 0x1FF;
constexpr MotorSet kOuter = kAllNine & ~kUnderside;

struct Timing {
    double on = 0.4, gap = 0.2, letterGap = 0.5, wordGap = 1.2;   // docs/BRAILLE.md "Passive drawing"
};

/// One log row in the columns of the §4.4.1 log (Access/SessionLog.h).
void logRow(std::string& log, double t, const char* event, const access::PlannedTrial* trial, int number, const std::string& prompt,
            int unit, int step, MotorSet motors, bool hasMotors, const std::string& answer, int correct)
{
    access::appendSessionLogRow(log, t, event, trial, number, prompt, unit, step, motors, hasMotors, answer, correct);
}

class Session {
public:
    Session(TactilePlayer& player, GuidedDevice& device, DisplayMethod method, float level)
        : player_(player), device_(device), method_(method), level_(level), start_(std::chrono::steady_clock::now())
    {
        log_ = access::kSessionLogHeader;
    }

    /// s of session time: the device link's clock (with --unpaced, the packet clock), so the log's
    /// display rows and answers share one time line.
    double now() const { return player_.clock(); }
    /// s of wall-clock time: response times are the reader's own.
    double wall() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
    std::string& log() { return log_; }

    /// Draws a text on the arm (cells one after another); logs each step; waits until done.
    void draw(const std::string& text, int grade, const access::PlannedTrial* trial, int number, double after = 0.0)
    {
        TranslationOptions o;
        o.grade = grade;
        const std::vector<ReadingUnit> units = layoutDocument(translateText(text, o), method_);
        std::vector<TactileSegment> segs;
        double at = 0.0;        // s into the current chunk
        double t0 = now();
        // A long text goes in chunks of whole units (the player takes at most 127 segments at a
        // time); each chunk is played out, stillness included, before the next.
        auto flush = [&](double extra) {
            double length = 0.0;   // a trailing pause row is waited out too
            for (const auto& seg : segs) length = std::max(length, seg.at + seg.duration);
            device_.waitFor(player_.play(segs, std::max(0.0, at - length) + extra));
            segs.clear();
            at = 0.0;
            t0 = now();
        };
        for (std::size_t u = 0; u < units.size(); ++u) {
            const ReadingUnit& unit = units[u];
            if (segs.size() + unit.steps.size() + 1 > 100) flush(0.0);
            if (unit.kind != UnitKind::Cell) {
                segs.push_back({at, 0.15, kUnderside, level_ * 0.6f, true, false});
                logRow(log_, t0 + at, "word-gap", trial, number, "", static_cast<int>(u), 0, 0, false, "", -1);
                at += timing_.wordGap;
                continue;
            }
            for (std::size_t s = 0; s < unit.steps.size(); ++s) {
                if (unit.steps[s] != 0) segs.push_back({at, timing_.on, unit.steps[s], level_, false, false});
                logRow(log_, t0 + at, "row", trial, number, "", static_cast<int>(u), static_cast<int>(s), unit.steps[s], true, "", -1);
                at += timing_.on + (s + 1 < unit.steps.size() ? timing_.gap : timing_.letterGap);
            }
        }
        flush(after);
    }

    /// "A trial begins": the underside line swept wrist → elbow (as the scene's turn-to-forward cue).
    void nextTrial(const access::PlannedTrial* trial, int number)
    {
        logRow(log_, now(), "cue", trial, number, "next", -1, 0, kUnderside, true, "", -1);
        device_.waitFor(player_.play({{0.0, 0.1, motorBit(0, 1), level_ * 0.8f, true, false},
                                      {0.1, 0.1, motorBit(1, 1), level_ * 0.8f, true, false},
                                      {0.2, 0.1, motorBit(2, 1), level_ * 0.8f, true, false}},
                                     0.5));
    }

    /// "Your turn": the underside line tapped twice (the end-of-message cue).
    void yourTurn(const access::PlannedTrial* trial, int number)
    {
        logRow(log_, now(), "cue", trial, number, "your turn", -1, 0, kUnderside, true, "", -1);
        device_.waitFor(player_.play({{0.0, 0.12, kUnderside, level_ * 0.8f, false, false}, {0.22, 0.12, kUnderside, level_ * 0.8f, false, false}}));
    }

    void feedback(bool right, const access::PlannedTrial* trial, int number)
    {
        logRow(log_, now(), "feedback", trial, number, right ? "right" : "wrong", -1, 0, right ? kAllNine : kOuter, true, "", right ? 1 : 0);
        device_.waitFor(player_.play(access::feedbackSensation(right, level_), access::feedbackPause(right)));
    }

private:
    TactilePlayer& player_;
    GuidedDevice& device_;
    DisplayMethod method_;
    float level_;
    Timing timing_;
    std::chrono::steady_clock::time_point start_;
    std::string log_;
};

std::string normalised(std::string s)
{
    std::string out;
    for (unsigned char c : s)
        if (c != ' ' && c != '\t') out += static_cast<char>(std::tolower(c));
    return out;
}

std::string utcNow()
{
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return date;
}

} // namespace

int printProgressReport(const CommandLine& cl)
{
    const std::string path = cl.value("--report");
    if (path.empty()) throw UsageError("--report needs a reader profile");
    if (!std::ifstream(path)) throw IoError("cannot read " + path);
    std::cout << access::progressReport(access::parseReaderProfile(readWholeFile(path), path));
    return kExitOk;
}

int runGuidedTraining(const CommandLine& cl)
{
    const std::string readerPath = cl.value("--reader");
    if (readerPath.empty()) throw UsageError("--adaptive needs --reader READER.json (created if it does not exist)");
    if (cl.has("--port") == cl.has("--simulate")) throw UsageError("--adaptive draws on the arm: choose --port NAME or --simulate");
    for (const char* o : {"--motion", "--answers"})
        if (cl.has(o)) throw UsageError(std::string(o) + " is for the replayed training; --adaptive takes answers live");
    const bool armOnly = cl.has("--arm-only");
    ReaderIo io(cl, armOnly);
    access::ReaderProfile reader = access::loadReaderProfile(readerPath);   // InputError (exit 3) for a bad file
    // Refuse an unwritable profile or log now, not after the reader has answered.
    for (const std::string& out : {readerPath, cl.value("--log")}) {
        if (out.empty()) continue;
        const std::filesystem::path dir = std::filesystem::absolute(out).parent_path();
        if (!std::filesystem::is_directory(dir) || ::access(dir.c_str(), W_OK) != 0) throw IoError("cannot write into " + dir.string());
    }

    access::AdaptiveOptions o;
    o.session = reader.nextSession();
    o.seed = static_cast<std::uint64_t>(cl.integer("--seed", o.session, 0, 2147483647L));
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
    const std::vector<std::string> signWords = cl.has("--words") ? readWordList(cl.value("--words")) : defaultSignWords();
    for (const std::string& w : signWords) {   // lower case; a phrase keeps its spaces (word gaps on the arm)
        std::string k;
        for (unsigned char c : w) k += static_cast<char>(std::tolower(c));
        o.words.push_back(k);
    }
    o.signs = signShorthand(signWords);
    o.contractions = contractionWords();
    const int trials = static_cast<int>(cl.integer("--trials", 30, 1, 10000));
    float level = static_cast<float>(cl.integer("--level", 5, 1, 15));
    access::AdaptivePlanner plan(reader, o);

    TactileConfig tc;
    const std::string arm = cl.value("--arm", "right");
    if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
    tc.side = arm == "left" ? ArmSide::Left : ArmSide::Right;
    if (cl.has("--profile")) {
        const device::TouchProfile touch = device::loadTouchProfile(cl.value("--profile"));
        tc.motorGain = device::touchProfileGains(touch);
        // Without --level the cells come at the reader's comfortable level: the level that, after
        // the profile's gain, gives the comfort motor what the reader chose as comfortable.
        const std::size_t cm = static_cast<std::size_t>(touch.comfortMotor - 1);
        if (!cl.has("--level") && touch.comfort > 0 && tc.motorGain[cm] > 0.0f)
            level = std::clamp(static_cast<float>(touch.comfort) / tc.motorGain[cm], 1.0f, 15.0f);
    }
    const int baud = static_cast<int>(cl.integer("--baud", 57600, 300, 4000000));
    const bool unpaced = cl.has("--unpaced");
    const std::string logPath = cl.value("--log");
    TactilePlayer player(tc, unpaced ? 1.0 / device::lockStepRate(baud) : 0.0);
    installInterruptHandlers();
    // Arm gestures: a twist of the forearm and back = '?' (again), two = '-' (skip). Detected on
    // the control thread from the calibrated roll rate; handed over in atomics.
    const device::Calibration calibration = cl.has("--calibration") ? device::loadCalibration(cl.value("--calibration")) : device::defaultCalibration();
    access::TwistDetector twist;
    std::atomic<int> repeats {0}, skips {0};
    auto onSensor = [&](const device::SensorCounts& counts, double t) {
        const double rollRate = calibration.apply(t, counts).gyro.x();
        const access::ArmGesture g = twist.update(t, rollRate);
        if (g == access::ArmGesture::Repeat) repeats.fetch_add(1);
        if (g == access::ArmGesture::Skip) skips.fetch_add(1);
    };
    GuidedDevice device(cl.value("--port"), baud, cl.has("--simulate"), unpaced, player,
                        cl.has("--no-gestures") ? GuidedDevice::SensorHook {} : GuidedDevice::SensorHook(onSensor));
    int repeatsTaken = 0, skipsTaken = 0;
    std::string armGesture;   // the gesture behind the last "?" / "-" (the log's gesture row)
    io.setExtraInput([&]() -> std::string {
        if (skips.load() > skipsTaken) {
            skipsTaken = skips.load();
            armGesture = "two twists";
            return "-";
        }
        if (repeats.load() > repeatsTaken) {
            repeatsTaken = repeats.load();
            armGesture = "twist";
            return "?";
        }
        return "";
    });
    Session session(player, device, method, level);
    const bool perkinsKeys = cl.has("--chords") && io.enableChordKeys();

    const std::size_t historyAnswers = reader.answers.size();
    auto save = [&](double seconds) {
        access::ReaderProfile out = reader;
        out.answers = plan.answers();
        out.sessions.push_back({o.session, utcNow(), o.method, seconds});
        access::saveReaderProfile(readerPath, out);
    };
    io.status("braille training, session " + std::to_string(o.session) + ": " + std::to_string(trials) + " trials. '?' repeats, '-' skips" +
              (cl.has("--chords") ? "; answer in chords: S D F J K L = dots 3 2 1 4 5 6" : "") +
              (perkinsKeys ? ", Space after each cell, Space again or Enter to answer" : ""));
    int right = 0, done = 0;
    // Whatever ends the session, the files asked for keep what was answered.
    auto finish = [&](bool early) {
        logRow(session.log(), session.now(), "end", nullptr, 0, "", -1, 0, 0, false, early ? "stopped" : "", -1);
        save(session.now());
        if (!logPath.empty()) writeFileAtomically(logPath, session.log());
    };
    bool stopped = false;
    try {
        for (int n = 1; n <= trials; ++n) {
            const access::PlannedTrial trial = plan.next();
            const int grade = trial.stage == "contractions" ? 2 : 1;
            const std::string header = std::to_string(n) + "/" + std::to_string(trials);
            logRow(session.log(), session.now(), "trial", &trial, n, trial.prompt, -1, 0, 0, false, "", -1);
            std::string answer;
            double shownAt = 0.0;
            for (;;) {
                session.nextTrial(&trial, n);
                session.draw(trial.shown, grade, &trial, n);
                session.yourTurn(&trial, n);
                shownAt = session.wall();
                io.prompt("trial " + header + ": " + trial.prompt, header + " " + trial.prompt);
                answer = io.readLine();
                if (!armGesture.empty() && (answer == "?" || answer == "-"))   // it came from the arm
                    logRow(session.log(), session.now(), "gesture", &trial, n, "", -1, 0, 0, false, armGesture, -1);
                armGesture.clear();
                if (answer == "?") continue;   // show it again
                if (answer == "-") break;
                if (cl.has("--chords")) {
                    std::string letters, why;
                    if (!access::chordsToLetters(answer, letters, why)) {
                        io.note("not understood: " + why + "; the letter again");
                        continue;
                    }
                    answer = letters;
                }
                if (!answer.empty()) break;
            }
            const double rt = session.wall() - shownAt;
            const bool skipped = answer == "-";
            const std::string given = skipped ? "(skipped)" : normalised(answer);
            const bool correct = !skipped && given == normalised(trial.expected);   // spaces do not count
            right += correct;
            plan.record(trial, given, correct, rt, session.now());
            logRow(session.log(), session.now(), "answer", &trial, n, "", -1, 0, 0, false, given, correct ? 1 : 0);
            if (correct) io.note("right");
            else io.note("wrong: it was '" + trial.expected + "'" + (skipped ? "" : ", you said '" + given + "'"));
            session.feedback(correct, &trial, n);
            if (!correct) {
                // The right cell again; when the answer was another letter, that one next to it.
                std::string again = trial.shown;
                if (trial.stage == "letters" && given.size() == 1 && given[0] >= 'a' && given[0] <= 'z') again += " " + given;
                session.draw(again, grade, &trial, n);
            }
            save(session.now());   // nothing lost if the session is cut short
            ++done;
            // Stillness between trials (the reader can tell the next trial from the replay).
            device.waitFor(player.play({}, 2.0));
        }
    } catch (const AnswersEnded&) {
        stopped = true;   // the reader stopped answering: a normal end
    } catch (const IoError&) {
        if (!interrupted()) {   // the display went away, the device failed: keep the answers, then say so
            finish(true);
            throw;
        }
        stopped = true;   // Ctrl-C
    }
    finish(stopped);
    if (stopped) io.status("training stopped after " + std::to_string(done) + " of " + std::to_string(trials) + " trials: " +
                           std::to_string(right) + " right; the answers are kept");
    else io.status("training complete: " + std::to_string(right) + " of " + std::to_string(trials) + " right");
    std::cout << "{\"session\":" << o.session << ",\"trials\":" << trials << ",\"trials_done\":" << done
              << ",\"stopped\":" << (stopped ? "true" : "false") << ",\"correct\":" << right
              << ",\"answers_in_profile\":" << plan.answers().size() << ",\"history\":" << historyAnswers << "}\n";
    return kExitOk;
}

} // namespace armadillo::cli
