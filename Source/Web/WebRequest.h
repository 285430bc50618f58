#pragma once
// What the web page's server checks before anything a request carries reaches the instrument
// (docs/SECURITY.md "The web page"): who the request says it is for (Host, against DNS
// rebinding), where a state change comes from (Origin), the session's token, which of the page's
// own files a path names (nothing else is ever served), the bodies of the page's two state
// changes (a stage command, a scene parameter), parsed strictly and bounded, and how often one
// client may ask. Plain functions and one small class, no sockets and no HTTP library, so the
// fuzz target `web_request` and the unit tests reach every rule.
#include "Core/StageCommand.h"
#include "Web/WebInstrument.h"
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace armadillo::web {

/// The Host values a request may carry ("127.0.0.1:8080", "localhost:8080", "[::1]:8080" and,
/// when bound beyond loopback, "ADDR:8080" for the bound address or, for a wildcard bind, every
/// address of this machine's interfaces). Lower case; compared without regard to case.
std::vector<std::string> allowedHosts(const std::string& bindAddress, int port);

/// True when `host` (the Host header) is one of `allowed`.
bool hostAllowed(std::string_view host, const std::vector<std::string>& allowed);

/// True when `origin` (the Origin header) is the page's own: "http://" + the request's Host,
/// that Host being allowed. An absent Origin ("") is refused: browsers send one on every POST.
bool originAllowed(std::string_view origin, std::string_view host, const std::vector<std::string>& allowed);

/// Compares a token without an early exit (the time taken does not say how much matched).
bool tokenEquals(std::string_view given, std::string_view token) noexcept;

/// The value of the cookie `name` in a Cookie header ("" when absent).
std::string cookieValue(std::string_view cookieHeader, std::string_view name);

/// A fresh session token: 32 hexadecimal digits from /dev/urandom (IoError when it cannot be read).
std::string makeToken();

/// One of the page's files, compiled into the program (Web/WebPage.h).
struct PageFile {
    std::string_view path;          ///< "/index.html"
    std::string_view contentType;   ///< "text/html; charset=utf-8"
    std::string_view body;
};
/// The page file a request path names: "/" is "/index.html"; anything else must be one of the
/// embedded files' paths exactly (no "..", no percent escapes, no query). Null otherwise.
const PageFile* pageFile(std::string_view path) noexcept;

/// A stage command as the page sends it (the body of POST /api/stage): "panic", "resume",
/// "next", "previous" or "cue=N" (N a cue index 0..9999). Nothing else, no surrounding space.
std::optional<core::StageCommand> parseStageCommand(std::string_view body);

/// A command of the guided calibration (the body of POST /api/calibration): "begin", "next",
/// "skip" or "cancel", nothing else.
std::optional<ProcedureCommand> parseProcedureCommand(std::string_view body);
/// A scene choice: exactly `scene=NAME`, NAME of 1–40 lower-case letters, digits and '-'.
std::optional<std::string> parseSceneChoice(std::string_view body);
/// A sensitivity-test command: exactly `begin`, `felt`, `not-felt`, `again` or `cancel`.
std::optional<TouchCommand> parseTouchCommand(std::string_view body);

/// A scene parameter as the page sends it (the body of POST /api/param):
/// "id=ID&value=NUMBER" — ID 1..64 characters of [a-z0-9._-], NUMBER a finite decimal of at most
/// 32 characters. The value is not clamped here: the instrument clamps it to the parameter's range.
struct ParamRequest {
    std::string id;
    double value = 0.0;
};
std::optional<ParamRequest> parseParamRequest(std::string_view body);

/// How often one client (by its address) may ask: a bucket of `burst` requests refilled at `rate`
/// per second. A client that empties it is cut off for `cutOffSeconds` (every request refused),
/// and named once. At most kMaxClients addresses are remembered (the least recent forgotten).
/// Thread-safe (one mutex; the server's worker threads share it).
class ClientLimiter {
public:
    static constexpr std::size_t kMaxClients = 256;
    struct Options {
        double rate = 40.0;          ///< requests per second, sustained
        double burst = 120.0;        ///< requests at once
        double cutOffSeconds = 10.0;
    };
    ClientLimiter() : ClientLimiter(Options {}) {}
    explicit ClientLimiter(Options options) : options_(options) {}

    enum class Verdict { Admit, Refuse, CutOffNow };
    /// `now`: seconds on any steady clock. CutOffNow: this request emptied the bucket (the caller
    /// says so once); Refuse: the client is cut off.
    Verdict admit(const std::string& client, double now);
    std::uint64_t refused() const;

private:
    struct Client {
        double tokens = 0.0, last = 0.0, cutOffUntil = -1.0;
    };
    Options options_;
    mutable std::mutex mutex_;
    std::unordered_map<std::string, Client> clients_;
    std::uint64_t refused_ = 0;
};

} // namespace armadillo::web
