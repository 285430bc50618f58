// The "score" scene (thesis §3.3): passive tactile art in time with music the user supplies.
// The scene makes no sound (producesAudio() is false: a render's audio track is silence); it
// follows the host transport's seconds (default) or beats, or its own clock without one.
#include "Tactile/ScoreScene.h"
#include "Core/Errors.h"
#include "Core/Resources.h"
#include "Tactile/ScoreFollower.h"
#include "Tactile/ScorePlayer.h"
#include <algorithm>
#include <atomic>
#include <filesystem>


namespace armadillo::tactile {

namespace {

/// SceneConfig::score → a score: a name is looked up as Scores/<name>.score in the resource
/// folders (a user's own scores live there) and then among the built-in ones; anything with a
/// slash or ending in ".score" is a path, and a MIDI or haptic file (.mid, .wav, .ahap, .haptic, .tact)
/// is imported by the reader the engine installed (docs/FORMATS.md).
Score resolveScore(const core::SceneConfig& config)
{
    const std::string& name = config.score;
    if (name.empty()) throw core::InputError("", 0, "score", "no score given (a name such as rite-of-spring, or a file)");
    const ScoreFileReader reader = scoreFileReader();
    const bool other = reader.accepts && reader.load && reader.accepts(name);   // a MIDI or haptic file
    const bool isPath = other || name.find('/') != std::string::npos || name.ends_with(".score");
    if (!isPath) {
        if (auto file = core::findResource("Scores/" + name + ".score", config.resourceDir))
            return parseScore(file->bytes, file->origin);
        std::string known;
        for (const core::ScoreEntry& e : core::listScores(config.resourceDir)) known += (known.empty() ? "" : ", ") + e.name;
        throw core::InputError(name, 0, "score", "no such score (known: " + known + "; or give a .score file)");
    }
    // A path that cannot be read is an I/O failure (exit 4), as for every other input file; a
    // name that is not a path and not found above is bad input (exit 3).
    if (!std::filesystem::exists(name)) throw core::IoError("cannot read score file '" + name + "': no such file");
    if (other) return reader.load(name);
    return loadScore(name);
}

class ScoreScene final : public core::Scene {
public:
    std::string_view name() const override { return "score"; }

    std::vector<core::ParamSpec> parameters() const override
    {
        return {
            core::ParamSpec {"score.intensity", "Intensity", 0.0f, 150.0f, 100.0f, "%", {}},
            core::ParamSpec {"score.sync", "Follow", 0.0f, 1.0f, 0.0f, "", {"transport seconds", "transport beats"}},
            core::ParamSpec {"score.listen", "Listen to the audio input", 0.0f, 1.0f, 1.0f, "", {"off", "on"}},
        };
    }

    void prepare(const core::SceneConfig& config) override
    {
        Score score = resolveScore(config);
        follower_.prepare(score, config.sampleRate > 0.0 ? config.sampleRate : 48000.0);
        player_.setScore(std::move(score));
        inputBlocks_.store(0);
        recordingDeclared_.store(false);
        seenBlocks_ = 0;
        quietFor_ = 1e9;
    }

    void setParameter(int index, float value) noexcept override
    {
        if (index == 0 && value >= 0.0f && value <= 150.0f) intensity_.store(value / 100.0f);
        if (index == 1) beats_.store(value >= 0.5f);
        if (index == 2) listen_.store(value >= 0.5f);
    }

    bool listensToAudio() const override { return true; }

    void processInput(const float* const* in, int channels, int numSamples) noexcept override
    {
        // An empty block declares the input to be the recording itself (render/play --audio-in):
        // followed from its first sample, leading silence included.
        if (numSamples == 0) recordingDeclared_.store(true, std::memory_order_release);
        follower_.process(in, channels, numSamples);
        inputBlocks_.fetch_add(1, std::memory_order_release);
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        player_.setIntensity(intensity_.load());
        player_.setSync(beats_.load() ? ScorePlayer::Sync::Beats : ScorePlayer::Sync::Seconds);
        // Audio "comes in" while the input delivers blocks (within the last 0.25 s) and it is a
        // declared recording or has carried sound (an unrouted plugin input delivers silence:
        // the transport keeps placing the score until the music starts); otherwise the
        // transport (or the scene's own clock) places the score, as in version 1.
        const std::uint64_t blocks = inputBlocks_.load(std::memory_order_acquire);
        if (blocks != seenBlocks_) {
            seenBlocks_ = blocks;
            quietFor_ = 0.0;
        } else {
            quietFor_ += std::max(0.0, in.dt);
        }
        const FollowState state = follower_.state();
        if (listen_.load() && quietFor_ < 0.25 && (recordingDeclared_.load(std::memory_order_acquire) || state.heard)) {
            player_.control(in.transport, in.dt, out.motors, &state);
        } else {
            player_.control(in.transport, in.dt, out.motors);
        }
    }

    void reset() override
    {
        player_.reset();
        follower_.requestReset();
    }

private:
    ScorePlayer player_;
    ScoreFollower follower_;
    std::atomic<float> intensity_ {1.0f};
    std::atomic<bool> beats_ {false};
    std::atomic<bool> listen_ {true};
    std::atomic<std::uint64_t> inputBlocks_ {0};
    std::atomic<bool> recordingDeclared_ {false};
    std::uint64_t seenBlocks_ = 0;   ///< control thread
    double quietFor_ = 1e9;          ///< control thread: s since the input last delivered
};

} // namespace

std::unique_ptr<core::Scene> makeScoreScene() { return std::make_unique<ScoreScene>(); }

} // namespace armadillo::tactile
