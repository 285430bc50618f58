#pragma once
// The messages Pure Data's [armadillo] and [armadillo~] take (docs/INTERFACES.md "Pure Data
// objects"), read once for both objects and without Pd's types, so the two objects differ only in
// the instrument they drive: [armadillo] the live session on the source's clock
// (live::LiveSession), [armadillo~] the block instrument on Pd's DSP blocks
// (live::BlockInstrument). A message that cannot be honoured throws core::InputError naming the
// problem; the object answers it with pd_error and keeps what ran before.
//
// Threads: Pd's one thread (messages, clocks and DSP method set-up all run there).
#include "Core/MotorTargets.h"
#include "Core/Types.h"
#include "Engine/Engine.h"
#include "Link/Calibration.h"
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace armadillo::pd {

/// One argument of a Pd message: a symbol or a float.
using Atom = std::variant<std::string, double>;

/// What the instrument is asked to be: its source, the files it reads and the scene it plays.
struct Settings {
    enum class Source { None, Simulate, Port, Osc };
    Source source = Source::None;
    std::string motionFile;             ///< Simulate: a pose/quaternion CSV; empty = the wandering arm
    std::string port;                   ///< Port: the device
    int baud = 57600;
    int oscPort = 0;                    ///< Osc: UDP (and TCP) port
    std::string format = "auto";        ///< Osc: the sender's dialect (osc::parseOscFormat)
    std::string mount;                  ///< Osc: a mount preset or file; empty = the format's usual one
    std::string calibrationFile;        ///< empty = the default calibration
    std::string profileFile;            ///< the reader's touch profile; empty = none
    core::ArmSide side = core::ArmSide::Right;
    std::string scene = "monitor";
    std::string sceneText;              ///< braille: what to read; score: the score's name or file
    std::vector<std::pair<std::string, std::string>> params;   ///< the scene's own, id → value, in order
};

/// What an object presents at each control step (Pd's thread reads it, lock-free).
struct Frame {
    bool valid = false;                 ///< the arm has been fused at least once
    double pose[3] {};                  ///< elevation, azimuth, roll (deg; docs/INTERFACES.md "Pose")
    double q[4] {1.0, 0.0, 0.0, 0.0};   ///< w x y z, device → earth
    core::MotorLevels motors {};        ///< what the safety stage let through
    int motorCount = core::kGridMotors;
};

/// The `status` message: the source, its connection, the control rate and what was dropped.
struct Status {
    std::string source = "none";        ///< none, simulate, port, osc
    std::string connection = "stopped"; ///< connected, waiting, stopped
    double rateHz = 0.0;                ///< control steps per second, measured
    std::uint64_t dropped = 0;          ///< samples the control step dropped, bad packets, gestures lost
};

/// What an object does with a message besides changing its settings, and what it presents.
class Instrument {
public:
    virtual ~Instrument() = default;
    /// Builds (or rebuilds) the instrument for `settings`; throws InputError/IoError when it cannot
    /// (the caller then restores the settings that ran).
    virtual void apply(const Settings& settings) = 0;
    /// The source stopped: the motors off, nothing fused (the scene and its parameters kept).
    virtual void stopSource() = 0;
    /// One of the running scene's parameters (already checked against the scene).
    virtual void setParameter(const std::string& id, const std::string& value) = 0;
    virtual void panic() = 0;
    virtual void resume() = 0;

    /// Pd's clock: the newest control step's frame, when one came since the last call.
    virtual bool poll(Frame& frame) = 0;
    /// Pd's clock: the next gesture since the last call (name of the scene's gesture).
    virtual bool nextGesture(std::string& name) = 0;
    /// Pd's clock: the source's state; `Status::rateHz` is the caller's to measure (controlSteps).
    virtual Status status() const = 0;
    /// Control steps so far (for the rate).
    virtual std::uint64_t controlSteps() const = 0;
};

/// The messages, on the settings and the instrument. `directory`: the patch's folder, against
/// which relative file names are read.
class Commands {
public:
    Commands(Instrument& instrument, std::string directory, std::shared_ptr<core::MotorTargets> targets);

    /// One message. Returns true when the caller should report the state now (`bang`). Throws
    /// core::InputError (or IoError) with the problem in words; the settings are then as before.
    bool handle(const std::string& selector, const std::vector<Atom>& args);

    const Settings& settings() const noexcept { return settings_; }
    /// The engine `settings` describe at `sampleRate` (the scene, its text, the arm, the touch
    /// profile, the parameters, the patch scene's cell). Throws InputError for a bad profile file.
    engine::EngineConfig engineConfig(double sampleRate) const;
    /// The calibration file read (the default without one). Throws InputError/IoError.
    link::Calibration calibration() const;
    std::shared_ptr<core::MotorTargets> targets() const noexcept { return targets_; }
    /// A path as the patch means it: absolute, or relative to the patch's folder.
    std::string resolve(const std::string& path) const;

private:
    void applyOrRestore(const Settings& next);
    void setScene(const std::vector<Atom>& args);
    void setParam(const std::vector<Atom>& args);
    void setMotors(const std::vector<Atom>& args);

    Instrument& instrument_;
    std::string directory_;
    std::shared_ptr<core::MotorTargets> targets_;
    Settings settings_;
};

/// Every scene a Pd object plays: `play`'s (engine::sceneNames()) and the hosted ones ("patch").
std::vector<std::string> pdSceneNames();
/// An atom as text (a float without trailing zeros).
std::string atomText(const Atom& a);

} // namespace armadillo::pd
