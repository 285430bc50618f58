#pragma once
// [armadillo~]'s instrument: the block-clock instrument the app and the plugin run
// (live::BlockInstrument), its control step clocked by Pd's DSP blocks as a plugin host's blocks
// clock the plugin's (BlockControl::processBlock at the 200 Hz grid inside each block), and by its
// own idle clock while Pd's DSP is off. The engine is built from the messages' settings
// (Pd/Commands.h) and handed to the instrument's loop; the sources are the instrument's rig: the
// simulated arm (wandering, or following a motion file), the device, an OSC sender.
//
// Threads: Pd's one thread runs the messages, the clock that presents, prepare() and render()
// (Pd runs DSP and messages on one thread, so no message runs during a block); the instrument's
// idle clock and device link run on their own threads (BlockInstrument.h). render() is real-time:
// it allocates, locks and waits for nothing (Tests/Pd/BlockHostRealtimeTests.cpp).
#include "Live/Session/BlockControl.h"
#include "Live/Step/SceneParameters.h"
#include "Pd/Commands.h"
#include <atomic>
#include <memory>
#include <vector>

namespace armadillo::live {
class BlockInstrument;
}

namespace armadillo::pd {

class BlockHost final : public Instrument {
public:
    explicit BlockHost(double sampleRate);
    ~BlockHost() override;   // the instrument stops: idle clock, device link (its last packet all-off)
    /// Before the first message: the commands whose settings and files it is built from.
    void setCommands(const Commands* commands) noexcept { commands_ = commands; }

    /// Pd's DSP being built (not real-time): the sample rate and the most samples a block has.
    /// A new rate builds the engine again for it.
    void prepare(double sampleRate, int maxBlock);
    /// One DSP block: the control steps that fall in it and the scene's sound, mono, into `out`.
    /// Real-time. A block longer than prepare() said is silent.
    void render(float* out, int n) noexcept;

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
    /// The host's MIDI for one block: none in, and what the mapping would send is let go.
    class NoMidi final : public live::BlockMidi {
    public:
        bool nextInput(Event&) noexcept override { return false; }
        void beginOutput() noexcept override {}
        bool add(const std::uint8_t*, int, int) noexcept override { return true; }
    };
    void installEngine();
    void chooseSource(const Settings& settings);
    void setStopped(bool stopped);
    void setSourceCell(live::SourceKind kind) noexcept { sourceCell_.store(static_cast<float>(kind), std::memory_order_relaxed); }

    const Commands* commands_ = nullptr;
    double sampleRate_ = 48000.0;
    std::atomic<float> elevation_ {0.0f}, azimuth_ {0.0f}, roll_ {0.0f}, sourceCell_ {0.0f};
    live::SceneParameterTable table_;   // empty: Pd runs no mapping set (before instrument_, which refers to it)
    std::unique_ptr<live::BlockInstrument> instrument_;
    std::vector<float> left_, right_;   // one block's two channels (sized in prepare)
    NoMidi midi_;
    std::uint64_t generation_ = 0;
    std::uint64_t lastSerial_ = 0;
    std::uint64_t lastGestureCount_ = 0;
    std::string source_ = "none";
    bool stopped_ = true;     // no source: the stage holds the scene silent
    bool userPanic_ = false;  // the patch's own `panic`, until its `resume`
};

} // namespace armadillo::pd
