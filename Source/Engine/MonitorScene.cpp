#include "Engine/MonitorScene.h"

namespace armadillo {
namespace {
class MonitorScene final : public Scene {
public:
    std::string_view name() const override { return "monitor"; }
    void prepare(const SceneConfig&) override {}
    void control(const ControlInput&, SceneOutput& out) override { out.motors.clearLevels(); }
};
} // namespace

std::unique_ptr<Scene> makeMonitorScene() { return std::make_unique<MonitorScene>(); }
} // namespace armadillo
