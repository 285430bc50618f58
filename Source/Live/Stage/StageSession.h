#pragma once
// The message-thread side of an audio-clocked rig's stage (docs/STAGE.md): a set list parsed and
// every cue's engine built here (CuePlayer, allocating: never on the audio thread) and handed to
// the control side through Stage (Core/Handover.h, one hand-over in flight: a newer set list
// waits for the next tick), the OSC stage commands (StageControlReceiver, as `play --control-in`
// hears them), and what changed since the last tick in words (panic, resume, the cue that now
// plays) for the app's status line, voice and performance view. No JUCE.
// Threads: the message thread and the host's state calls (a mutex here serialises them); the
// OSC receiver's thread only calls Stage's atomics.
#include "Core/Scene.h"
#include "Live/Stage/SetList.h"
#include "Live/Stage/Stage.h"
#include "Live/Stage/StageControl.h"
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace armadillo::live {

/// How every cue's engine is built: the base scene configuration (sample rate, control rate,
/// seed, arm side), the motors, the reader's touch profile and whether the left arm plays too.
struct CueBuild {
    core::SceneConfig base;
    int motors = core::kGridMotors;
    std::array<float, core::kMaxMotors> gains = tactile::TactileConfig::unitMotorGains();
    bool twoArms = false;
};

class StageSession {
public:
    /// Longest set list text taken (the app's setting keeps as much).
    static constexpr std::size_t kMaxSetListBytes = std::size_t(1) << 20;

    explicit StageSession(Stage& stage) : stage_(stage) {}
    ~StageSession();

    /// Parses `text` (its name in messages: `name`), builds every cue and hands the set list to
    /// the control side. Returns "" and `summary` ("Set list NAME: 4 cues, cue 1 'Intro' (theremin)"),
    /// or why it was refused (nothing changes then).
    std::string use(const std::string& text, const std::string& name, const CueBuild& build, std::string& summary);
    /// Reads a set list file's text. Returns "" or why not (naming the file).
    static std::string readFile(const std::string& path, std::string& text);
    /// No set list: the single scene plays.
    void clear();
    /// A set list is loaded (or waiting to be taken).
    bool loaded() const;
    /// prepareToPlay, audio stopped: a set list built for another sample rate is built again for
    /// `build.base.sampleRate` (`text` empty: nothing). Returns it (null: nothing to replace) and,
    /// when it cannot be built, why.
    std::unique_ptr<CuePlayer> rebuild(const std::string& text, const std::string& name, const CueBuild& build, std::string& why);
    /// With the control token held: installs what rebuild() made.
    void install(std::unique_ptr<CuePlayer> player);

    /// What changed since the last tick (panic, resume, the cue now playing).
    struct Report {
        bool panicked = false;    ///< a panic began (or another one came)
        bool resumed = false;
        std::string cue;          ///< "Cue 2 of 4: 'Verse' (cymbal)" when the cue changed, else ""
        /// "refused stage control from 10.0.0.9 (not in the allow-list)" for each sender the OSC
        /// stage commands refused since the last tick, every sender once (docs/SECURITY.md).
        std::vector<std::string> refused;
    };
    /// The message thread's timer: collects the player the control side gave up (deleted here),
    /// retries a waiting hand-over, and reports.
    Report tick();

    /// What the performance view shows.
    struct Info {
        bool setList = false;
        std::string listName;                  ///< the name it was given (its file's name)
        int cue = -1, cueCount = 0;            ///< the cue playing (0-based), how many
        std::string cueName, cueScene;
        int next = -1;                         ///< the next cue (−1: the last cue plays)
        std::string nextName, nextScene;
        bool panicked = false;
        std::uint32_t panics = 0;
    };
    Info info() const;

    /// The OSC stage commands on UDP `port` (0: any free port), or off; heard on `listen.bind`
    /// (loopback by default) from the senders `listen.allow` holds. Returns "" or why not.
    std::string setOsc(bool on, int port, const StageControlListen& listen = {});
    /// The app's settings as a listener: `bind` ("" = loopback) and `allow` ("" = every sender
    /// that reaches it; else ADDR[/BITS],…). Returns "" or why not (the setting named).
    static std::string listenFromSettings(const std::string& bind, const std::string& allow, StageControlListen& listen);
    /// The port they are heard on, 0 when off.
    int oscPort() const;

private:
    std::unique_ptr<CuePlayer> build(const std::string& text, const std::string& name, const CueBuild& build) const;
    void offer(std::unique_ptr<CuePlayer> player);   // under mutex_

    Stage& stage_;
    mutable std::mutex mutex_;
    std::unique_ptr<CuePlayer> waiting_;   // built, not yet taken by Stage::offer
    bool waitingSet_ = false;              // waiting_ (maybe null: "no set list") is to be offered
    double builtRate_ = 0.0;               // the sample rate the newest player was built for
    std::string name_;                     // the newest set list's name
    int reportedCue_ = -1;
    bool reportedPanicked_ = false;
    std::uint32_t reportedPanics_ = 0;
    // Last, so it stops first: its thread calls into stage_.
    std::unique_ptr<StageControlReceiver> osc_;
    std::string oscBind_, oscAllow_;   // what osc_ was opened with (a change reopens it)
};

} // namespace armadillo::live
