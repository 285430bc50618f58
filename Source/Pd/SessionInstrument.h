#pragma once
// [armadillo]'s instrument: the live session `armadillo play` runs (live::LiveSession), on its
// source's own clock — the device link's, the simulator's or the OSC receiver's thread runs the
// control step once per sensor packet. Pd only describes it (live::LiveConfig) and reads what it
// published (pose, quaternion, the levels the safety stage let through, gestures) on a Pd clock;
// the source's thread never calls into Pd.
#include "Pd/Commands.h"
#include <memory>

namespace armadillo::live {
class LiveSession;
}

namespace armadillo::pd {

class SessionInstrument final : public Instrument {
public:
    SessionInstrument();
    ~SessionInstrument() override;
    /// Before the first message: the commands whose settings and files it is built from.
    void setCommands(const Commands* commands) noexcept { commands_ = commands; }

    void apply(const Settings& settings) override;
    void stopSource() override;
    void setParameter(const std::string& id, const std::string& value) override;
    void panic() override;
    void resume() override;
    bool poll(Frame& frame) override;
    bool nextGesture(std::string& name) override;
    Status status() const override;
    std::uint64_t controlSteps() const override;

private:
    const Commands* commands_ = nullptr;
    std::unique_ptr<live::LiveSession> session_;
    std::string source_ = "none";
    bool panicked_ = false;
    std::uint64_t lastUpdate_ = 0;
};

} // namespace armadillo::pd
