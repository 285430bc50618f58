#include "CliRun.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
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

TEST_CASE("cli: render writes the WAV and one tactile row per motion row", "[cli]")
{
    std::string rows = "t,elevation,azimuth,roll\n";
    for (int i = 0; i < 50; ++i) rows += std::to_string(i * 0.01) + ",5,0,0\n";
    const std::string motion = file("motion.csv", rows);
    const std::string wav = (workDir() / "m.wav").string(), tactile = (workDir() / "m.csv").string();
    const Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --out '" + wav + "' --tactile '" + tactile + "'");
    REQUIRE(r.code == 0);
    CHECK(fs::file_size(wav) > 44);
    const std::string t = armadillo::readWholeFile(tactile);
    CHECK(t.rfind("t,m1,m2,m3,m4,m5,m6,m7,m8,m9\n", 0) == 0);
    CHECK(std::count(t.begin(), t.end(), '\n') == 51);
}

TEST_CASE("cli: render sets scene parameters with --param and refuses unknown ones", "[cli]")
{
    std::string rows = "t,elevation,azimuth,roll\n";
    for (int i = 0; i < 20; ++i) rows += std::to_string(i * 0.01) + ",0,0,0\n";
    const std::string motion = file("param.csv", rows);
    const std::string out = (workDir() / "param.wav").string();
    CHECK(runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + out + "' --param theremin.range=24").code == 0);
    const Run bad = runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + out + "' --param theremin.colour=red");
    CHECK(bad.code == 3);
    CHECK(bad.err.find("theremin.colour") != std::string::npos);
}
