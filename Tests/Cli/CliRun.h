#pragma once
// Runs the real `armadillo` binary as a user would, in a private temporary folder.
#include "Common/ScratchDir.h"
#include "Core/AtomicFile.h"
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace armadillo::cli {

struct Run {
    int code = -1;
    std::string out, err;
};

inline std::filesystem::path workDir()
{
    return test::scratchDir("armadillo-cli");
}

inline std::string path(const std::string& name) { return (workDir() / name).string(); }

inline std::string file(const std::string& name, const std::string& content)
{
    core::writeFileAtomically(path(name), content);
    return path(name);
}

/// `armadillo ARGS` through the shell, capturing stdout, stderr and the exit code; stdin comes
/// from `input` (a file path; nothing by default).
inline Run runArmadillo(const std::string& args, const std::string& input = "/dev/null")
{
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = std::string("'") + ARMADILLO_BIN + "' " + args + " >'" + out + "' 2>'" + err + "' <'" + input + "'";
    const int status = std::system(cmd.c_str());
    Run r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = core::readWholeFile(out);
    r.err = core::readWholeFile(err);
    return r;
}

/// As runArmadillo, but killed after `seconds` (a hang is then exit code 137, never a stuck
/// suite); a program killed by any other signal (a crash) is -1.
inline Run runArmadilloWithin(double seconds, const std::string& args, const std::string& input = "/dev/null")
{
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = "timeout -s KILL " + std::to_string(seconds) + " '" + std::string(ARMADILLO_BIN) + "' " + args + " >'" + out +
                            "' 2>'" + err + "' <'" + input + "'";
    const int status = std::system(cmd.c_str());
    Run r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = core::readWholeFile(out);
    r.err = core::readWholeFile(err);
    return r;
}

} // namespace armadillo::cli
