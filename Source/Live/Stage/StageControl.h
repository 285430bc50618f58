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
#include "Osc/AllowList.h"
#include "Osc/Osc.h"
#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace armadillo::live {

/// A decoded OSC message as a stage command. false (with the reason in `why`) for any other
/// address or a /armadillo/cue whose argument is not one whole number ≥ 0.
bool stageCommandFromOsc(const osc::OscMessage& message, core::StageCommand& out, std::string& why);
/// A key typed on the terminal as a stage command; false for keys with no meaning.
bool stageCommandFromKey(char key, core::StageCommand& out);
/// "panic", "resume", "next cue", "previous cue", "cue 3".
std::string describe(const core::StageCommand& command);

/// Who the stage-control port hears (docs/SECURITY.md): the address it binds (loopback unless
/// told otherwise: `play --control-bind`, the app's stageOscBind) and the senders allowed
/// (`--control-allow`, stageOscAllow; empty: every sender that reaches the bound address).
struct StageControlListen {
    std::string bind = osc::kLoopbackAddress;
    osc::AllowList allow;
    /// How the refusal names the allow-list ("refused stage control from 10.0.0.9 (not in --control-allow)").
    std::string allowName = "--control-allow";
};

/// Listens for stage commands on a UDP port (loopback unless StageControlListen says otherwise)
/// on its own thread; the handler runs on that thread. Refused messages are counted; datagrams
/// from senders outside the allow-list are counted apart and each such sender named once.
class StageControlReceiver {
public:
    using Handler = std::function<void(const core::StageCommand&)>;
    /// Binds now (port 0 = any free port); throws IoError when the port is taken or the bind
    /// address is not one of this machine's.
    StageControlReceiver(int port, Handler handler, const StageControlListen& listen = {});
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
    /// Datagrams dropped because their sender is not in the allow-list.
    std::uint64_t notAllowed() const noexcept { return notAllowed_.load(); }
    /// The address the socket is bound to, as getsockname says ("127.0.0.1").
    const std::string& boundAddress() const noexcept { return boundAddress_; }
    /// "refused stage control from ADDR (not in --control-allow)" for each sender refused since
    /// the last call, every sender once (the first 64; later ones are only counted).
    std::vector<std::string> takeRefusals();
    /// The counters as JSON members for the session summary: ,"control_commands":N,
    /// "control_refused":N,"control_not_allowed":N.
    std::string summaryJson() const;
    /// Decodes one datagram and runs the handler for each command in it (public for tests).
    void handleDatagram(const std::uint8_t* data, std::size_t size);
    /// What the thread does with a datagram from `sender`: refused (counted, named once) when
    /// the allow-list does not hold it, else handleDatagram. Public for tests.
    void handleFrom(const struct sockaddr* sender, const std::uint8_t* data, std::size_t size);

private:
    void run();
    int fd_ = -1;
    int port_ = 0;
    std::string boundAddress_;
    StageControlListen listen_;
    std::mutex refusalsMutex_;
    std::vector<std::string> refusedSenders_, newRefusals_;   // under refusalsMutex_
    std::atomic<std::uint64_t> notAllowed_ {0};
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
