#pragma once
// A JACK client with N audio output ports (the tactor output of `armadillo play --tactors jack`,
// issue 33; docs/TACTORS.md). JACK's own process thread calls the render callback once per
// period with one buffer per port; the callback must be real-time safe.
//
// The client never starts a server (JackNoStartServer): with none running the constructor
// throws IoError ("JACK server not running"), so nothing is half-started. The server to talk to
// is JACK's usual choice: $JACK_DEFAULT_SERVER, else "default".
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::audio {

class JackOutput {
public:
    using Render = std::function<void(float* const* channels, int numChannels, int numSamples)>;

    /// Opens client `clientName` (JACK renames it when taken) with `channels` (1…32) output ports
    /// named `portPrefix`1, `portPrefix`2, …; not yet active. IoError naming the cause.
    JackOutput(const std::string& clientName, int channels, const std::string& portPrefix = "tactor_");
    ~JackOutput();
    JackOutput(const JackOutput&) = delete;
    JackOutput& operator=(const JackOutput&) = delete;

    /// The input ports matching `pattern` (a JACK regular expression, as jack_lsp shows names),
    /// in the server's order. IoError when none match.
    std::vector<std::string> inputPorts(const std::string& pattern) const;
    /// Activates the client: `render` runs on JACK's process thread from now on.
    void start(Render render);
    /// Connects output port k to the k-th input port matching `pattern` (after start()). IoError
    /// when fewer ports match than there are channels (nothing connected then).
    void connect(const std::string& pattern);
    /// Deactivates and closes the client (silence at once). Idempotent.
    void stop();

    const std::string& clientName() const noexcept { return name_; }
    std::string portName(int channel) const;   ///< full name "client:tactor_k" (channel 0-based)
    int channels() const noexcept { return static_cast<int>(ports_.size()); }
    double sampleRate() const noexcept { return sampleRate_; }
    int bufferFrames() const noexcept { return bufferFrames_; }
    /// Frames from our ports to the playback hardware (JACK's playback latency range, max), as the
    /// server reports it now.
    int playbackLatencyFrames() const;
    std::uint64_t framesWritten() const noexcept { return frames_.load(std::memory_order_relaxed); }
    /// The server went away (shut down, killed): the output has stopped.
    bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }

private:
    static int process(std::uint32_t frames, void* self);
    static void shutdown(void* self);
    struct Client;
    std::unique_ptr<Client> client_;
    std::vector<void*> ports_;             // jack_port_t*
    std::vector<float*> buffers_;          // process thread: this period's port buffers
    std::string name_;
    double sampleRate_ = 0.0;
    int bufferFrames_ = 0;
    Render render_;
    bool active_ = false;
    std::atomic<std::uint64_t> frames_ {0};
    std::atomic<bool> failed_ {false};
};

} // namespace armadillo::audio
