#include "CliRun.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fcntl.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

using armadillo::cli::runArmadillo;
using armadillo::cli::file;
using armadillo::cli::workDir;
using armadillo::cli::Run;

TEST_CASE("cli: --help lists every subcommand, and each subcommand has --help", "[cli]")
{
    const Run r = runArmadillo("--help");
    CHECK(r.code == 0);
    for (const char* c : {"ports", "fuse", "render", "play", "braille"}) {
        CHECK(r.out.find(std::string("  ") + c + " ") != std::string::npos);
        const Run h = runArmadillo(std::string(c) + " --help");
        CHECK(h.code == 0);
        CHECK(h.out.find("usage: armadillo " + std::string(c)) != std::string::npos);
    }
}

TEST_CASE("cli: bad usage exits 2 with a message", "[cli]")
{
    CHECK(runArmadillo("").code == 2);
    const Run unknown = runArmadillo("juggle");
    CHECK(unknown.code == 2);
    CHECK(unknown.err.find("unknown command 'juggle'") != std::string::npos);
    const Run opt = runArmadillo("render --scene monitor --motion x.csv --out y.wav --bogus");
    CHECK(opt.code == 2);
    CHECK(opt.err.find("--bogus") != std::string::npos);
    CHECK(runArmadillo("render --scene kazoo --motion x.csv --out y.wav").code == 2);
    CHECK(runArmadillo("render --scene monitor --out y.wav").code == 2);   // missing --motion
    CHECK(runArmadillo("render --scene monitor --motion x.csv --out y.wav --sample-rate fast").code == 2);
}

TEST_CASE("cli: bad input exits 3 naming file, line and column; nothing is written", "[cli]")
{
    const std::string motion = file("bad.csv", "t,elevation,azimuth,roll\n0,0,0,0\n0.1,abc,0,0\n");
    const std::string out = (workDir() / "never.wav").string();
    const Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --out '" + out + "'");
    CHECK(r.code == 3);
    CHECK(r.err.find("bad.csv:3: column 'elevation'") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    const std::string backwards = file("back.csv", "t,elevation,azimuth,roll\n1,0,0,0\n0,0,0,0\n");
    CHECK(runArmadillo("render --scene monitor --motion '" + backwards + "' --out '" + out + "'").code == 3);
    CHECK(runArmadillo("render --scene monitor --motion '" + file("empty.csv", "") + "' --out '" + out + "'").code == 3);
}

TEST_CASE("cli: I/O failure exits 4", "[cli]")
{
    const Run r = runArmadillo("render --scene monitor --motion /nonexistent/motion.csv --out x.wav");
    CHECK(r.code == 4);
    CHECK(r.err.find("/nonexistent/motion.csv") != std::string::npos);
    const std::string motion = file("ok.csv", "t,elevation,azimuth,roll\n0,0,0,0\n0.1,0,0,0\n");
    CHECK(runArmadillo("render --scene monitor --motion '" + motion + "' --out /nonexistent/dir/out.wav").code == 4);
}

TEST_CASE("cli: render writes the WAV, one tactile row per motion row and the all-off sent at the end", "[cli]")
{
    std::string rows = "t,elevation,azimuth,roll\n";
    for (int i = 0; i < 50; ++i) rows += std::to_string(i * 0.01) + ",5,0,0\n";
    const std::string motion = file("motion.csv", rows);
    const std::string wav = (workDir() / "m.wav").string(), tactile = (workDir() / "m.csv").string();
    const Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --out '" + wav + "' --tactile '" + tactile + "'");
    REQUIRE(r.code == 0);
    CHECK(fs::file_size(wav) > 44);
    const std::string t = armadillo::core::readWholeFile(tactile);
    CHECK(t.rfind("t,m1,m2,m3,m4,m5,m6,m7,m8,m9\n", 0) == 0);
    CHECK(std::count(t.begin(), t.end(), '\n') == 52);   // header, 50 rows, the all-off
    CHECK(t.substr(t.rfind('\n', t.size() - 2) + 1) == "0.49,0,0,0,0,0,0,0,0,0\n");   // at the last row's time (no --tail)
}

TEST_CASE("cli: render sets scene parameters with --param and refuses unknown ones as bad usage", "[cli]")
{
    std::string rows = "t,elevation,azimuth,roll\n";
    for (int i = 0; i < 20; ++i) rows += std::to_string(i * 0.01) + ",0,0,0\n";
    const std::string motion = file("param.csv", rows);
    const std::string out = (workDir() / "param.wav").string();
    CHECK(runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + out + "' --param theremin.range=24").code == 0);
    const Run bad = runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + out + "' --param theremin.colour=red");
    CHECK(bad.code == 2);   // INTERFACES.md: a bad option value is bad usage
    CHECK(bad.err.find("--param theremin.colour=red") != std::string::npos);
    const Run range = runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + out + "' --param theremin.range=1000");
    CHECK(range.code == 2);
    CHECK(range.err.find("not a valid value") != std::string::npos);
    CHECK(runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + out + "' --param novalue").code == 2);
}

TEST_CASE("cli: the shipped scores play from any folder without the source tree; a user's own score is found by name", "[cli][resources]")
{
    // A user elsewhere: another working folder, an empty home, no ARMADILLO_RESOURCES. Only the
    // bytes compiled into the program can provide the score.
    const fs::path elsewhere = workDir() / "elsewhere";
    const fs::path home = elsewhere / "home";
    fs::create_directories(home);
    std::string rows = "t,elevation,azimuth,roll\n";
    for (int i = 0; i < 400; ++i) rows += std::to_string(i * 0.01) + ",0,0,0\n";
    const std::string motion = file("still.csv", rows);
    const std::string env = "cd '" + elsewhere.string() + "' && HOME='" + home.string() + "' XDG_DATA_HOME= ARMADILLO_RESOURCES= ";
    auto run = [&](const std::string& args) {
        const std::string out = (elsewhere / "out.txt").string();
        const int status = std::system((env + "'" + ARMADILLO_BIN + "' " + args + " >'" + out + "' 2>&1").c_str());
        return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, armadillo::core::readWholeFile(out));
    };
    for (const char* score : {"rite-of-spring", "polytope"}) {
        INFO(score);
        const auto [code, output] = run(std::string("render --scene score --score ") + score + " --motion '" + motion +
                                        "' --out s.wav --tactile s.csv");
        INFO(output);
        REQUIRE(code == 0);
        const std::string t = armadillo::core::readWholeFile((elsewhere / "s.csv").string());
        CHECK(std::count(t.begin(), t.end(), '\n') == 402);   // header, 400 rows, the all-off
        // The score drove a motor somewhere in the first four seconds (a level other than 0).
        bool moved = false;
        for (std::size_t i = t.find('\n'); i != std::string::npos && !moved; i = t.find('\n', i + 1)) {
            const std::string row = t.substr(i + 1, t.find('\n', i + 1) - i - 1);
            moved = row.find(',') != std::string::npos && row.substr(row.find(',')).find_first_of("123456789") != std::string::npos;
        }
        CHECK(moved);
    }
    // The program does not carry the checkout's Resources path at all.
    const std::string binary = armadillo::core::readWholeFile(ARMADILLO_BIN);
    CHECK(binary.find(std::string(ARMADILLO_SOURCE_DIR) + "/Resources") == std::string::npos);

    // A score of the user's own in ~/.local/share/armadillo/Scores: listed and played by name.
    const std::string builtIn = run("resources --export '" + (elsewhere / "export").string() + "'").second;
    CHECK(builtIn.find("Scores/rite-of-spring.score") != std::string::npos);
    fs::create_directories(home / ".local/share/armadillo/Scores");
    fs::copy_file(elsewhere / "export/Scores/polytope.score", home / ".local/share/armadillo/Scores/my-own.score");
    const auto [listCode, list] = run("resources --scores");
    CHECK(listCode == 0);
    CHECK(list.find("my-own\n") != std::string::npos);
    CHECK(list.find("rite-of-spring\n") != std::string::npos);
    CHECK(run("render --scene score --score my-own --motion '" + motion + "' --out s.wav --tactile s.csv").first == 0);
    const auto [badCode, bad] = run("render --scene score --score not-a-score --motion '" + motion + "' --out s.wav");
    CHECK(badCode == 3);
    CHECK(bad.find("known: my-own, polytope, rite-of-spring") != std::string::npos);
}

TEST_CASE("cli: --version prints project(VERSION), --help lists it, and --man carries every command's help", "[cli]")
{
    const Run v = runArmadillo("--version");
    CHECK(v.code == 0);
    CHECK(v.out == std::string("armadillo ") + ARMADILLO_PROJECT_VERSION + "\n");
    const Run h = runArmadillo("--help");
    CHECK(h.out.find("--version") != std::string::npos);
    const Run man = runArmadillo("--man");
    REQUIRE(man.code == 0);
    CHECK(man.out.rfind(".TH ARMADILLO 1", 0) == 0);
    CHECK(man.out.find(std::string("armadillo ") + ARMADILLO_PROJECT_VERSION) != std::string::npos);
    for (const char* c : {"ports", "fuse", "render", "play", "braille", "resources"}) {
        INFO(c);
        CHECK(man.out.find(std::string(".SS ") + c + "\n") != std::string::npos);
        // The first option line of the command's own --help appears in the page unchanged.
        const std::string help = runArmadillo(std::string(c) + " --help").out;
        const std::size_t options = help.find("options:\n");
        REQUIRE(options != std::string::npos);
        const std::string firstOption = help.substr(options + 9, help.find('\n', options + 9) - options - 9);
        CHECK(man.out.find(firstOption) != std::string::npos);
    }
    // No line of the page starts with a stray roff request from the help texts.
    for (std::size_t at = 0; (at = man.out.find("\n.", at)) != std::string::npos; ++at) {
        const std::string request = man.out.substr(at + 1, 3);
        CHECK((request == ".TH" || request == ".SH" || request == ".SS" || request == ".nf" || request == ".fi" ||
               request == ".B " || request == ".I " || request == ".IR"));
    }
}

TEST_CASE("cli: play shows progress on a terminal's stderr, and only there", "[cli][play]")
{
    // stderr on a pseudo-terminal, stdout to a file: the progress line (elapsed time, packets,
    // link state) appears on the terminal; stdout holds only the JSON summary.
    int master = -1, slave = -1;
    REQUIRE(::openpty(&master, &slave, nullptr, nullptr, nullptr) == 0);
    const std::string out = (workDir() / "play-progress.txt").string();
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, 1);
        ::dup2(slave, 2);
        ::close(master);
        ::execl(ARMADILLO_BIN, ARMADILLO_BIN, "play", "--scene", "monitor", "--simulate", "--seconds", "1.6", "--no-audio", nullptr);
        ::_exit(127);
    }
    ::close(slave);
    std::string terminal;
    char buf[512];
    for (ssize_t n; (n = ::read(master, buf, sizeof buf)) > 0;) terminal.append(buf, static_cast<std::size_t>(n));   // EIO once the child exits
    int status = 0;
    ::waitpid(pid, &status, 0);
    ::close(master);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    INFO(terminal);
    CHECK(terminal.find(" s of 2  packets ") != std::string::npos);
    CHECK(terminal.find("link up") != std::string::npos);
    const std::string json = armadillo::core::readWholeFile(out);
    CHECK(json.rfind("{\"packets\":", 0) == 0);
    CHECK(std::count(json.begin(), json.end(), '\n') == 1);
    // Without a terminal (the other tests' case) stderr carries no progress line.
    const Run quiet = runArmadillo("play --scene monitor --simulate --seconds 0.6 --no-audio");
    CHECK(quiet.code == 0);
    CHECK(quiet.err.find("packets") == std::string::npos);
}
