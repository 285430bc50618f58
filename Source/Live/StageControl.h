#pragma once
// Stage commands (docs/STAGE.md): panic, resume and set-list steps, from OSC on a control port
// (`armadillo play --control-in PORT`) and from single keys (`--keys`). The messages:
//   /armadillo/panic            everything off (Engine::panic)
//   /armadillo/resume           back to the current cue (Engine::resume)
//   /armadillo/cue/next         the next cue of the set list
//   /armadillo/cue/prev         the previous cue
//   /armadillo/cue i|f          cue number i (0-based)
//   /armadillo/message s [i|f]  a text for the arm to read, priority ≥ 1 = urgent (issue 35)
// Keys: p or Escape = panic, r = resume, n or Space = next cue, b = previous cue, 0..9 = cue.
// Parsing is separate from the socket so tests can feed it messages and keys directly.
#include "Core/StageCommand.h"
#include "Osc/Osc.h"
#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace armadillo::live {

/// A decoded OSC message as a stage command. false (with the reason in `why`) for any other
/// address or a /armadillo/cue whose argument is not one whole number ≥ 0.
bool stageCommandFromOsc(const osc::OscMessage& message, core::StageCommand& out, std::string& why);
/// A key typed on the terminal as a stage command; false for keys with no meaning.
bool stageCommandFromKey(char key, core::StageCommand& out);
/// "panic", "resume", "next cue", "previous cue", "cue 3".
std::string describe(const core::StageCommand& command);

/// Listens for stage commands on a UDP port (all interfaces, IPv6 and IPv4) on its own thread;
/// the handler runs on that thread. Refused messages are counted.
class StageControlReceiver {
public:
    using Handler = std::function<void(const core::StageCommand&)>;
    /// Binds now (port 0 = any free port); throws IoError when the port is taken.
    StageControlReceiver(int port, Handler handler);
    ~StageControlReceiver();
    StageControlReceiver(const StageControlReceiver&) = delete;
    StageControlReceiver& operator=(const StageControlReceiver&) = delete;
    /// Text messages for the arm (issue 35, docs/MQTT.md): `/armadillo/message s [i|f]` — the text
    /// and an optional priority (≥ 1 = urgent). Set before start(); runs on the receiver's thread.
    /// Without one these messages are refused (counted).
    using TextHandler = std::function<void(const std::string& text, int priority)>;
    void setTextHandler(TextHandler handler) { textHandler_ = std::move(handler); }
    void start();
    void stop();
    int port() const noexcept { return port_; }
    std::uint64_t commands() const noexcept { return commands_.load(); }
    std::uint64_t refused() const noexcept { return refused_.load(); }
    /// Decodes one datagram and runs the handler for each command in it (public for tests).
    void handleDatagram(const std::uint8_t* data, std::size_t size);

private:
    void run();
    int fd_ = -1;
    int port_ = 0;
    Handler handler_;
    TextHandler textHandler_;
    std::thread thread_;
    std::atomic<bool> stop_ {false};
    std::atomic<std::uint64_t> commands_ {0}, refused_ {0};
};

/// Reads single keys from a file descriptor (stdin) on its own thread. On a terminal it switches
/// off line buffering and echo (restored by stop()/the destructor); from a pipe it reads bytes.
class KeyReader {
public:
    using Handler = std::function<void(const core::StageCommand&)>;
    KeyReader(int fd, Handler handler);
    ~KeyReader();
    KeyReader(const KeyReader&) = delete;
    KeyReader& operator=(const KeyReader&) = delete;
    void start();
    void stop();

private:
    void run();
    int fd_;
    Handler handler_;
    std::thread thread_;
    std::atomic<bool> stop_ {false};
    bool restore_ = false;
    unsigned char saved_[128] {};   ///< the terminal's termios (opaque here)
};

} // namespace armadillo::live
