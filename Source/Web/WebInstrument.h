#pragma once
// What the web page asks of the instrument it presents: a snapshot of its state, the scene's
// parameters, and the two kinds of state change the page may make — a stage command (through
// the instrument's one switch, live::Stage::apply) and a scene parameter (clamped to its range
// by the instrument). The live session implements it (Live/Session/SessionWebView.h); the web room
// knows nothing above Core, so it cannot reach a source, the control step or the audio thread
// except through this.
//
// Threads: every function is called on one of the web server's worker threads, several at once;
// implementations read atomics and snapshots and never wait for the control step.
#include "Core/StageCommand.h"
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::web {

/// A guided procedure as the page presents it (today the device calibration of thesis §2.4,
/// procedures::DeviceCalibration: the same steps, prompts and results as `armadillo calibrate`
/// and the app's Calibration window).
struct ProcedureStatus {
    bool available = false;        ///< the source can run it (a device or the simulated forearm)
    std::string why;               ///< why not, when not available
    bool running = false, finished = false;
    int step = 0, steps = 0;       ///< 1-based step, of steps
    std::string title, instruction;
    double progress = 0.0;         ///< 0..1: how much of the step's data is in
    bool ready = false;            ///< the step has enough data: Next takes it
    std::string note;              ///< what the last command did ("not enough data yet: …", "skipped", …)
};
enum class ProcedureCommand { Begin, Next, Skip, Cancel };

/// The sensitivity test as the page presents it (procedures::TouchTest, issue 26: one motor at a
/// time, "felt it?", a staircase per motor, then a comfortable level; the same questions as
/// `armadillo touch-profile` and the app's Reader window).
struct TouchTestStatus {
    bool available = false;        ///< the instrument has motors to test
    std::string why;               ///< why not, when not available
    bool running = false;          ///< a test runs (presenting or asking)
    bool asking = false;           ///< a stimulus was played: answer felt / not felt, or feel it again
    bool comfort = false;          ///< the thresholds are measured: now the comfortable level
    bool finished = false;         ///< a profile was measured (its file can be downloaded)
    int stimuli = 0;               ///< stimuli so far
    std::string question;          ///< "motor m3, level 8: felt it?" while asking
    std::string result;            ///< the profile in words, when finished
    std::string note;              ///< what the last command did
};
enum class TouchCommand { Begin, Felt, NotFelt, Again, Cancel };

/// The instrument's state as the page shows it.
struct InstrumentStatus {
    double t = 0.0;                ///< the session's time, s (the source's clock: the tactile CSV's t)
    std::string source;            ///< "simulated forearm", "device on /dev/ttyACM0", "OSC on UDP port 9001"
    bool connected = false;        ///< the source delivers (device in sync, OSC heard lately)
    double rateHz = 0.0;           ///< sensor packets per second so far
    std::uint64_t packets = 0, badPackets = 0, gaps = 0, dropped = 0;
    std::string sender;            ///< an OSC source's detected sender ("" for none or a device)
    bool hasPose = false;          ///< a pose has been tracked
    double elevationDeg = 0.0, azimuthDeg = 0.0, rollDeg = 0.0;
    std::string scene;             ///< the scene that plays (a set list: the current cue's)
    bool panicked = false;         ///< a panic holds: motors off until Resume
    std::uint32_t panics = 0;
    int cue = -1;                  ///< a set list's current cue (−1: none)
    std::vector<std::string> cues; ///< a set list's cue names
    std::vector<std::string> messages;   ///< read on the arm, newest first (at most 20)
    struct Walk {
        bool on = false;
        std::string route;
        int waypoint = 0, waypointCount = 0, arrivals = 0;
        std::string waypointName;
        double distanceM = -1.0, bearingDeg = -1.0;   ///< −1: not known yet
        bool finished = false;
        std::string fix;           ///< "waiting", "good", …
    };
    Walk walk;
    ProcedureStatus calibration;
    TouchTestStatus touch;
};

/// One of the scene's own parameters (Core/Scene.h ParamSpec) and the value it has as far as the
/// page knows (the configured value, or the last one set through the page).
struct ParameterInfo {
    std::string id, name, unit;
    double min = 0.0, max = 1.0, value = 0.0;
    std::vector<std::string> choices;   ///< non-empty: a choice (value = index)
};

class InstrumentView {
public:
    virtual ~InstrumentView() = default;
    virtual InstrumentStatus status() = 0;
    /// The parameters of the scene that plays.
    virtual std::vector<ParameterInfo> parameters() = 0;
    /// Through the instrument's stage (live::Stage::apply): acts at its next control step.
    virtual void stage(const core::StageCommand& command) = 0;
    /// Sets a parameter of the scene that plays, clamped to its range (a choice rounded);
    /// returns the value set, or false when the scene has no parameter `id`.
    virtual bool setParameter(const std::string& id, double value, double& set) = 0;
    /// The device calibration: begin, take the step (when it has enough data), skip it, cancel.
    /// What it did is in status().calibration.note.
    virtual void calibration(ProcedureCommand command) = 0;
    /// The finished calibration as a calibration file (docs/INTERFACES.md), "" before it is finished.
    virtual std::string calibrationFile() = 0;
    /// The scenes the page may choose now (docs/INTERFACES.md names), or none with `why` not (a
    /// set list plays: its cues are the choice; a walk; …).
    virtual std::vector<std::string> sceneChoices(std::string& why) = 0;
    /// `name` plays instead of the scene that plays (from the next control step): "" or why not.
    virtual std::string chooseScene(const std::string& name) = 0;
    /// The sensitivity test: begin it (the motors are the test's until it ends), answer the
    /// stimulus just played, feel it again, cancel. What it did is in status().touch.note.
    virtual void touchTest(TouchCommand command) = 0;
    /// The measured touch profile as a touch-profile file (docs/INTERFACES.md), "" before one is.
    virtual std::string touchProfileFile() = 0;
};

} // namespace armadillo::web
