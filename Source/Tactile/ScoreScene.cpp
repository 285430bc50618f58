// The "score" scene (thesis §3.3): passive tactile art in time with music the user supplies.
// The scene makes no sound (producesAudio() is false: a render's audio track is silence); it
// follows the host transport's seconds (default) or beats, or its own clock without one.
#include "Tactile/ScoreScene.h"
#include "Core/Errors.h"
#include "Core/Resources.h"
#include "Tactile/ScorePlayer.h"
#include <atomic>
#include <filesystem>


namespace armadillo {

namespace {

/// SceneConfig::score → a score: a name is looked up as Scores/<name>.score in the resource
/// folders (a user's own scores live there) and then among the built-in ones; anything with a
/// slash or ending in ".score" is a path.
Score resolveScore(const SceneConfig& config)
{
    const std::string& name = config.score;
    if (name.empty()) throw InputError("", 0, "score", "no score given (a name such as rite-of-spring, or a file)");
    const bool isPath = name.find('/') != std::string::npos || name.ends_with(".score");
    if (!isPath) {
        if (auto file = findResource("Scores/" + name + ".score", config.resourceDir))
            return parseScore(file->bytes, file->origin);
        std::string known;
        for (const ScoreEntry& e : listScores(config.resourceDir)) known += (known.empty() ? "" : ", ") + e.name;
        throw InputError(name, 0, "score", "no such score (known: " + known + "; or give a .score file)");
    }
    if (!std::filesystem::exists(name)) throw InputError(name, 0, "score", "no such score file");
    return loadScore(name);
}

class ScoreScene final : public Scene {
public:
    std::string_view name() const override { return "score"; }

    std::vector<ParamSpec> parameters() const override
    {
        return {
            ParamSpec {"score.intensity", "Intensity", 0.0f, 150.0f, 100.0f, "%", {}},
            ParamSpec {"score.sync", "Follow", 0.0f, 1.0f, 0.0f, "", {"transport seconds", "transport beats"}},
        };
    }

    void prepare(const SceneConfig& config) override
    {
        player_.setScore(resolveScore(config));
    }

    void setParameter(int index, float value) noexcept override
    {
        if (index == 0 && value >= 0.0f && value <= 150.0f) intensity_.store(value / 100.0f);
        if (index == 1) beats_.store(value >= 0.5f);
    }

    void control(const ControlInput& in, SceneOutput& out) override
    {
        player_.setIntensity(intensity_.load());
        player_.setSync(beats_.load() ? ScorePlayer::Sync::Beats : ScorePlayer::Sync::Seconds);
        player_.control(in.transport, in.dt, out.motors);
    }

    void reset() override { player_.reset(); }

private:
    ScorePlayer player_;
    std::atomic<float> intensity_ {1.0f};
    std::atomic<bool> beats_ {false};
};

} // namespace

std::unique_ptr<Scene> makeScoreScene() { return std::make_unique<ScoreScene>(); }

} // namespace armadillo
