// "patch" (issue 46): the patch is the scene. The place the thesis's Python tactile mapping had
// (§3.3) is taken by a patcher: a front end writes the grid's nine targets into a lock-free cell
// (Core/MotorTargets.h, SceneConfig::motorTargets) and this scene states them, every control
// step, as sustained intents on its MotorCanvas — so they are shaped and pass the safety stage
// like any scene's, never around it. Silent; it reads no arm (the patch does that itself).
#include "Core/MotorTargets.h"
#include "Instruments/Scenes.h"

namespace armadillo::instruments {
namespace {

class PatchScene final : public core::Scene {
public:
    std::string_view name() const override { return "patch"; }
    void prepare(const core::SceneConfig& config) override
    {
        targets_ = config.motorTargets ? config.motorTargets : std::make_shared<core::MotorTargets>();
        last_ = {};
    }
    void control(const core::ControlInput&, core::SceneOutput& out) override
    {
        last_ = targets_->load(last_);
        for (int i = 0; i < core::MotorTargets::kCount; ++i) out.motors.setLevel(i, last_[static_cast<std::size_t>(i)]);
    }
    void reset() override { last_ = {}; }

private:
    std::shared_ptr<core::MotorTargets> targets_;
    core::MotorTargets::Levels last_ {};
};

} // namespace

std::unique_ptr<core::Scene> makePatchScene() { return std::make_unique<PatchScene>(); }

} // namespace armadillo::instruments
