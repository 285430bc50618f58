// The "score" scene (thesis §3.3): passive tactile art in time with music the user supplies.
// The scene makes no sound (producesAudio() is false: a render's audio track is silence); it
// follows the host transport's seconds (default) or beats, or its own clock without one.
#include "Tactile/ScoreScene.h"
#include "Core/Errors.h"
#include "Tactile/ScorePlayer.h"
#include <atomic>
#include <filesystem>

#ifndef ARMADILLO_RESOURCE_DIR
#define ARMADILLO_RESOURCE_DIR ""
#endif

namespace armadillo {

namespace {

/// SceneConfig::score → a file: the shipped names live in <resourceDir>/Scores/<name>.score;
/// anything else is a path.
std::string scorePath(const SceneConfig& config)
{
    const std::string resources = config.resourceDir.empty() ? std::string(ARMADILLO_RESOURCE_DIR) : config.resourceDir;
    const std::string& name = config.score;
    if (name.empty()) throw InputError("", 0, "score", "no score given (rite-of-spring, polytope or a file)");
    if (name == "rite-of-spring" || name == "polytope") return resources + "/Scores/" + name + ".score";
    if (!std::filesystem::exists(name))
        throw InputError(name, 0, "score", "no such score (the shipped ones are rite-of-spring and polytope)");
    return name;
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
        player_.setScore(loadScore(scorePath(config)));
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
