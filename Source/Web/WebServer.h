#pragma once
// The live instrument as a web page (issue 47; docs/INTERFACES.md "The web page", docs/SECURITY.md
// "The web page"): an HTTP server (cpp-httplib, Debian's libcpp-httplib-dev) that serves the
// page's files compiled into the program (Resources/web → Web/WebPage.h), the instrument's state
// as server-sent events, and takes the page's two state changes — stage commands and scene
// parameters — checked (Web/WebRequest.h) before they reach the instrument (Web/WebInstrument.h).
//
// Safe by default: it binds 127.0.0.1 unless given an address; with an address every request
// needs the session's token (in the address printed: ?token=…, then a cookie); a request whose
// Host is not this machine is refused (DNS rebinding); a state change needs the page's own
// Origin and the token in a header; only the page's own files are served; every response carries
// a Content-Security-Policy; a client that floods is cut off; bodies are at most 256 bytes.
//
// Threads: the constructor binds (the caller's thread); start() runs the listener on a thread of
// its own and the requests on a pool of kWorkers threads; stop() (or the destructor) ends both,
// the event streams within kEventPeriodMs. Everything else: any thread.
#include "Web/WebInstrument.h"
#include "Web/WebRequest.h"
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace armadillo::web {

/// `play --web PORT [--web-bind ADDR]` and the app's Setup → Web page.
struct WebConfig {
    bool on = false;
    int port = 0;          ///< 0: a free port
    std::string bind;      ///< "" = 127.0.0.1 and no token needed to read; else a numeric address of this machine
};

/// True for a numeric IPv4 or IPv6 address ("0.0.0.0" and "::" included).
bool isNumericAddress(const std::string& address);

class WebServer {
public:
    static constexpr int kWorkers = 12;        ///< request threads (the event streams and idle keep-alive connections hold one each)
    static constexpr int kMaxStreams = 4;      ///< event streams at once (more: 503)
    static constexpr int kEventPeriodMs = 200; ///< a status event every 200 ms
    static constexpr std::size_t kMaxBody = 256;

    /// Binds now: IoError when the port is taken or the address is not this machine's;
    /// std::invalid_argument for an address that is not numeric or a port out of range (the
    /// front ends check both first).
    WebServer(const WebConfig& config, InstrumentView& instrument);
    ~WebServer();
    WebServer(const WebServer&) = delete;
    WebServer& operator=(const WebServer&) = delete;

    void start();
    void stop();

    int port() const noexcept { return port_; }
    /// Where to open the page: "http://127.0.0.1:PORT/", or with an address
    /// "http://ADDR:PORT/?token=…" (IPv6 in brackets; for 0.0.0.0 or :: the first address of
    /// this machine's interfaces that is not loopback, else loopback).
    std::string address() const;
    bool tokenRequired() const noexcept { return tokenRequired_; }

    /// What happened since the last call, in words, for the front end to print: a command taken
    /// ("panic from 127.0.0.1 at t=5.230 s"), a client refused or cut off (each kind named once
    /// per client address, at most 64 addresses).
    std::vector<std::string> takeLines();

    struct Counters {
        std::uint64_t requests = 0, refusedHost = 0, refusedOrigin = 0, refusedToken = 0, refusedPath = 0,
                      refusedRate = 0, refusedBody = 0, stageCommands = 0, parameters = 0, procedureCommands = 0;
    };
    Counters counters() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int port_ = 0;
    bool tokenRequired_ = false;
    std::thread listener_;
};

} // namespace armadillo::web
