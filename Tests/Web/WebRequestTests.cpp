// The web page's checks (Web/WebRequest.h) one rule at a time, and the server (Web/WebServer.h)
// over real loopback sockets with a stand-in instrument: what reaches the instrument and what is
// refused before it (docs/SECURITY.md "The web page").
#include "Common/HttpProbe.h"
#include "Web/QrText.h"
#include "Web/WebPage.h"
#include "Web/WebRequest.h"
#include "Web/WebServer.h"
#include <catch2/catch.hpp>
#include <arpa/inet.h>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <mutex>
#include <netinet/in.h>
#include <string>
#include <sys/socket.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::web;

TEST_CASE("Host: only this machine's names with the port", "[web][security]")
{
    const auto hosts = allowedHosts("", 8080);
    CHECK(hostAllowed("127.0.0.1:8080", hosts));
    CHECK(hostAllowed("LOCALHOST:8080", hosts));
    CHECK(hostAllowed("[::1]:8080", hosts));
    CHECK_FALSE(hostAllowed("127.0.0.1:8081", hosts));
    CHECK_FALSE(hostAllowed("127.0.0.1", hosts));
    CHECK_FALSE(hostAllowed("evil.example:8080", hosts));
    CHECK_FALSE(hostAllowed("", hosts));
    CHECK_FALSE(hostAllowed("192.168.1.20:8080", hosts));
    CHECK(hostAllowed("192.168.1.20:8080", allowedHosts("192.168.1.20", 8080)));
}

TEST_CASE("Origin: a state change only from the page's own origin", "[web][security]")
{
    const auto hosts = allowedHosts("", 9000);
    CHECK(originAllowed("http://127.0.0.1:9000", "127.0.0.1:9000", hosts));
    CHECK_FALSE(originAllowed("http://evil.example", "127.0.0.1:9000", hosts));
    CHECK_FALSE(originAllowed("http://localhost:9000", "127.0.0.1:9000", hosts));   // another origin, though this machine
    CHECK_FALSE(originAllowed("", "127.0.0.1:9000", hosts));
    CHECK_FALSE(originAllowed("null", "127.0.0.1:9000", hosts));
    CHECK_FALSE(originAllowed("https://127.0.0.1:9000", "127.0.0.1:9000", hosts));
    CHECK_FALSE(originAllowed("http://evil.example:9000", "evil.example:9000", hosts));   // a rebound name
}

TEST_CASE("token: fresh, compared whole, found in a cookie", "[web][security]")
{
    const std::string a = makeToken(), b = makeToken();
    CHECK(a.size() == 32);
    CHECK(a != b);
    CHECK(tokenEquals(a, a));
    CHECK_FALSE(tokenEquals(a.substr(0, 31), a));
    CHECK_FALSE(tokenEquals(a + "0", a));
    CHECK_FALSE(tokenEquals("", ""));
    CHECK(cookieValue("x=1; armadillo_token=abc; y=2", "armadillo_token") == "abc");
    CHECK(cookieValue("armadillo_token_x=abc", "armadillo_token").empty());
}

TEST_CASE("paths: the page's own files and nothing else", "[web][security]")
{
    REQUIRE(pageFile("/") != nullptr);
    CHECK(pageFile("/")->path == "/index.html");
    CHECK(pageFile("/app.js") != nullptr);
    CHECK(pageFile("/style.css") != nullptr);
    CHECK(pageFile("/style.css")->contentType.find("text/css") == 0);
    CHECK(pageFile("/../../etc/passwd") == nullptr);
    CHECK(pageFile("/index.html/..") == nullptr);
    CHECK(pageFile("//index.html") == nullptr);
    CHECK(pageFile("/Index.html") == nullptr);
    CHECK(pageFile("") == nullptr);
    CHECK(pageFile("/%2e%2e/etc/passwd") == nullptr);
}

TEST_CASE("stage commands: five words, nothing else", "[web]")
{
    using Kind = core::StageCommand::Kind;
    CHECK(parseStageCommand("panic")->kind == Kind::Panic);
    CHECK(parseStageCommand("resume")->kind == Kind::Resume);
    CHECK(parseStageCommand("next")->kind == Kind::CueNext);
    CHECK(parseStageCommand("previous")->kind == Kind::CuePrev);
    CHECK(parseStageCommand("cue=12")->cue == 12);
    for (const char* bad : {"", "Panic", " panic", "panic\n", "cue=", "cue=-1", "cue=12345", "cue=1a", "stop"})
        CHECK_FALSE(parseStageCommand(bad).has_value());
}

TEST_CASE("calibration commands: four words, nothing else", "[web]")
{
    CHECK(parseProcedureCommand("begin") == ProcedureCommand::Begin);
    CHECK(parseProcedureCommand("next") == ProcedureCommand::Next);
    CHECK(parseProcedureCommand("skip") == ProcedureCommand::Skip);
    CHECK(parseProcedureCommand("cancel") == ProcedureCommand::Cancel);
    for (const char* bad : {"", "save", "begin ", "NEXT", "next\n"}) CHECK_FALSE(parseProcedureCommand(bad).has_value());
    CHECK(parseSceneChoice("scene=theremin") == std::optional<std::string>("theremin"));
    CHECK(parseSceneChoice("scene=audio-touch") == std::optional<std::string>("audio-touch"));
    for (const char* bad : {"", "scene=", "theremin", "scene=Theremin", "scene=../x", "scene=a b", "scene=a\n"})
        CHECK_FALSE(parseSceneChoice(bad).has_value());
    CHECK_FALSE(parseSceneChoice("scene=" + std::string(41, 'a')).has_value());
    CHECK(parseTouchCommand("begin") == TouchCommand::Begin);
    CHECK(parseTouchCommand("felt") == TouchCommand::Felt);
    CHECK(parseTouchCommand("not-felt") == TouchCommand::NotFelt);
    CHECK(parseTouchCommand("again") == TouchCommand::Again);
    CHECK(parseTouchCommand("cancel") == TouchCommand::Cancel);
    for (const char* bad : {"", "yes", "felt ", "FELT", "not felt", "next"}) CHECK_FALSE(parseTouchCommand(bad).has_value());
}

TEST_CASE("parameters: a plain id and a finite number", "[web]")
{
    const auto p = parseParamRequest("id=theremin.range&value=24.5");
    REQUIRE(p.has_value());
    CHECK(p->id == "theremin.range");
    CHECK(p->value == 24.5);
    CHECK(parseParamRequest("id=a&value=-1e3")->value == -1000.0);
    for (const char* bad : {"", "id=&value=1", "id=A&value=1", "id=a b&value=1", "id=a&value=", "id=a&value=nan",
                            "id=a&value=inf", "id=a&value=1e999", "id=a&value=0x10", "value=1&id=a", "id=a;rm&value=1"})
        CHECK_FALSE(parseParamRequest(bad).has_value());
}

TEST_CASE("a client that floods is cut off, others are not", "[web][security]")
{
    ClientLimiter limiter({10.0, 20.0, 5.0});
    int admitted = 0;
    ClientLimiter::Verdict last = ClientLimiter::Verdict::Admit;
    for (int i = 0; i < 100; ++i) {   // 100 requests within 0.1 s
        last = limiter.admit("10.0.0.9", i * 0.001);
        if (last == ClientLimiter::Verdict::Admit) ++admitted;
        else break;
    }
    CHECK(admitted == 20);
    CHECK(last == ClientLimiter::Verdict::CutOffNow);
    CHECK(limiter.admit("10.0.0.9", 1.0) == ClientLimiter::Verdict::Refuse);   // still cut off
    CHECK(limiter.admit("10.0.0.8", 1.0) == ClientLimiter::Verdict::Admit);    // another client
    CHECK(limiter.admit("10.0.0.9", 5.2) == ClientLimiter::Verdict::Admit);    // after the cut-off
}

namespace {

/// A stand-in instrument: counts what reaches it.
struct FakeInstrument : InstrumentView {
    std::atomic<int> panics {0}, params {0};
    InstrumentStatus status() override
    {
        InstrumentStatus s;
        s.t = 1.5;
        s.source = "test";
        return s;
    }
    std::vector<ParameterInfo> parameters() override { return {{"x.gain", "Gain", "", 0.0, 1.0, 0.5, {}}}; }
    void stage(const core::StageCommand& c) override
    {
        if (c.kind == core::StageCommand::Kind::Panic) ++panics;
    }
    bool setParameter(const std::string& id, double value, double& set) override
    {
        if (id != "x.gain") return false;
        ++params;
        set = std::clamp(value, 0.0, 1.0);
        return true;
    }
    void calibration(ProcedureCommand) override {}
    std::string calibrationFile() override { return {}; }
    std::vector<std::string> sceneChoices(std::string& why) override
    {
        why.clear();
        return {"theremin", "cymbal"};
    }
    std::atomic<int> sceneChanges {0};
    std::string chooseScene(const std::string& name) override
    {
        if (name != "cymbal") return "not here";
        ++sceneChanges;
        return {};
    }
    std::atomic<int> touches {0};
    void touchTest(TouchCommand) override { ++touches; }
    std::string touchProfileFile() override { return {}; }
};

int send(int port, const std::string& request, std::string* reply = nullptr) { return testing::httpSend(port, request, reply); }
std::string post(int port, const std::string& path, const std::string& body, const std::string& origin, const std::string& token)
{
    return testing::httpPost(port, path, body, origin, token);
}
std::string tokenOf(int port) { return testing::pageToken(port); }

} // namespace

TEST_CASE("server: what reaches the instrument, what is refused before it", "[web][security]")
{
    FakeInstrument instrument;
    WebServer server({true, 0, ""}, instrument);
    server.start();
    const int port = server.port();
    const std::string self = "http://127.0.0.1:" + std::to_string(port), host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
    CHECK(server.address() == self + "/");
    const std::string token = tokenOf(port);
    REQUIRE(token.size() == 32);

    std::string reply;
    CHECK(send(port, "GET /app.js HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", &reply) == 200);
    CHECK(reply.find("Content-Security-Policy: default-src 'self'") != std::string::npos);
    CHECK(reply.find("X-Content-Type-Options: nosniff") != std::string::npos);
    CHECK(send(port, "GET / HTTP/1.1\r\nHost: evil.example:" + std::to_string(port) + "\r\nConnection: close\r\n\r\n") == 403);
    CHECK(send(port, "GET /../../etc/passwd HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", &reply) == 400);
    CHECK(reply.find("root:") == std::string::npos);
    CHECK(send(port, "GET /secret.txt HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n") == 404);
    CHECK(send(port, "GET /api/calibration.json HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n") == 404);   // none finished

    CHECK(send(port, post(port, "/api/stage", "panic", "http://evil.example", token)) == 403);
    CHECK(send(port, post(port, "/api/stage", "panic", self, "0123")) == 403);
    CHECK(send(port, post(port, "/api/stage", "explode", self, token)) == 400);
    CHECK(send(port, post(port, "/api/stage", std::string(300, 'a'), self, token)) == 413);
    CHECK(instrument.panics == 0);
    CHECK(send(port, post(port, "/api/stage", "panic", self, token), &reply) == 200);
    CHECK(instrument.panics == 1);
    CHECK(reply.find("\"t\":1.500") != std::string::npos);
    CHECK(send(port, post(port, "/api/param", "id=x.gain&value=7", self, token), &reply) == 200);
    CHECK(reply.find("\"value\":1.0000") != std::string::npos);   // clamped by the instrument
    CHECK(send(port, post(port, "/api/param", "id=x.other&value=7", self, token)) == 404);
    CHECK(instrument.params == 1);
    CHECK(send(port, post(port, "/api/scene", "scene=cymbal", "http://evil.example", token)) == 403);
    CHECK(send(port, post(port, "/api/scene", "scene=../x", self, token)) == 400);
    CHECK(send(port, post(port, "/api/scene", "scene=braille", self, token), &reply) == 409);
    CHECK(reply.find("not here") != std::string::npos);
    CHECK(instrument.sceneChanges == 0);
    CHECK(send(port, post(port, "/api/scene", "scene=cymbal", self, token)) == 200);
    CHECK(instrument.sceneChanges == 1);
    CHECK(send(port, "GET /api/scene HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", &reply) == 200);
    CHECK(reply.find("\"scenes\":[\"theremin\",\"cymbal\"],\"scene_choice\":\"\"") != std::string::npos);
    CHECK(send(port, post(port, "/api/touch", "yes", self, token)) == 400);
    CHECK(send(port, post(port, "/api/touch", "felt", "http://evil.example", token)) == 403);
    CHECK(instrument.touches == 0);
    CHECK(send(port, post(port, "/api/touch", "felt", self, token), &reply) == 200);
    CHECK(instrument.touches == 1);
    CHECK(reply.find("\"touch\":{\"available\":false") != std::string::npos);
    CHECK(send(port, "GET /api/touch-profile.json HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n") == 404);   // none measured

    const WebServer::Counters c = server.counters();
    CHECK(c.refusedHost == 1);
    CHECK(c.refusedOrigin == 3);
    CHECK(c.refusedToken == 1);
    CHECK(c.refusedBody == 3);
    CHECK(c.stageCommands == 2);
    server.stop();
}

TEST_CASE("server: with an address every request needs the token", "[web][security]")
{
    FakeInstrument instrument;
    WebServer server({true, 0, "127.0.0.1"}, instrument);   // "bound to an address": the token is required
    server.start();
    const int port = server.port();
    const std::string address = server.address();
    REQUIRE(address.find("?token=") != std::string::npos);
    const std::string token = address.substr(address.find("?token=") + 7);
    const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\nConnection: close\r\n";
    CHECK(send(port, "GET / HTTP/1.1\r\n" + host + "\r\n") == 403);
    CHECK(send(port, "GET /api/status HTTP/1.1\r\n" + host + "\r\n") == 403);
    std::string reply;
    CHECK(send(port, "GET /?token=" + token + " HTTP/1.1\r\n" + host + "\r\n", &reply) == 200);
    CHECK(reply.find("Set-Cookie: armadillo_token=" + token) != std::string::npos);
    CHECK(send(port, "GET /app.js HTTP/1.1\r\n" + host + "Cookie: armadillo_token=" + token + "\r\n\r\n") == 200);
    server.stop();
}

TEST_CASE("server: a client that floods is cut off", "[web][security]")
{
    FakeInstrument instrument;
    WebServer server({true, 0, ""}, instrument);
    server.start();
    const int port = server.port();
    const std::string request = "GET /style.css HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nConnection: close\r\n\r\n";
    int ok = 0, refused = 0;
    for (int i = 0; i < 400 && refused == 0; ++i) (send(port, request) == 200 ? ok : refused)++;
    CHECK(refused == 1);
    CHECK(ok >= 100);                      // the burst was served
    CHECK(send(port, request) == 429);     // and now it is cut off
    CHECK(server.counters().refusedRate >= 2);
    bool named = false;
    for (const std::string& line : server.takeLines()) named = named || line.find("cut off 127.0.0.1") != std::string::npos;
    CHECK(named);
    server.stop();
}

TEST_CASE("page files: every file of Resources/web is built in with the source tree's bytes, and nothing else", "[web]")
{
    namespace fs = std::filesystem;
    const fs::path source = fs::path(ARMADILLO_SOURCE_DIR) / "Resources" / "web";
    std::size_t onDisk = 0;
    for (const auto& entry : fs::directory_iterator(source)) {
        if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
        ++onDisk;
        const std::string path = "/" + entry.path().filename().string();
        INFO(path);
        const PageFile* f = pageFile(path);
        REQUIRE(f != nullptr);
        std::ifstream in(entry.path(), std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        CHECK(std::string(f->body) == bytes.str());
        CHECK_FALSE(f->contentType.empty());
    }
    CHECK(onDisk >= 3);   // the HTML, its style sheet and its script
    CHECK(pageFiles().size() == onDisk);
}

TEST_CASE("QR code: the page's address as modules (the app draws them) and as terminal lines", "[web]")
{
    const std::string address = "http://192.168.1.20:8080/?token=0123456789abcdef0123456789abcdef";
    int w = 0;
    const std::vector<bool> dark = qrModules(address, w);
    REQUIRE(w >= 21);
    CHECK((w - 17) % 4 == 0);   // a QR version's size: 21, 25, 29, …
    REQUIRE(dark.size() == static_cast<std::size_t>(w * w));
    // The three finder patterns: a dark 7×7 ring around a light ring around a dark 3×3 centre.
    for (const auto [ox, oy] : {std::pair {0, 0}, std::pair {w - 7, 0}, std::pair {0, w - 7}}) {
        CHECK(dark[static_cast<std::size_t>(oy * w + ox)]);
        CHECK(dark[static_cast<std::size_t>((oy + 6) * w + ox + 6)]);
        CHECK_FALSE(dark[static_cast<std::size_t>((oy + 1) * w + ox + 1)]);
        CHECK(dark[static_cast<std::size_t>((oy + 3) * w + ox + 3)]);
    }
    CHECK(qrLines(address).size() == static_cast<std::size_t>((w + 4 + 1) / 2));   // two rows a line, quiet zone 2
}
