// `armadillo calibrate --simulate` as a user runs it: a scripted user reads each "? " prompt on
// stderr and answers on stdin (Enter = the step is done, s = skip, q = cancel). The simulated
// forearm rehearses each step (procedures::CalibrationRehearsal), so Enter waits until the step
// has enough data and then takes it; the file written, the summary line, cancel and the end of
// input are checked.
#include "CliRun.h"
#include "Link/Calibration.h"
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <functional>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace armadillo::cli;

namespace {

struct Interactive {
    int code = -1;
    std::vector<std::string> prompts;
    std::string err, out;
};

/// Runs `armadillo ARGS`, answering each line of stderr that starts with "? " with answer(prompt)
/// (a line; a null answer closes stdin). Killed after `seconds` (then code -1).
Interactive runAnswering(const std::vector<std::string>& args, const std::function<const char*(const std::string&)>& answer, double seconds)
{
    int toChild[2], fromChild[2];
    REQUIRE(::pipe(toChild) == 0);
    REQUIRE(::pipe(fromChild) == 0);
    const std::string outPath = path("calibrate-stdout.txt");
    // Built before the fork: the child only makes async-signal-safe calls until it execs.
    std::vector<char*> argv {const_cast<char*>(ARMADILLO_BIN)};
    std::vector<std::string> argStore = args;
    for (auto& s : argStore) argv.push_back(s.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::dup2(toChild[0], 0);
        ::dup2(fromChild[1], 2);
        const int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(out, 1);
        ::close(toChild[1]);
        ::close(fromChild[0]);
        ::execv(ARMADILLO_BIN, argv.data());
        ::_exit(127);
    }
    ::close(toChild[0]);
    ::close(fromChild[1]);
    ::signal(SIGPIPE, SIG_IGN);
    Interactive r;
    std::string pending;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    bool open = true;
    for (;;) {
        pollfd p {fromChild[0], POLLIN, 0};
        if (::poll(&p, 1, 50) > 0) {
            char buf[1024];
            const ssize_t n = ::read(fromChild[0], buf, sizeof buf);
            if (n <= 0) break;   // the program ended (stderr closed)
            pending.append(buf, static_cast<std::size_t>(n));
            for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
                const std::string line = pending.substr(0, nl);
                pending.erase(0, nl + 1);
                r.err += line + "\n";
                if (line.rfind("? ", 0) != 0 || !open) continue;
                r.prompts.push_back(line);
                const char* a = answer(line);
                if (a == nullptr) {
                    ::close(toChild[1]);
                    open = false;
                } else {
                    const std::string l = std::string(a) + "\n";
                    (void)!::write(toChild[1], l.data(), l.size());
                }
            }
        }
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(pid, SIGKILL);
            break;
        }
    }
    if (open) ::close(toChild[1]);
    ::close(fromChild[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = armadillo::core::readWholeFile(outPath);
    return r;
}

} // namespace

TEST_CASE("calibrate --simulate: the seven steps on stdin/stderr, Enter waits for enough data, s skips", "[cli][calibrate]")
{
    const std::string out = path("calibrate-sim.json");
    std::filesystem::remove(out);
    // Enter on the gyroscope bias, the accelerometer and the roll; the rest skipped.
    const char* script[] = {"", "", "s", "s", "", "s", "s"};
    int step = 0;
    const Interactive r = runAnswering({"calibrate", "--simulate", "--out", out}, [&](const std::string&) { return step < 7 ? script[step++] : "q"; },
                                       300.0);
    INFO(r.err);
    REQUIRE(r.code == 0);
    REQUIRE(r.prompts.size() == 7);
    CHECK(r.prompts[0].rfind("? Step 1 of 7: gyroscope bias (keep still): ", 0) == 0);
    CHECK(r.prompts[1].rfind("? Step 2 of 7: accelerometer", 0) == 0);
    CHECK(r.prompts[4].rfind("? Step 5 of 7: gyroscope scale, roll (x)", 0) == 0);
    CHECK(r.prompts[6].rfind("? Step 7 of 7: ", 0) == 0);
    CHECK(r.out.find("{\"steps\":7,\"measured\":3,\"skipped\":4,") == 0);
    CHECK(r.err.find("calibration written to " + out) != std::string::npos);
    // The simulated board's ADC is the built-in calibration: what was measured is close to it,
    // what was skipped is exactly it.
    const armadillo::link::Calibration c = armadillo::link::loadCalibration(out), d = armadillo::link::defaultCalibration();
    CHECK((c.accel.scale - d.accel.scale).cwiseAbs().maxCoeff() < 0.03 * d.accel.scale.cwiseAbs().maxCoeff());
    CHECK((c.accel.bias - d.accel.bias).cwiseAbs().maxCoeff() < 15.0);   // counts
    CHECK(c.mag.bias.isApprox(d.mag.bias, 1e-9));                         // skipped: kept (as written in the JSON)
    CHECK(c.gyro.scale.z() == Approx(d.gyro.scale.z()).epsilon(1e-6));
    CHECK(std::abs(c.gyro.scale.x() - d.gyro.scale.x()) < 0.03 * d.gyro.scale.x());
}

TEST_CASE("calibrate: q cancels and writes nothing; stdin ending is exit 3; bad usage", "[cli][calibrate]")
{
    const std::string out = path("calibrate-cancel.json");
    std::filesystem::remove(out);
    const Interactive q = runAnswering({"calibrate", "--simulate", "--out", out}, [](const std::string&) { return "q"; }, 60.0);
    CHECK(q.code == 0);
    CHECK(q.out.find("\"cancelled\":true") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
    const Run ended = runArmadilloWithin(60, "calibrate --simulate --out " + out);   // stdin: /dev/null
    CHECK(ended.code == 3);
    CHECK_FALSE(std::filesystem::exists(out));
    CHECK(runArmadillo("calibrate --out " + out).code == 2);
    CHECK(runArmadillo("calibrate --simulate").code == 2);
    CHECK(runArmadillo("calibrate --simulate --baud 9600 --out " + out).code == 2);
    CHECK(runArmadillo("calibrate --port /dev/does-not-exist --out " + out).code == 4);
}
