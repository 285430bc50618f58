#include "Engine/MonitorScene.h"

namespace armadillo::engine {
namespace {
class MonitorScene final : public core::Scene {
public:
    std::string_view name() const override { return "monitor"; }
    void prepare(const core::SceneConfig&) override {}
    void control(const core::ControlInput&, core::SceneOutput& out) override { out.motors.clearLevels(); }
};
} // namespace

std::unique_ptr<core::Scene> makeMonitorScene() { return std::make_unique<MonitorScene>(); }
} // namespace armadillo::engine
