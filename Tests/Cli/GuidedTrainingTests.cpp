// `armadillo braille --train --adaptive` end to end (issue 26's done-when): a whole session on a
// pty device answered by a simulated reader who reads only the arm — it decodes each cell from
// the motor packets (rows method, docs/BRAILLE.md: braille row r on motor row r, the left dot on
// column 0, the right dot on column 2), waits for the "your turn" cue (the underside line 2,5,8
// tapped twice; a trial starts with the line swept wrist → elbow), answers in Perkins chords, and feels right (all nine motors) or wrong (the outer
// columns) — with nothing on the screen (--arm-only); and the same session with speech and the
// braille display captured, every prompt and feedback reaching both.
#include "CliRun.h"
#include "Common/FakeBrlApi.h"
#include "Core/AtomicFile.h"
#include "PtyDevice.h"
#include <algorithm>
#include <filesystem>
#include <atomic>
#include <map>
#include <memory>
#include <thread>
#include <sstream>
#include <termios.h>

using namespace armadillo::cli;

namespace {

// Grade 1 letters by dots, written out by hand (dot d = bit d−1).
const std::map<int, char>& letterOfDots()
{
    static const std::map<int, char> table = [] {
        const std::pair<const char*, char> rows[] {{"1", 'a'}, {"12", 'b'}, {"14", 'c'}, {"145", 'd'}, {"15", 'e'}, {"124", 'f'}, {"1245", 'g'},
                                                   {"125", 'h'}, {"24", 'i'}, {"245", 'j'}, {"13", 'k'}, {"123", 'l'}, {"134", 'm'}, {"1345", 'n'},
                                                   {"135", 'o'}, {"1234", 'p'}, {"12345", 'q'}, {"1235", 'r'}, {"234", 's'}, {"2345", 't'},
                                                   {"136", 'u'}, {"1236", 'v'}, {"2456", 'w'}, {"1346", 'x'}, {"13456", 'y'}, {"1356", 'z'}};
        std::map<int, char> t;
        for (const auto& [dots, c] : rows) {
            int bits = 0;
            for (const char* d = dots; *d; ++d) bits |= 1 << (*d - '1');
            t[bits] = c;
        }
        return t;
    }();
    return table;
}

std::string chordOf(int bits)
{
    static const char keys[6] {'f', 'd', 's', 'j', 'k', 'l'};   // dots 1..6 on the Perkins home row
    std::string out;
    for (int d = 0; d < 6; ++d)
        if (bits & (1 << d)) out += keys[d];
    return out;
}

struct ArmReaderRun {
    int code = -1;
    std::vector<std::string> answers;   // what the reader answered (letters)
    std::vector<bool> feltRight;        // the feedback felt on the arm after each answer
    std::vector<bool> shouldBeRight;    // the reader's own knowledge: was the answer the cell shown?
    int twisted = 0;                    // trials the reader asked again for with a twist of the arm
    std::string err;
};

/// The reader who reads the arm and always mixes up e and i.
/// With `twistAt` ≥ 0 the reader answers that trial's first your-turn cue with a twist of the
/// forearm and back (≈ 6 rad/s each way for 0.1 s: "again") instead of an answer.
ArmReaderRun runArmReader(const std::string& reader, const std::string& log, int trials, const std::vector<std::string>& extra,
                          int twistAt = -1)
{
    std::vector<std::string> args {"braille", "--train", "--adaptive", "--reader", reader, "--unpaced", "--trials", std::to_string(trials),
                                   "--log", log, "--chords", "--seed", "5"};
    args.insert(args.end(), extra.begin(), extra.end());
    test::PtyDevice dev(args);
    ArmReaderRun r;
    enum class State { Collect, Await, Replay } state = State::Collect;
    std::vector<int> cells;       // dots of the cells of this trial
    int previousSet = 0;
    long packet = 0, lastTapStart = -100000;
    int taps = 0, twistLeft = 0;
    constexpr int kUnderside = (1 << 1) | (1 << 4) | (1 << 7);
    constexpr int kAll = 0x1FF;
    constexpr int kOuter = kAll & ~kUnderside;
    dev.run(
        [&](const test::Levels& levels) {
            ++packet;
            if (twistLeft > 0) {   // default calibration: 600 °/s over 2048 counts, 1200 counts ≈ 6.1 rad/s
                dev.setGyroX(--twistLeft > 30 ? 1200 : twistLeft > 0 ? -1200 : 0);
            }
            int set = 0;
            for (int m = 0; m < 9; ++m)
                if (levels[static_cast<std::size_t>(m)] > 0) set |= 1 << m;
            const bool newStep = set != 0 && set != previousSet;
            previousSet = set;
            if (set == (1 << 7) && newStep) {   // the elbow end of the "next" sweep: a new trial
                state = State::Collect;
                cells.clear();
                taps = 0;
                return;
            }
            switch (state) {
            case State::Collect:
                if (!newStep || set == (1 << 1) || set == (1 << 4)) break;   // the sweep's first two steps
                if (set == kUnderside) {   // a tap of the underside line
                    taps = packet - lastTapStart < 150 ? taps + 1 : 1;   // within 0.5 s: the same cue
                    lastTapStart = packet;
                    if (taps == 2 && static_cast<int>(r.answers.size()) == twistAt && r.twisted == 0) {
                        ++r.twisted;             // "again", by the arm: the trial comes back
                        twistLeft = 61;
                        state = State::Replay;   // until the next sweep
                        break;
                    }
                    if (taps == 2) {   // your turn
                        std::string letters, chords, truth;
                        for (int c : cells) {
                            const auto it = letterOfDots().find(c);
                            const char seen = it == letterOfDots().end() ? '?' : it->second;
                            const char said = seen == 'e' ? 'i' : seen == 'i' ? 'e' : seen;
                            truth += seen;
                            letters += said;
                            for (const auto& [bits, ch] : letterOfDots())
                                if (ch == said) chords += (chords.empty() ? "" : " ") + chordOf(bits);
                        }
                        r.answers.push_back(letters);
                        r.shouldBeRight.push_back(letters == truth);
                        dev.answer(chords);
                        state = State::Await;
                    }
                    break;
                }
                // A row of a cell: the wrist row starts a new cell.
                if (set & 0x7) cells.push_back(0);
                if (cells.empty()) cells.push_back(0);
                for (int m = 0; m < 9; ++m)
                    if (set & (1 << m)) {
                        const int row = m / 3, col = m % 3;
                        if (col == 0) cells.back() |= 1 << row;
                        if (col == 2) cells.back() |= 1 << (row + 3);
                    }
                break;
            case State::Await:
                if (set == kAll || set == kOuter) {
                    r.feltRight.push_back(set == kAll);
                    state = State::Replay;
                }
                break;
            case State::Replay: break;   // the right cell again, until the next trial's sweep
            }
        },
        [&](const std::string&) {});
    r.code = dev.wait();
    r.err = dev.err;
    return r;
}

std::vector<std::vector<std::string>> csvRows(const std::string& text)
{
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> f;
        std::string cur;
        bool quoted = false;
        for (char c : line) {
            if (c == '"') quoted = !quoted;
            else if (c == ',' && !quoted) {
                f.push_back(cur);
                cur.clear();
            } else cur += c;
        }
        f.push_back(cur);
        rows.push_back(f);
    }
    return rows;
}

} // namespace

TEST_CASE("adaptive training with no screen and no sound: the arm alone carries it, the log has every answer", "[cli][adaptive][pty]")
{
    const std::string reader = path("arm-reader.json"), log = path("arm-training.csv");
    // An earlier session in which the reader mixed up e and i: the plan brings them back.
    std::string history = "{\"format\": \"armadillo-reader\", \"version\": 1, \"answers\": [";
    for (int k = 0; k < 3; ++k)
        history += std::string(k ? "," : "") +
                   "{\"session\": 1, \"stage\": \"letters\", \"expected\": \"e\", \"answer\": \"i\", \"correct\": false},"
                   "{\"session\": 1, \"stage\": \"letters\", \"expected\": \"i\", \"answer\": \"e\", \"correct\": false}";
    file("arm-reader.json", history + "]}");
    const int trials = 14;
    const ArmReaderRun r = runArmReader(reader, log, trials, {"--arm-only"}, 3);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.empty());   // nothing on the screen
    REQUIRE(r.answers.size() == static_cast<std::size_t>(trials));
    CHECK(r.feltRight == r.shouldBeRight);   // the arm said right exactly when it was
    CHECK(std::count(r.feltRight.begin(), r.feltRight.end(), false) >= 2);   // e and i came back, and were missed
    CHECK(std::count(r.feltRight.begin(), r.feltRight.end(), true) >= 2);
    // The log: one answer row per trial, holding what the reader chorded, scored as the reader knows.
    const auto rows = csvRows(armadillo::core::readWholeFile(log));
    REQUIRE(!rows.empty());
    CHECK(rows[0].size() == 13);
    std::vector<std::string> logged;
    std::vector<bool> scored;
    for (const auto& row : rows)
        if (row.size() == 13 && row[1] == "answer") {
            logged.push_back(row[11]);
            scored.push_back(row[12] == "1");
        }
    CHECK(logged == r.answers);
    CHECK(scored == r.shouldBeRight);
    // The twist of the arm showed trial 4 again: its "next" cue is in the log twice, the others once.
    REQUIRE(r.twisted == 1);
    std::map<std::string, int> nextCues;
    for (const auto& row : rows)
        if (row.size() == 13 && row[1] == "cue" && row[5] == "next") ++nextCues[row[3]];
    CHECK(nextCues["4"] == 2);
    CHECK(nextCues["3"] == 1);
    CHECK(nextCues["5"] == 1);
    // ... and the log says it came from the arm: one gesture row, trial 4, "twist".
    int gestures = 0;
    for (const auto& row : rows)
        if (row.size() == 13 && row[1] == "gesture") {
            ++gestures;
            CHECK(row[3] == "4");
            CHECK(row[11] == "twist");
        }
    CHECK(gestures == 1);
    // The profile kept every answer.
    const std::string profile = armadillo::core::readWholeFile(reader);
    CHECK(profile.find("\"format\": \"armadillo-reader\"") != std::string::npos);
    std::size_t n = 0;
    for (std::size_t at = 0; (at = profile.find("\"expected\"", at)) != std::string::npos; ++at) ++n;
    CHECK(n >= static_cast<std::size_t>(trials) + 6);
    CHECK(profile.find("\"session\": 2") != std::string::npos);
}

TEST_CASE("adaptive training with speech and a braille display captured: every prompt and feedback reaches both", "[cli][adaptive][pty]")
{
    const std::string reader = path("voiced-reader.json"), log = path("voiced-training.csv");
    const std::string speech = path("speech.txt"), display = path("display.txt");
    for (const auto& f : {reader, speech, display}) std::filesystem::remove(f);
    const int trials = 8;
    const ArmReaderRun r = runArmReader(reader, log, trials, {"--speech", "capture:" + speech, "--braille-display", "capture:" + display});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string said = armadillo::core::readWholeFile(speech), shown = armadillo::core::readWholeFile(display);
    INFO(said);
    INFO(shown);
    for (int k = 1; k <= trials; ++k) {
        const std::string n = std::to_string(k) + "/" + std::to_string(trials);
        CHECK(said.find("say: trial " + n + ": ") != std::string::npos);   // the prompt, interrupting
        CHECK(shown.find("write: " + n + " ") != std::string::npos);
        CHECK(r.err.find("? trial " + n + ": ") != std::string::npos);    // and on the screen
    }
    auto count = [](const std::string& text, const std::string& what) {
        std::size_t c = 0;
        for (std::size_t at = 0; (at = text.find(what, at)) != std::string::npos; ++at) ++c;
        return c;
    };
    CHECK(count(said, "say+: right\n") + count(said, "say+: wrong: it was") == static_cast<std::size_t>(trials));
    CHECK(count(shown, "write: right\n") + count(shown, "write: wrong: it was") == static_cast<std::size_t>(trials));
    CHECK(said.find("say+: training complete") != std::string::npos);
    CHECK(shown.find("write: training complete") != std::string::npos);
    // The reader's report of the two sessions in one profile shows the e/i confusion when it came up.
    const Run report = runArmadillo("braille --report " + reader);
    CHECK(report.code == 0);
    CHECK(report.out.find("confusions") != std::string::npos);
}

TEST_CASE("adaptive training stopped early keeps every answer given, in the log and the profile", "[cli][adaptive]")
{
    // Issue 32: a reader who stops answering after 20 of 60 trials (end of input) ended with exit 3
    // and no log. Stopping is a normal end: exit 0, the log asked for holds the 20 answers and an
    // `end` row that says `stopped`, the profile keeps them, the summary says so.
    const std::string reader = path("stop-reader.json"), log = path("stop-training.csv");
    std::filesystem::remove(reader);
    std::filesystem::remove(log);
    std::string lines;
    for (int i = 0; i < 20; ++i) lines += (i % 2 ? "e\n" : "a\n");
    const std::string answers = file("stop-answers.txt", lines);
    const Run r = runArmadilloWithin(300, "braille --train --adaptive --reader " + reader + " --simulate --unpaced --trials 60 --seed 4 --log " + log,
                                     answers);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.out.find("\"trials\":60") != std::string::npos);
    CHECK(r.out.find("\"trials_done\":20") != std::string::npos);
    CHECK(r.out.find("\"stopped\":true") != std::string::npos);
    CHECK(r.err.find("training stopped after 20 of 60 trials") != std::string::npos);
    REQUIRE(std::filesystem::exists(log));
    const auto rows = csvRows(armadillo::core::readWholeFile(log));
    int answered = 0, ends = 0;
    for (const auto& row : rows) {
        if (row.size() != 13) continue;
        if (row[1] == "answer") ++answered;
        if (row[1] == "end") {
            ++ends;
            CHECK(row[11] == "stopped");
        }
    }
    CHECK(answered == 20);
    CHECK(ends == 1);
    CHECK(rows.back()[1] == "end");
    const std::string profile = armadillo::core::readWholeFile(reader);
    std::size_t n = 0;
    for (std::size_t at = 0; (at = profile.find("\"expected\"", at)) != std::string::npos; ++at) ++n;
    CHECK(n >= 20);   // a confused pair is also recorded as its letters
    CHECK(n < 60);
    // A session that runs to its end says so too: no `stopped`.
    const std::string log2 = path("full-training.csv");
    const Run full = runArmadilloWithin(300, "braille --train --adaptive --reader " + path("full-reader.json") +
                                                 " --simulate --unpaced --trials 3 --seed 4 --log " + log2, file("full-answers.txt", "a\nb\nc\n"));
    CHECK(full.code == 0);
    CHECK(full.out.find("\"stopped\":false") != std::string::npos);
    const auto rows2 = csvRows(armadillo::core::readWholeFile(log2));
    REQUIRE(!rows2.empty());
    CHECK(rows2.back()[1] == "end");
    CHECK(rows2.back()[11].empty());
}

TEST_CASE("adaptive training: bad usage and bad files are refused", "[cli][adaptive]")
{
    CHECK(runArmadillo("braille --train --adaptive --simulate").code == 2);                       // no --reader
    CHECK(runArmadillo("braille --train --adaptive --reader " + path("r.json")).code == 2);         // no device
    CHECK(runArmadillo("braille --adaptive --reader " + path("r.json") + " --simulate").code == 2); // not --train
    CHECK(runArmadillo("braille --text exit --chords").code == 2);                                  // adaptive-only option
    const std::string bad = file("bad-reader.json", "{\"format\": \"armadillo-reader\", \"answers\": [{\"session\": 1}]}");
    const Run r = runArmadillo("braille --train --adaptive --reader " + bad + " --simulate --unpaced");
    CHECK(r.code == 3);
    CHECK(r.err.find("bad-reader.json") != std::string::npos);
    CHECK(runArmadillo("braille --report " + path("missing.json")).code == 4);
    CHECK(runArmadillo("braille --train --adaptive --reader /nonexistent/dir/r.json --simulate --unpaced").code == 4);
    CHECK(runArmadillo("braille --report " + bad).code == 3);
    CHECK(runArmadillo("braille --train --adaptive --reader " + path("r2.json") + " --simulate --speech klingon").code == 2);
}

TEST_CASE("adaptive training: Perkins keys on a terminal — S D F J K L, Space ends a cell, Enter or a second Space answers", "[cli][adaptive][pty]")
{
    int master = -1, slave = -1;
    REQUIRE(::openpty(&master, &slave, nullptr, nullptr, nullptr) == 0);
    const std::string reader = path("keys-reader.json"), log = path("keys-training.csv"), err = path("keys-stderr.txt");
    std::filesystem::remove(reader);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::dup2(slave, 0);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(e, 2);
        const int out = ::open("/dev/null", O_WRONLY);
        ::dup2(out, 1);
        ::close(master);
        ::execl(ARMADILLO_BIN, ARMADILLO_BIN, "braille", "--train", "--adaptive", "--reader", reader.c_str(), "--simulate", "--unpaced",
                "--chords", "--trials", "3", "--log", log.c_str(), nullptr);
        ::_exit(127);
    }
    // Typed ahead: b (f d, Space, Space); e (f k, Enter); b again after taking back a dot
    // (f d j, Backspace, Space, Enter).
    const std::string keys = "df  fk\rfdj\x7f \r";
    REQUIRE(::write(master, keys.data(), keys.size()) == static_cast<ssize_t>(keys.size()));
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (::waitpid(pid, &status, WNOHANG) == 0) {
        char buf[256];
        pollfd p {master, POLLIN, 0};
        if (::poll(&p, 1, 20) > 0) (void)!::read(master, buf, sizeof buf);
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(pid, SIGTERM);
            ::waitpid(pid, &status, 0);
            FAIL("the training did not finish");
        }
    }
    termios after {};
    REQUIRE(::tcgetattr(slave, &after) == 0);
    CHECK((after.c_lflag & ICANON) != 0);   // the terminal is given back as it was
    CHECK((after.c_lflag & ECHO) != 0);
    ::close(master);
    ::close(slave);
    INFO(armadillo::core::readWholeFile(err));
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    std::vector<std::string> answers;
    for (const auto& row : csvRows(armadillo::core::readWholeFile(log)))
        if (row.size() == 13 && row[1] == "answer") answers.push_back(row[11]);
    CHECK(answers == std::vector<std::string> {"b", "e", "b"});
}

TEST_CASE("play --training-log with speech and a braille display captured: the §4.4.1 prompts and results reach both", "[cli][adaptive]")
{
    const Run plan = runArmadillo("braille --plan --seed 3");
    REQUIRE(plan.code == 0);
    std::vector<std::string> expected;
    {
        std::istringstream in(plan.out);
        std::string line;
        std::getline(in, line);   // header
        while (std::getline(in, line)) expected.push_back(line.substr(line.rfind(',') + 1));
    }
    REQUIRE(expected.size() > 20);
    std::string answers;
    for (const auto& e : expected) answers += e + "\n";
    const std::string speech = path("play-speech.txt"), display = path("play-display.txt");
    for (const auto& f : {speech, display}) std::filesystem::remove(f);
    const Run r = runArmadillo("play --scene braille --simulate --seed 3 --seconds 120 --no-audio --training-log " + path("play-training.csv") +
                                   " --speech capture:" + speech + " --braille-display capture:" + display,
                               file("play-answers.txt", answers));
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string said = armadillo::core::readWholeFile(speech), shown = armadillo::core::readWholeFile(display);
    const std::string n = std::to_string(expected.size());
    for (std::size_t k = 1; k <= expected.size(); ++k) {
        const std::string prompt = "trial " + std::to_string(k) + " of " + n + ": ";
        CHECK(said.find("say: " + prompt) != std::string::npos);
        CHECK(shown.find("write: " + prompt) != std::string::npos);
    }
    auto count = [](const std::string& text, const std::string& what) {
        std::size_t c = 0;
        for (std::size_t at = 0; (at = text.find(what, at)) != std::string::npos; ++at) ++c;
        return c;
    };
    CHECK(count(said, "say+: correct") + count(said, "say+: wrong") == expected.size());
    CHECK(count(shown, "write: correct") + count(shown, "write: wrong") == expected.size());
    CHECK(said.find("say+: braille training complete") != std::string::npos);
    // stderr is what it always was.
    CHECK(r.err.find("braille training 1/" + n + ": ") != std::string::npos);
}

TEST_CASE("adaptive training on a braille display alone: prompts and feedback to a fake BrlAPI server, answers from its keys", "[cli][adaptive][brlapi]")
{
    armadillo::test::FakeBrlApiServer server;
    REQUIRE(server.ok());
    // The reader answers every prompt on the display's keyboard: "b" on the first, "x" on the others.
    int prompts = 0;
    server.onWrite([&](const std::string& text) {
        if (text.find(" which letter?") == std::string::npos) return;
        server.type(++prompts == 1 ? "b\n" : "x\n");
    });
    const std::string log = path("brlapi-training.csv"), reader = path("brlapi-reader.json");
    std::filesystem::remove(reader);
    const Run r = runArmadillo("braille --train --adaptive --reader " + reader + " --simulate --unpaced --trials 3 --log " + log +
                              " --braille-display brlapi:" + server.host());
    INFO(r.err);
    if (r.code == 4 && r.err.find("not found") != std::string::npos) {
        WARN("libbrlapi is not installed here: " + r.err);
        return;
    }
    REQUIRE(r.code == 0);
    CHECK(server.enteredTty());
    std::vector<std::string> answers;
    for (const auto& row : csvRows(armadillo::core::readWholeFile(log)))
        if (row.size() == 13 && row[1] == "answer") answers.push_back(row[11]);
    CHECK(answers == std::vector<std::string> {"b", "x", "x"});
    const auto writes = server.writes();
    auto has = [&](const std::string& prefix) {
        return std::any_of(writes.begin(), writes.end(), [&](const std::string& w) { return w.rfind(prefix, 0) == 0; });
    };
    for (const char* p : {"1/3 which letter?", "2/3 which letter?", "3/3 which letter?", "training complete"}) CHECK(has(p));
    CHECK(std::count_if(writes.begin(), writes.end(), [](const std::string& w) { return w == "right" || w.rfind("wrong: it was", 0) == 0; }) == 3);
}

TEST_CASE("adaptive training with a touch profile: cells at the reader's comfortable level", "[cli][adaptive][pty]")
{
    // Thresholds all 4 (gains 1), comfortable level 8 on m5: the cells come at 8 instead of 5.
    auto levelsSeen = [](const std::vector<std::string>& extra) {
        const std::string reader = path("comfort-reader.json");
        std::filesystem::remove(reader);
        std::vector<std::string> args {"braille", "--train", "--adaptive", "--reader", reader, "--unpaced", "--trials", "4"};
        args.insert(args.end(), extra.begin(), extra.end());
        test::PtyDevice dev(args);
        std::map<int, int> seen;   // level → packets, over all motors
        dev.run(
            [&](const test::Levels& l) {
                for (int x : l) ++seen[x];
            },
            [&](const std::string& line) {
                if (line.rfind("? ", 0) == 0) dev.answer("a");
            });
        INFO(dev.err);
        CHECK(dev.wait() == 0);
        return seen;
    };
    const auto plain = levelsSeen({});
    const auto comfortable = levelsSeen({"--profile", file("comfort.json", "{\"threshold\": [4, 4, 4, 4, 4, 4, 4, 4, 4], \"comfort\": 8}")});
    CHECK(plain.count(8) == 0);   // default: cells at 5, cues at 4, the wrong buzz at 5
    CHECK(comfortable.count(8) == 1);
}

TEST_CASE("adaptive training: a braille display that goes away ends the session with exit 4, not a hang", "[cli][adaptive][brlapi]")
{
    auto server = std::make_unique<armadillo::test::FakeBrlApiServer>();
    REQUIRE(server->ok());
    std::atomic<bool> gone {false};
    armadillo::test::FakeBrlApiServer* raw = server.get();
    // The display vanishes at the first prompt (its server closes the connection).
    std::thread killer;
    raw->onWrite([&](const std::string& text) {
        if (text.find("which letter?") != std::string::npos && !gone.exchange(true)) killer = std::thread([&] { server.reset(); });
    });
    const Run r = runArmadillo("braille --train --adaptive --reader " + path("gone-reader.json") + " --simulate --unpaced --trials 3" +
                              " --braille-display brlapi:" + raw->host());
    if (killer.joinable()) killer.join();
    INFO(r.err);
    if (r.code == 4 && r.err.find("not found") != std::string::npos) return;   // no libbrlapi here
    CHECK(gone.load());
    CHECK(r.code == 4);
    CHECK(r.err.find("went away") != std::string::npos);
}
