#include "Web/WebServer.h"
#include "Core/Errors.h"
#include "Web/WebJson.h"
#include <httplib.h>
#include <algorithm>
#include <arpa/inet.h>
#include <chrono>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <sys/socket.h>

namespace armadillo::web {

namespace {

constexpr const char* kTokenCookie = "armadillo_token";
constexpr const char* kTokenHeader = "X-Armadillo-Token";
constexpr const char* kTokenPlaceholder = "@ARMADILLO_TOKEN@";

double steadySeconds()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The first non-loopback address of this machine for a wildcard bind (the one printed).
std::string printableAddress(const std::string& bind, const std::vector<std::string>& hosts)
{
    if (bind != "0.0.0.0" && bind != "::") return bind.empty() ? "127.0.0.1" : bind;
    for (const std::string& h : hosts) {
        if (h.rfind("127.", 0) == 0 || h.rfind("localhost:", 0) == 0 || h.rfind("[::1]", 0) == 0) continue;
        if (bind == "0.0.0.0" && h.front() == '[') continue;
        const std::string a = h.substr(0, h.rfind(':'));
        return a.front() == '[' ? a.substr(1, a.size() - 2) : a;
    }
    return "127.0.0.1";
}

std::string formatSeconds(double t)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", t);
    return text;
}

const char* commandName(const core::StageCommand& c)
{
    switch (c.kind) {
    case core::StageCommand::Kind::Panic: return "panic";
    case core::StageCommand::Kind::Resume: return "resume";
    case core::StageCommand::Kind::CueNext: return "next cue";
    case core::StageCommand::Kind::CuePrev: return "previous cue";
    case core::StageCommand::Kind::CueGoto: return "cue";
    }
    return "?";
}

} // namespace

bool isNumericAddress(const std::string& address)
{
    unsigned char buf[sizeof(in6_addr)];
    return ::inet_pton(AF_INET, address.c_str(), buf) == 1 || ::inet_pton(AF_INET6, address.c_str(), buf) == 1;
}

struct WebServer::Impl {
    Impl(const WebConfig& c, InstrumentView& i) : config(c), instrument(i) {}

    WebConfig config;
    InstrumentView& instrument;
    httplib::Server server;
    std::string token;
    bool tokenRequired = false;
    std::vector<std::string> hosts;   // allowed Host values
    ClientLimiter limiter;
    std::atomic<int> streams {0};
    std::atomic<bool> stopping {false};
    mutable std::mutex mutex;         // lines, named, counters
    std::vector<std::string> lines;
    std::set<std::string> named;      // "kind client" said once
    Counters counters;

    void say(const std::string& line)
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (lines.size() < 256) lines.push_back(line);
    }
    /// Counts a refusal and names the client the first time for this kind.
    void refuse(std::uint64_t Counters::*counter, const std::string& kind, const std::string& client)
    {
        std::lock_guard<std::mutex> lock(mutex);
        ++(counters.*counter);
        if (named.size() < 64 * 6 && named.insert(kind + " " + client).second && lines.size() < 256)
            lines.push_back("refused a request from " + client + " (" + kind + ")");
    }

    static void refusal(httplib::Response& res, int status, const std::string& why)
    {
        res.status = status;
        res.set_header("Connection", "close");
        res.set_content("refused: " + why + "\n", "text/plain; charset=utf-8");
    }

    bool tokenGiven(const httplib::Request& req) const
    {
        return tokenEquals(req.get_header_value(kTokenHeader), token) || tokenEquals(req.get_param_value("token"), token) ||
               tokenEquals(cookieValue(req.get_header_value("Cookie"), kTokenCookie), token);
    }

    /// Every check before a route runs: rate, Host, path, token, and for a state change Origin.
    httplib::Server::HandlerResponse check(const httplib::Request& req, httplib::Response& res)
    {
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++counters.requests;
        }
        const ClientLimiter::Verdict verdict = limiter.admit(req.remote_addr, steadySeconds());
        if (verdict != ClientLimiter::Verdict::Admit) {
            if (verdict == ClientLimiter::Verdict::CutOffNow) say("cut off " + req.remote_addr + " for 10 s (too many requests)");
            refuse(&Counters::refusedRate, "too many requests", req.remote_addr);
            refusal(res, 429, "too many requests");
            return httplib::Server::HandlerResponse::Handled;
        }
        if (!hostAllowed(req.get_header_value("Host"), hosts)) {
            refuse(&Counters::refusedHost, "Host is not this machine", req.remote_addr);
            refusal(res, 403, "Host is not this machine");
            return httplib::Server::HandlerResponse::Handled;
        }
        if (req.path.find("..") != std::string::npos || req.path.find('\\') != std::string::npos || req.path.empty() || req.path.front() != '/') {
            refuse(&Counters::refusedPath, "a path outside the page", req.remote_addr);
            refusal(res, 400, "not a path of this page");
            return httplib::Server::HandlerResponse::Handled;
        }
        const bool change = req.method == "POST";
        if ((tokenRequired || change) && !tokenGiven(req)) {
            refuse(&Counters::refusedToken, "no session token", req.remote_addr);
            refusal(res, 403, "the session's token is missing or wrong");
            return httplib::Server::HandlerResponse::Handled;
        }
        const std::string site = req.get_header_value("Sec-Fetch-Site");
        if (change && (!originAllowed(req.get_header_value("Origin"), req.get_header_value("Host"), hosts) || (!site.empty() && site != "same-origin"))) {
            refuse(&Counters::refusedOrigin, "a state change from another origin", req.remote_addr);
            refusal(res, 403, "state changes only from this page");
            return httplib::Server::HandlerResponse::Handled;
        }
        return httplib::Server::HandlerResponse::Unhandled;
    }

    void servePage(const httplib::Request& req, httplib::Response& res)
    {
        const PageFile* file = pageFile(req.path);
        if (file == nullptr) {
            refuse(&Counters::refusedPath, "a path outside the page", req.remote_addr);
            refusal(res, 404, "not a file of this page");
            return;
        }
        std::string body(file->body);
        if (file->path == "/index.html") {
            const std::size_t at = body.find(kTokenPlaceholder);
            if (at != std::string::npos) body.replace(at, std::string_view(kTokenPlaceholder).size(), token);
            if (tokenRequired)   // the page's own files and its events carry the token from now on
                res.set_header("Set-Cookie", std::string(kTokenCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict");
        }
        res.set_content(body, std::string(file->contentType));
    }

    void serveEvents(httplib::Response& res)
    {
        if (streams.fetch_add(1) >= kMaxStreams) {
            streams.fetch_sub(1);
            refusal(res, 503, "too many event streams");
            return;
        }
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "text/event-stream",
            [this](std::size_t, httplib::DataSink& sink) {
                if (stopping.load()) return false;
                const std::string event = "data: " + statusJson(instrument.status()) + "\n\n";
                if (!sink.write(event.data(), event.size())) return false;
                for (int waited = 0; waited < kEventPeriodMs && !stopping.load(); waited += 20)
                    std::this_thread::sleep_for(std::chrono::milliseconds(20));
                return !stopping.load();
            },
            [this](bool) { streams.fetch_sub(1); });
    }

    void takeStage(const httplib::Request& req, httplib::Response& res)
    {
        const std::optional<core::StageCommand> command = parseStageCommand(req.body);
        if (!command) {
            refuse(&Counters::refusedBody, "a malformed stage command", req.remote_addr);
            refusal(res, 400, "not a stage command (panic, resume, next, previous, cue=N)");
            return;
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++counters.stageCommands;   // before it acts: a front end that sees the panic finds it counted
        }
        instrument.stage(*command);
        const double t = instrument.status().t;
        std::string what = commandName(*command);
        if (command->kind == core::StageCommand::Kind::CueGoto) what += " " + std::to_string(command->cue);
        say(what + " from " + req.remote_addr + " at t=" + formatSeconds(t) + " s");
        res.set_content(commandJson(what, t), "application/json");
    }

    void takeParameter(const httplib::Request& req, httplib::Response& res)
    {
        const std::optional<ParamRequest> p = parseParamRequest(req.body);
        if (!p) {
            refuse(&Counters::refusedBody, "a malformed parameter", req.remote_addr);
            refusal(res, 400, "not a parameter (id=ID&value=NUMBER)");
            return;
        }
        double set = 0.0;
        if (!instrument.setParameter(p->id, p->value, set)) {
            refusal(res, 404, "the scene has no parameter '" + p->id + "'");
            return;
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++counters.parameters;
        }
        res.set_content(parameterSetJson(p->id, set), "application/json");
    }

    void takeSceneChoice(const httplib::Request& req, httplib::Response& res)
    {
        const std::optional<std::string> name = parseSceneChoice(req.body);
        if (!name) {
            refuse(&Counters::refusedBody, "a malformed scene choice", req.remote_addr);
            refusal(res, 400, "not a scene choice (scene=NAME)");
            return;
        }
        if (const std::string why = instrument.chooseScene(*name); !why.empty()) {
            refusal(res, 409, "scene " + *name + " not played: " + why);
            return;
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++counters.stageCommands;
        }
        say("scene " + *name + " from " + req.remote_addr);
        res.set_content(std::string("{\"ok\":true,\"scene\":\"") + *name + "\"}", "application/json");
    }

    void takeCalibration(const httplib::Request& req, httplib::Response& res)
    {
        const std::optional<ProcedureCommand> command = parseProcedureCommand(req.body);
        if (!command) {
            refuse(&Counters::refusedBody, "a malformed calibration command", req.remote_addr);
            refusal(res, 400, "not a calibration command (begin, next, skip, cancel)");
            return;
        }
        instrument.calibration(*command);
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++counters.procedureCommands;
        }
        res.set_content(statusJson(instrument.status()), "application/json");
    }

    void takeTouch(const httplib::Request& req, httplib::Response& res)
    {
        const std::optional<TouchCommand> command = parseTouchCommand(req.body);
        if (!command) {
            refuse(&Counters::refusedBody, "a malformed sensitivity-test command", req.remote_addr);
            refusal(res, 400, "not a sensitivity-test command (begin, felt, not-felt, again, cancel)");
            return;
        }
        instrument.touchTest(*command);
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++counters.procedureCommands;
        }
        res.set_content(statusJson(instrument.status()), "application/json");
    }

    void serveTouchProfile(httplib::Response& res)
    {
        const std::string file = instrument.touchProfileFile();
        if (file.empty()) {
            refusal(res, 404, "no measured touch profile yet");
            return;
        }
        res.set_header("Content-Disposition", "attachment; filename=\"touch-profile.json\"");
        res.set_content(file, "application/json");
    }

    void serveCalibrationFile(httplib::Response& res)
    {
        const std::string file = instrument.calibrationFile();
        if (file.empty()) {
            refusal(res, 404, "no finished calibration yet");
            return;
        }
        res.set_header("Content-Disposition", "attachment; filename=\"calibration.json\"");
        res.set_content(file, "application/json");
    }

    void routes()
    {
        server.set_pre_routing_handler([this](const httplib::Request& q, httplib::Response& r) { return check(q, r); });
        server.Get("/events", [this](const httplib::Request&, httplib::Response& r) { serveEvents(r); });
        server.Get("/api/status", [this](const httplib::Request&, httplib::Response& r) {
            r.set_content(statusJson(instrument.status()), "application/json");
        });
        server.Get("/api/scene", [this](const httplib::Request&, httplib::Response& r) {
            std::string why;
            const std::vector<std::string> scenes = instrument.sceneChoices(why);
            r.set_content(sceneJson(instrument.status(), instrument.parameters(), scenes, why), "application/json");
        });
        // Browsers ask for an icon on their own; the page has none (no refusal to report).
        server.Get("/favicon.ico", [](const httplib::Request&, httplib::Response& r) { r.status = 204; });
        server.Post("/api/stage", [this](const httplib::Request& q, httplib::Response& r) { takeStage(q, r); });
        server.Post("/api/param", [this](const httplib::Request& q, httplib::Response& r) { takeParameter(q, r); });
        server.Post("/api/calibration", [this](const httplib::Request& q, httplib::Response& r) { takeCalibration(q, r); });
        server.Get("/api/calibration.json", [this](const httplib::Request&, httplib::Response& r) { serveCalibrationFile(r); });
        server.Post("/api/scene", [this](const httplib::Request& q, httplib::Response& r) { takeSceneChoice(q, r); });
        server.Post("/api/touch", [this](const httplib::Request& q, httplib::Response& r) { takeTouch(q, r); });
        server.Get("/api/touch-profile.json", [this](const httplib::Request&, httplib::Response& r) { serveTouchProfile(r); });
        server.Get(R"(/[a-z]*(\.[a-z]+)?)", [this](const httplib::Request& q, httplib::Response& r) { servePage(q, r); });
        server.set_error_handler([this](const httplib::Request& q, httplib::Response& r) {
            if (r.status == 404 && r.body.empty()) {
                refuse(&Counters::refusedPath, "a path outside the page", q.remote_addr);
                refusal(r, 404, "not a file of this page");
            }
        });
        server.set_exception_handler([](const httplib::Request&, httplib::Response& r, std::exception_ptr) {
            refusal(r, 500, "internal error");
        });
    }

    void configure()
    {
        // Everything the page is may come only from here: no inline script, no other site.
        server.set_default_headers({
            {"Content-Security-Policy", "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self'; connect-src 'self'; "
                                        "object-src 'none'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'"},
            {"X-Content-Type-Options", "nosniff"},
            {"X-Frame-Options", "DENY"},
            {"Referrer-Policy", "no-referrer"},
            {"Cache-Control", "no-store"},
        });
        server.set_payload_max_length(kMaxBody);
        server.set_keep_alive_max_count(100);
        server.set_keep_alive_timeout(3);
        server.set_read_timeout(5, 0);
        server.set_write_timeout(5, 0);
        server.new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
        // SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, which would let another
        // process of the same user bind the same port and take half the requests.
        server.set_socket_options([](socket_t sock) {
            int yes = 1;
            ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        });
        routes();
    }
};

WebServer::WebServer(const WebConfig& config, InstrumentView& instrument) : impl_(std::make_unique<Impl>(config, instrument))
{
    const std::string bind = config.bind.empty() ? "127.0.0.1" : config.bind;
    if (!isNumericAddress(bind)) throw std::invalid_argument("web page: '" + bind + "' is not a numeric IPv4 or IPv6 address");
    if (config.port < 0 || config.port > 65535) throw std::invalid_argument("web page: port " + std::to_string(config.port) + " is out of range");
    impl_->token = makeToken();
    impl_->tokenRequired = tokenRequired_ = !config.bind.empty();
    impl_->configure();
    if (bind.find(':') != std::string::npos) impl_->server.set_address_family(AF_INET6);
    if (config.port == 0) {
        port_ = impl_->server.bind_to_any_port(bind);
        if (port_ < 0) port_ = 0;
    } else if (impl_->server.bind_to_port(bind, config.port)) {
        port_ = config.port;
    }
    if (port_ <= 0)
        throw core::IoError("web page: cannot listen on " + bind + " port " + std::to_string(config.port) +
                            " (taken, or not an address of this machine)");
    impl_->hosts = allowedHosts(config.bind, port_);
}

WebServer::~WebServer() { stop(); }

void WebServer::start()
{
    if (listener_.joinable()) return;
    listener_ = std::thread([this] { impl_->server.listen_after_bind(); });
    // Running before start() returns, so a stop() that follows at once finds it running and ends it.
    for (int i = 0; i < 200 && !impl_->server.is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

void WebServer::stop()
{
    impl_->stopping.store(true);
    impl_->server.stop();
    if (listener_.joinable()) listener_.join();
}

std::string WebServer::address() const
{
    const std::string a = printableAddress(impl_->config.bind, impl_->hosts);
    const std::string host = a.find(':') != std::string::npos ? "[" + a + "]" : a;
    std::string url = "http://" + host + ":" + std::to_string(port_) + "/";
    if (tokenRequired_) url += "?token=" + impl_->token;
    return url;
}

std::vector<std::string> WebServer::takeLines()
{
    std::lock_guard<std::mutex> lock(impl_->mutex);
    std::vector<std::string> out;
    out.swap(impl_->lines);
    return out;
}

WebServer::Counters WebServer::counters() const
{
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->counters;
}

} // namespace armadillo::web
