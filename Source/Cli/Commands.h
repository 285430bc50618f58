#pragma once
// The subcommands of `armadillo` (INTERFACES.md). Each lives in its own Cmd<Name>.cpp.
#include <string>
#include <vector>

namespace armadillo::cli {

using Arguments = std::vector<std::string>;   ///< what follows the subcommand name

int runPorts(const Arguments& args);     // CmdPorts.cpp   — serial ports found
int runFuse(const Arguments& args);      // CmdFuse.cpp    — offline SR-UKF fusion
int runRender(const Arguments& args);    // CmdRender.cpp  — offline deterministic engine run
int runPlay(const Arguments& args);      // CmdPlay.cpp    — the live engine, headless
int runBraille(const Arguments& args);   // CmdBraille.cpp — cells and row sensations of a text
int runResources(const Arguments& args); // CmdResources.cpp — search folders, scores, built-in files
int runMap(const Arguments& args);       // CmdMap.cpp     — mapping files: check, show, learn a posture
int runScore(const Arguments& args);     // CmdScore.cpp   — scores from MIDI and haptic files
int runTouchProfile(const Arguments& args); // CmdTouchProfile.cpp — per-motor thresholds of the reader
int runCalibrate(const Arguments& args); // CmdCalibrate.cpp — the device calibration (thesis §2.4), step by step
int runTactors(const Arguments& args);   // CmdTactors.cpp — a tactor rig's channels buzzed in turn
int runNavigate(const Arguments& args);  // CmdNavigate.cpp — walk a route guided by the arm (issue 34)
int runMqtt(const Arguments& args);      // CmdMqtt.cpp    — MQTT: check a broker
int runRead(const Arguments& args);      // CmdRead.cpp    — messages only, on the arm (play's session)

struct CommandInfo {
    const char* name;
    const char* summary;
    int (*run)(const Arguments&);
};
const std::vector<CommandInfo>& commands();

} // namespace armadillo::cli
