#pragma once
// A set list (docs/STAGE.md): an ordered list of cues — scene, its parameters, a mapping set
// and a profile — read from a versioned JSON file, and the CuePlayer that steps through it on
// stage: every cue's Engine is built and prepared in advance, so a cue change allocates
// nothing; audio is cross-faded between the old and the new cue over kFadeSeconds; the old
// cue's motors go off through its tactile engine's all-off path and one safety stage spanning
// the whole set list has the last word, so a cue change cannot reset the motors' heat budget.
//
// File (version 1):
//   {"armadillo_setlist": 1,
//    "cues": [ {"name": "Intro", "scene": "theremin",
//               "parameters": {"theremin.range": 24, "theremin.scale": "minor"},
//               "mapping": "default", "profile": "alice",
//               "score": "rite-of-spring", "text": "…"}, … ]}
// `scene` is required; the rest is optional. `mapping` and `profile` are names kept for the
// mapping layer and the user profiles (opaque strings here). Unknown keys, a wrong type, an
// unknown scene or parameter are refused with the file, the line and the key path.
#include "Core/Csv.h"
#include "Core/Scene.h"
#include "Core/Types.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Tactile/TactileEngine.h"
#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::live {

struct Cue {
    std::string name;
    std::string scene;
    std::vector<std::string> parameters;   ///< "id=value", in file order
    std::string mapping;                   ///< mapping set name (opaque for now)
    std::string profile;                   ///< user profile name (opaque for now)
    std::string score, text;               ///< the score and braille scenes' material
    long line = 0;                         ///< where the cue starts in its file
};

struct SetList {
    static constexpr int kVersion = 1;
    std::string source;                    ///< file name, for messages
    std::vector<Cue> cues;
};

/// Parses a set list; throws InputError(source, line, key path, message) for anything wrong.
SetList parseSetList(std::string_view text, const std::string& source);
/// Reads and parses a file (IoError when it cannot be read).
SetList loadSetList(const std::string& path);

class CuePlayer {
public:
    static constexpr double kFadeSeconds = 0.050;
    static constexpr int kMaxBlock = 8192;   ///< audio blocks longer than this are split

    /// Not real-time: builds and prepares every cue's engine (`base` gives the sample rate, seed,
    /// arm side and resource folder). Throws InputError naming the set list's file and the cue's
    /// line for an unknown scene or a bad parameter.
    /// `twoArms`: every cue's engine takes a left arm too (EngineConfig::twoArms), and the left
    /// arm's motors have a safety stage of their own spanning the set list. `motorGain`: the
    /// reader's touch profile (EngineConfig::motorGain), given to every cue's engine as the
    /// single engine gets it.
    CuePlayer(const SetList& list, const core::SceneConfig& base, int motorCount = core::kGridMotors, bool twoArms = false,
              const std::array<float, core::kMaxMotors>& motorGain = tactile::TactileConfig::unitMotorGains());
    ~CuePlayer();
    CuePlayer(const CuePlayer&) = delete;
    CuePlayer& operator=(const CuePlayer&) = delete;

    int cueCount() const noexcept { return static_cast<int>(engines_.size()); }
    const Cue& cue(int index) const { return cues_[static_cast<std::size_t>(index)]; }
    engine::Engine& engine(int index) { return *engines_[static_cast<std::size_t>(index)]; }
    const engine::Engine& engine(int index) const { return *engines_[static_cast<std::size_t>(index)]; }

    /// Any thread: the cue to run from the next control update (clamped to the list).
    void request(int index) noexcept;
    void next() noexcept;
    void previous() noexcept;
    int requested() const noexcept { return requested_.load(std::memory_order_acquire); }
    /// The cue the control thread runs now.
    int current() const noexcept { return active_.load(std::memory_order_acquire); }
    /// Cue changes so far.
    std::uint32_t changes() const noexcept { return changes_.load(std::memory_order_relaxed); }

    /// Control thread, real-time: takes a requested cue change (old cue's motors off, new
    /// cue's scene reset), runs the current cue's engine, then the set list's safety stage.
    core::MotorLevels control(const core::ArmState& arm, const core::Transport& transport, double dt) noexcept;
    /// Two arms (constructed with twoArms): as above with the left arm's state; the left arm's
    /// levels (after its own set-list safety stage) are leftLevels() until the next call.
    core::MotorLevels control(const core::ArmState& arm, const core::ArmState& leftArm, const core::Transport& transport, double dt) noexcept;
    const core::MotorLevels& leftLevels() const noexcept { return leftLevels_; }
    bool twoArms() const noexcept { return twoArms_; }
    /// Audio thread, real-time: every listening cue hears the input (a follower keeps its place).
    void processInput(const float* const* in, int channels, int numSamples) noexcept;
    /// Audio thread, real-time: the instrument's MIDI notes of the coming block (Engine::processMidi),
    /// to every cue whose scene takes MIDI input, before processInput() of the same samples.
    void processMidi(const core::MidiNoteEvent* events, int count) noexcept;
    /// Audio thread, real-time: the current cue, cross-faded from the previous one after a change.
    void renderAudio(float* left, float* right, int numSamples) noexcept;
    /// Control thread, real-time: another arm from now on (a switch of source). The current cue
    /// starts afresh (Engine::restart()); the safety stages keep their heat history.
    void restart() noexcept;
    /// Panic / resume every cue's engine (any thread).
    void panic() noexcept;
    void resume() noexcept;

private:
    void renderChunk(float* left, float* right, int n) noexcept;
    std::vector<Cue> cues_;
    std::vector<std::unique_ptr<engine::Engine>> engines_;
    tactile::SafetyStage safety_;
    tactile::SafetyStage leftSafety_;        ///< two arms: the left arm's own heat budget across the set list
    core::MotorLevels leftLevels_ {};
    bool twoArms_ = false;
    core::MotorLevels step(const core::ArmState& arm, const core::ArmState* leftArm, const core::Transport& transport, double dt) noexcept;
    std::atomic<int> requested_ {0};
    std::atomic<int> active_ {0};
    std::atomic<std::uint32_t> changes_ {0};
    int controlCue_ = 0;                     ///< control thread
    int audioCue_ = 0, fadeFrom_ = -1;       ///< audio thread
    int fadeLength_ = 2400, fadePos_ = 0;    ///< samples
    std::vector<float> scratchL_, scratchR_;
};

/// A cue change at a time of the render (s from the first motion row).
struct CueChange {
    double t = 0.0;
    int cue = 0;
};
/// "T:INDEX" (e.g. "2.5:1"); throws UsageError-free std::invalid_argument with a reason.
CueChange parseCueChange(const std::string& text);

} // namespace armadillo::live
