#include "Web/WebRequest.h"
#include "Core/Errors.h"
#include "Web/WebPage.h"
#include <algorithm>
#include <arpa/inet.h>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <ifaddrs.h>
#include <netinet/in.h>

namespace armadillo::web {

namespace {

char lower(char c) noexcept { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

bool equalsNoCase(std::string_view a, std::string_view b) noexcept
{
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (lower(a[i]) != lower(b[i])) return false;
    return true;
}

bool isWildcard(const std::string& address) { return address == "0.0.0.0" || address == "::"; }

/// "ADDR:PORT", IPv6 in brackets.
std::string hostWithPort(const std::string& address, int port)
{
    const bool v6 = address.find(':') != std::string::npos;
    std::string h = v6 ? "[" + address + "]" : address;
    std::transform(h.begin(), h.end(), h.begin(), lower);
    return h + ":" + std::to_string(port);
}

/// Every IPv4 and IPv6 address of this machine's interfaces (for a wildcard bind).
std::vector<std::string> interfaceAddresses()
{
    std::vector<std::string> out;
    ifaddrs* list = nullptr;
    if (::getifaddrs(&list) != 0) return out;
    for (const ifaddrs* a = list; a != nullptr; a = a->ifa_next) {
        if (a->ifa_addr == nullptr) continue;
        char text[INET6_ADDRSTRLEN] {};
        if (a->ifa_addr->sa_family == AF_INET) {
            ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof text);
        } else if (a->ifa_addr->sa_family == AF_INET6) {
            const auto* in6 = reinterpret_cast<const sockaddr_in6*>(a->ifa_addr);
            if (IN6_IS_ADDR_LINKLOCAL(&in6->sin6_addr)) continue;   // a link-local Host needs a zone: not offered
            ::inet_ntop(AF_INET6, &in6->sin6_addr, text, sizeof text);
        } else {
            continue;
        }
        out.emplace_back(text);
    }
    ::freeifaddrs(list);
    return out;
}

/// A decimal of at most 32 characters: [-+]digits[.digits][e[-+]digits], finite.
std::optional<double> parseNumber(std::string_view s)
{
    if (s.empty() || s.size() > 32) return std::nullopt;
    for (char c : s)
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) return std::nullopt;
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

} // namespace

std::vector<std::string> allowedHosts(const std::string& bindAddress, int port)
{
    std::vector<std::string> hosts {hostWithPort("127.0.0.1", port), "localhost:" + std::to_string(port), hostWithPort("::1", port)};
    std::vector<std::string> extra;
    if (isWildcard(bindAddress)) extra = interfaceAddresses();
    else if (!bindAddress.empty()) extra.push_back(bindAddress);
    for (const std::string& a : extra) {
        const std::string h = hostWithPort(a, port);
        if (std::find(hosts.begin(), hosts.end(), h) == hosts.end()) hosts.push_back(h);
    }
    return hosts;
}

bool hostAllowed(std::string_view host, const std::vector<std::string>& allowed)
{
    return std::any_of(allowed.begin(), allowed.end(), [&](const std::string& a) { return equalsNoCase(host, a); });
}

bool originAllowed(std::string_view origin, std::string_view host, const std::vector<std::string>& allowed)
{
    constexpr std::string_view scheme = "http://";
    if (origin.size() <= scheme.size() || !equalsNoCase(origin.substr(0, scheme.size()), scheme)) return false;
    const std::string_view originHost = origin.substr(scheme.size());
    return equalsNoCase(originHost, host) && hostAllowed(host, allowed);
}

bool tokenEquals(std::string_view given, std::string_view token) noexcept
{
    unsigned diff = given.size() == token.size() ? 0u : 1u;
    for (std::size_t i = 0; i < token.size(); ++i) {
        const char g = i < given.size() ? given[i] : '\0';
        diff |= static_cast<unsigned>(static_cast<unsigned char>(g) ^ static_cast<unsigned char>(token[i]));
    }
    return diff == 0 && !token.empty();
}

std::string cookieValue(std::string_view header, std::string_view name)
{
    while (!header.empty()) {
        const std::size_t semi = header.find(';');
        std::string_view part = header.substr(0, semi);
        header = semi == std::string_view::npos ? std::string_view {} : header.substr(semi + 1);
        while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
        const std::size_t eq = part.find('=');
        if (eq != std::string_view::npos && part.substr(0, eq) == name) return std::string(part.substr(eq + 1));
    }
    return {};
}

std::string makeToken()
{
    unsigned char bytes[16] {};
    std::FILE* f = std::fopen("/dev/urandom", "rb");
    const bool ok = f != nullptr && std::fread(bytes, 1, sizeof bytes, f) == sizeof bytes;
    if (f != nullptr) std::fclose(f);
    if (!ok) throw core::IoError("web page: cannot read /dev/urandom for the session token");
    static constexpr char kHex[] = "0123456789abcdef";
    std::string token;
    for (unsigned char b : bytes) {
        token += kHex[b >> 4];
        token += kHex[b & 15];
    }
    return token;
}

const PageFile* pageFile(std::string_view path) noexcept
{
    if (path == "/") path = "/index.html";
    for (const PageFile& f : pageFiles())
        if (f.path == path) return &f;
    return nullptr;
}

std::optional<core::StageCommand> parseStageCommand(std::string_view body)
{
    using Kind = core::StageCommand::Kind;
    if (body == "panic") return core::StageCommand {Kind::Panic, 0};
    if (body == "resume") return core::StageCommand {Kind::Resume, 0};
    if (body == "next") return core::StageCommand {Kind::CueNext, 0};
    if (body == "previous") return core::StageCommand {Kind::CuePrev, 0};
    constexpr std::string_view cue = "cue=";
    if (body.size() <= cue.size() || body.size() > cue.size() + 4 || body.substr(0, cue.size()) != cue) return std::nullopt;
    int index = 0;
    for (char c : body.substr(cue.size())) {
        if (c < '0' || c > '9') return std::nullopt;
        index = index * 10 + (c - '0');
    }
    return core::StageCommand {Kind::CueGoto, index};
}

std::optional<ProcedureCommand> parseProcedureCommand(std::string_view body)
{
    if (body == "begin") return ProcedureCommand::Begin;
    if (body == "next") return ProcedureCommand::Next;
    if (body == "skip") return ProcedureCommand::Skip;
    if (body == "cancel") return ProcedureCommand::Cancel;
    return std::nullopt;
}

std::optional<std::string> parseSceneChoice(std::string_view body)
{
    constexpr std::string_view key = "scene=";
    if (body.substr(0, key.size()) != key) return std::nullopt;
    const std::string_view name = body.substr(key.size());
    if (name.empty() || name.size() > 40) return std::nullopt;
    for (const char c : name)
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-')) return std::nullopt;
    return std::string(name);
}

std::optional<TouchCommand> parseTouchCommand(std::string_view body)
{
    if (body == "begin") return TouchCommand::Begin;
    if (body == "felt") return TouchCommand::Felt;
    if (body == "not-felt") return TouchCommand::NotFelt;
    if (body == "again") return TouchCommand::Again;
    if (body == "cancel") return TouchCommand::Cancel;
    return std::nullopt;
}

std::optional<ParamRequest> parseParamRequest(std::string_view body)
{
    constexpr std::string_view idKey = "id=", valueKey = "&value=";
    if (body.size() > 128 || body.substr(0, idKey.size()) != idKey) return std::nullopt;
    const std::size_t amp = body.find(valueKey);
    if (amp == std::string_view::npos) return std::nullopt;
    const std::string_view id = body.substr(idKey.size(), amp - idKey.size());
    if (id.empty() || id.size() > 64) return std::nullopt;
    for (char c : id)
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-')) return std::nullopt;
    const std::optional<double> value = parseNumber(body.substr(amp + valueKey.size()));
    if (!value) return std::nullopt;
    return ParamRequest {std::string(id), *value};
}

ClientLimiter::Verdict ClientLimiter::admit(const std::string& client, double now)
{
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = clients_.find(client);
    if (it == clients_.end()) {
        if (clients_.size() >= kMaxClients) {   // forget the client heard least recently
            auto oldest = std::min_element(clients_.begin(), clients_.end(),
                                           [](const auto& a, const auto& b) { return a.second.last < b.second.last; });
            clients_.erase(oldest);
        }
        it = clients_.emplace(client, Client {options_.burst, now, -1.0}).first;
    }
    Client& c = it->second;
    if (now < c.cutOffUntil) {
        ++refused_;
        return Verdict::Refuse;
    }
    c.tokens = std::min(options_.burst, c.tokens + std::max(0.0, now - c.last) * options_.rate);
    c.last = now;
    if (c.tokens < 1.0) {
        c.cutOffUntil = now + options_.cutOffSeconds;
        c.tokens = options_.burst;   // a full bucket again once the cut-off is over
        ++refused_;
        return Verdict::CutOffNow;
    }
    c.tokens -= 1.0;
    return Verdict::Admit;
}

std::uint64_t ClientLimiter::refused() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return refused_;
}

} // namespace armadillo::web
