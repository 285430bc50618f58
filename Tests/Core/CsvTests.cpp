#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
namespace fs = std::filesystem;

namespace {
/// The InputError a parse throws, for checking what it names.
InputError errorOf(const std::string& text, const std::function<void(const CsvTable&)>& use = {})
{
    try {
        const CsvTable t = CsvTable::parse(text, "in.csv");
        if (use) use(t);
    } catch (const InputError& e) {
        return e;
    }
    FAIL("expected an InputError for:\n" << text);
    throw std::logic_error("unreachable");
}

fs::path tempDir()
{
    static int counter = 0;
    fs::path p = fs::temp_directory_path() / ("armadillo-core-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::create_directories(p);
    return p;
}
} // namespace

TEST_CASE("CSV: header-driven, any column order, comments and blank lines", "[csv]")
{
    const auto t = CsvTable::parse("# recorded 2026\n\nay,t,gx,gz,gy,ax,az\n# mid comment\n9.8,0.5,0.1,0.3,0.2,0,0.1\r\n9.7,0.6,1,3,2,0.5,nan\n", "x.csv");
    REQUIRE(t.rowCount() == 2);
    const auto imu = readImu(t);
    CHECK(imu[0].t == 0.5);
    CHECK(imu[0].gyro == Eigen::Vector3d(0.1, 0.2, 0.3));
    CHECK(imu[0].accel == Eigen::Vector3d(0.0, 9.8, 0.1));
    CHECK(std::isnan(imu[1].accel.z()));
    CHECK(imu[1].mag.array().isNaN().all());   // no magnetometer columns
    CHECK(t.lineOf(1) == 6);
}

TEST_CASE("CSV: bad input is refused naming file, line and column", "[csv]")
{
    SECTION("empty file")
    {
        const auto e = errorOf("");
        CHECK(std::string(e.what()).find("in.csv") != std::string::npos);
        CHECK(std::string(e.what()).find("empty") != std::string::npos);
    }
    SECTION("only comments") { CHECK(std::string(errorOf("# nothing\n\n").what()).find("empty") != std::string::npos); }
    SECTION("header only")
    {
        const auto e = errorOf("t,qw,qx,qy,qz\n");
        CHECK(e.line() == 1);
        CHECK(std::string(e.what()).find("no data") != std::string::npos);
    }
    SECTION("no header row")
    {
        const auto e = errorOf("0.1,1,0,0,0\n");
        CHECK(e.line() == 1);
    }
    SECTION("non-number names line and column")
    {
        const auto e = errorOf("t,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,zero,0,0\n");
        CHECK(e.line() == 3);
        CHECK(e.column() == "qx");
        CHECK(std::string(e.what()) == "in.csv:3: column 'qx': 'zero' is not a number");
    }
    SECTION("empty value")
    {
        const auto e = errorOf("t,qw,qx,qy,qz\n0,1,,0,0\n");
        CHECK(e.column() == "qx");
    }
    SECTION("trailing garbage after a number") { CHECK(errorOf("t,a\n1,2x\n").column() == "a"); }
    SECTION("wrong field count")
    {
        const auto e = errorOf("t,qw,qx,qy,qz\n0,1,0,0\n");
        CHECK(e.line() == 2);
    }
    SECTION("duplicate column") { CHECK(errorOf("t,qw,qw\n0,1,1\n").column() == "qw"); }
    SECTION("missing column names the column")
    {
        const auto e = errorOf("t,qw,qx,qy\n0,1,0,0\n", [](const CsvTable& t) { readQuaternions(t); });
        CHECK(e.column() == "qz");
        CHECK(e.line() == 1);
    }
    SECTION("time going backwards")
    {
        const auto e = errorOf("t,elevation,azimuth,roll\n0,0,0,0\n1,0,0,0\n0.5,0,0,0\n", [](const CsvTable& t) { readPoses(t); });
        CHECK(e.line() == 4);
        CHECK(e.column() == "t");
        CHECK(std::string(e.what()).find("backwards") != std::string::npos);
    }
    SECTION("NaN time") { CHECK(errorOf("t,qw,qx,qy,qz\nnan,1,0,0,0\n", [](const CsvTable& t) { readQuaternions(t); }).column() == "t"); }
    SECTION("zero quaternion") { CHECK(errorOf("t,qw,qx,qy,qz\n0,0,0,0,0\n", [](const CsvTable& t) { readQuaternions(t); }).line() == 2); }
    SECTION("elevation out of range") { CHECK(errorOf("t,elevation,azimuth,roll\n0,95,0,0\n", [](const CsvTable& t) { readPoses(t); }).column() == "elevation"); }
    SECTION("tactile level not a whole number 0..15")
    {
        const std::string head = "t,m1,m2,m3,m4,m5,m6,m7,m8,m9\n";
        CHECK(errorOf(head + "0,1,2,3,4,5,6,7,8,16\n", [](const CsvTable& t) { readTactile(t); }).column() == "m9");
        CHECK(errorOf(head + "0,1.5,2,3,4,5,6,7,8,9\n", [](const CsvTable& t) { readTactile(t); }).column() == "m1");
        CHECK(errorOf(head + "0,-1,2,3,4,5,6,7,8,9\n", [](const CsvTable& t) { readTactile(t); }).column() == "m1");
    }
    SECTION("tactile with too few motors") { CHECK(errorOf("t,m1,m2\n0,1,2\n", [](const CsvTable& t) { readTactile(t); }).column() == "m3"); }
    SECTION("partial magnetometer") { CHECK(errorOf("t,gx,gy,gz,ax,ay,az,mx,my\n0,0,0,0,0,0,0,0,0\n", [](const CsvTable& t) { readImu(t); }).column() == "mz"); }
    SECTION("binary data") { CHECK(errorOf(std::string("t,a\n1,\0\n", 7)).line() == 2); }
    SECTION("a header that is not a motion file")
    {
        CHECK_THROWS_AS(motionAsQuaternions(CsvTable::parse("t,foo\n0,1\n", "m.csv")), InputError);
    }
}

TEST_CASE("CSV: motion kinds are told apart by their header", "[csv]")
{
    CHECK(detectMotionKind(CsvTable::parse("t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,9.8,0\n", "a")) == MotionKind::Imu);
    CHECK(detectMotionKind(CsvTable::parse("t,qx,qw,qz,qy\n0,0,1,0,0\n", "a")) == MotionKind::Quaternion);
    CHECK(detectMotionKind(CsvTable::parse("roll,t,elevation,azimuth\n0,0,0,0\n", "a")) == MotionKind::Pose);
    const auto q = motionAsQuaternions(CsvTable::parse("t,elevation,azimuth,roll\n0,0,0,0\n", "a"));
    CHECK(q.at(0).q.isApprox(restOrientation()));
}

TEST_CASE("CSV: random garbage never crashes the parser", "[csv][fuzz]")
{
    std::mt19937 rng(1234);
    const std::string alphabet = "t,qwxyz0123456789.-+eEnaN#\n\r \t";
    int refused = 0, accepted = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string s;
        const int n = static_cast<int>(rng() % 80);
        for (int k = 0; k < n; ++k) s += (rng() % 10 == 0) ? static_cast<char>(rng() % 256) : alphabet[rng() % alphabet.size()];
        if (i % 2) s = "t,qw,qx,qy,qz\n" + s;
        try {
            const auto t = CsvTable::parse(s, "fuzz");
            (void) readQuaternions(t);
            ++accepted;
        } catch (const InputError&) {
            ++refused;
        }
    }
    CHECK(refused + accepted == 20000);
    CHECK(refused > 0);
}

TEST_CASE("CSV: writers round-trip and write whole or nothing", "[csv][io]")
{
    const fs::path dir = tempDir();
    std::vector<TimedQuaternion> rows;
    for (int i = 0; i < 50; ++i) rows.push_back({i * 0.01, poseToQuaternion({i * 1.0, i * 7.0, -i * 3.0})});
    const std::string path = (dir / "q.csv").string();
    writeQuaternions(path, rows);
    const auto back = readQuaternions(CsvTable::read(path));
    REQUIRE(back.size() == rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        CHECK(back[i].t == Approx(rows[i].t));
        CHECK(back[i].q.angularDistance(rows[i].q) < 1e-7);
    }

    std::vector<TactileRow> tactile(3);
    tactile[1].levels[0] = 15;
    tactile[2].levels[11] = 4;
    tactile[2].t = 0.5;
    writeTactile((dir / "t.csv").string(), tactile, 12);
    int motors = 0;
    const auto tBack = readTactile(CsvTable::read((dir / "t.csv").string()), &motors);
    CHECK(motors == 12);
    CHECK(tBack[1].levels[0] == 15);
    CHECK(tBack[2].levels[11] == 4);

    // A failed write leaves no file and no temporary behind.
    const std::string missing = (dir / "no-such-dir" / "x.csv").string();
    CHECK_THROWS_AS(writeFileAtomically(missing, "data"), IoError);
    CHECK_FALSE(fs::exists(missing));
    // Replacing keeps either the old or the new content, never a mix, and no temporaries.
    writeFileAtomically(path, "new\n");
    CHECK(readWholeFile(path) == "new\n");
    int files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
    CHECK(files == 2);
    CHECK_THROWS_AS(CsvTable::read((dir / "absent.csv").string()), IoError);
    fs::remove_all(dir);
}

TEST_CASE("appendCsvField quotes only fields that need it, doubling quotes (RFC 4180)", "[core][csv]")
{
    std::string out;
    appendCsvField(out, "plain");
    out += ',';
    appendCsvField(out, "a,b");
    out += ',';
    appendCsvField(out, "say \"here\"");
    out += ',';
    appendCsvField(out, "two\nlines");
    out += ',';
    appendCsvField(out, "");
    CHECK(out == "plain,\"a,b\",\"say \"\"here\"\"\",\"two\nlines\",");
}
