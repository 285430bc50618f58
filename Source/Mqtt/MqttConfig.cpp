#include "Mqtt/MqttConfig.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace armadillo::mqtt {

void parseBrokerAddress(const std::string& text, const std::string& option, std::string& host, int& port)
{
    std::string h = text, p;
    if (!h.empty() && h.front() == '[') {   // [IPv6]:port
        const auto close = h.find(']');
        if (close == std::string::npos) throw core::InputError("", 0, option, "'" + text + "': '[' without ']'");
        p = close + 1 < h.size() && h[close + 1] == ':' ? h.substr(close + 2) : "";
        if (close + 1 < h.size() && h[close + 1] != ':') throw core::InputError("", 0, option, "'" + text + "': expected ':PORT' after ']'");
        h = h.substr(1, close - 1);
    } else if (const auto colon = h.rfind(':'); colon != std::string::npos && h.find(':') == colon) {
        p = h.substr(colon + 1);
        h = h.substr(0, colon);
        if (p.empty()) throw core::InputError("", 0, option, "'" + text + "': empty port after ':'");
    }
    if (h.empty()) throw core::InputError("", 0, option, "'" + text + "': no host name (HOST or HOST:PORT)");
    if (!p.empty()) {
        int v = 0;
        const auto r = std::from_chars(p.data(), p.data() + p.size(), v);
        if (r.ec != std::errc() || r.ptr != p.data() + p.size() || v < 1 || v > 65535)
            throw core::InputError("", 0, option, "'" + text + "': port '" + p + "' is not a number from 1 to 65535");
        port = v;
    }
    host = h;
}

std::string topicFilterProblem(const std::string& filter)
{
    if (filter.empty()) return "an empty topic";
    if (filter.size() > 65535) return "a topic longer than 65535 bytes";
    for (std::size_t i = 0; i < filter.size(); ++i) {
        const char c = filter[i];
        if (c == '\0') return "a NUL character in the topic";
        if (c == '#' && (i + 1 != filter.size() || (i > 0 && filter[i - 1] != '/')))
            return "'#' must be a whole level and the last one (\"a/#\")";
        if (c == '+' && ((i > 0 && filter[i - 1] != '/') || (i + 1 < filter.size() && filter[i + 1] != '/')))
            return "'+' must be a whole level (\"a/+/b\")";
    }
    return {};
}

bool topicMatches(const std::string& filter, const std::string& topic) noexcept
{
    // MQTT 3.1.1 §4.7.2: topics starting with '$' are not matched by a leading wildcard.
    if (!topic.empty() && topic[0] == '$' && !filter.empty() && (filter[0] == '+' || filter[0] == '#')) return false;
    std::size_t f = 0, t = 0;
    while (true) {
        const std::size_t fe = filter.find('/', f), te = topic.find('/', t);
        const std::string_view fl(filter.data() + f, (fe == std::string::npos ? filter.size() : fe) - f);
        if (fl == "#") return true;
        if (t > topic.size()) return false;
        const std::string_view tl(topic.data() + t, (te == std::string::npos ? topic.size() : te) - t);
        if (fl != "+" && fl != tl) return false;
        const bool fEnd = fe == std::string::npos, tEnd = te == std::string::npos;
        if (fEnd && tEnd) return true;
        if (tEnd) {
            // "a/#" matches "a" too (the parent level).
            return filter.compare(fe + 1, std::string::npos, "#") == 0;
        }
        if (fEnd) return false;
        f = fe + 1;
        t = te + 1;
    }
}

namespace {

using armadillo::core::JsonValue;

class Reader {
public:
    explicit Reader(std::string source) : source_(std::move(source)) {}

    [[noreturn]] void fail(const core::JsonValue& at, const std::string& key, const std::string& why) const
    {
        throw core::InputError(source_, at.line, "", "column " + std::to_string(at.column) + ": " + key + ": " + why);
    }
    const core::JsonValue& expect(const core::JsonValue& v, core::JsonValue::Kind kind, const std::string& key) const
    {
        if (v.kind != kind) fail(v, key, std::string("expected ") + core::JsonValue::kindName(kind) + ", found " + core::JsonValue::kindName(v.kind));
        return v;
    }
    std::string text(const core::JsonValue& v, const std::string& key) const { return expect(v, core::JsonValue::Kind::String, key).string; }
    double number(const core::JsonValue& v, const std::string& key, double lo, double hi) const
    {
        const double x = expect(v, core::JsonValue::Kind::Number, key).number;
        if (!std::isfinite(x) || x < lo || x > hi) fail(v, key, "must be from " + fmt(lo) + " to " + fmt(hi));
        return x;
    }
    int integer(const core::JsonValue& v, const std::string& key, int lo, int hi) const
    {
        const double x = number(v, key, lo, hi);
        if (x != std::floor(x)) fail(v, key, "must be a whole number");
        return static_cast<int>(x);
    }
    bool boolean(const core::JsonValue& v, const std::string& key) const { return expect(v, core::JsonValue::Kind::Bool, key).boolean; }
    void unknown(const core::JsonValue& v, const std::string& key, const char* known) const
    {
        fail(v, key, std::string("unknown key (known: ") + known + ")");
    }
    static std::string fmt(double x)
    {
        std::ostringstream o;
        o << x;
        return o.str();
    }

private:
    std::string source_;
};

void readTopic(const Reader& r, const core::JsonValue& v, const std::string& key, MqttConfig& c)
{
    TopicSubscription t;
    if (v.kind == core::JsonValue::Kind::String) {
        t.filter = v.string;
    } else {
        r.expect(v, core::JsonValue::Kind::Object, key);
        for (const auto& [k, x] : v.object) {
            if (k == "topic") t.filter = r.text(x, key + ".topic");
            else if (k == "qos") t.qos = r.integer(x, key + ".qos", 0, 2);
            else if (k == "urgent") t.urgent = r.boolean(x, key + ".urgent");
            else r.unknown(x, key + "." + k, "topic, qos, urgent");
        }
        if (!v.find("topic")) r.fail(v, key, "a topic object needs \"topic\"");
    }
    if (const std::string why = topicFilterProblem(t.filter); !why.empty()) r.fail(v, key, "'" + t.filter + "': " + why);
    c.topics.push_back(std::move(t));
}

} // namespace

MqttConfig parseMqttConfig(const std::string& text, const std::string& source)
{
    const core::JsonValue root = armadillo::core::parseJson(text, source);
    const Reader r(source);
    r.expect(root, core::JsonValue::Kind::Object, "the file");
    MqttConfig c;
    c.source = source;
    for (const auto& [key, v] : root.object) {
        if (key == "broker") {
            try {
                parseBrokerAddress(r.text(v, key), key, c.host, c.port);
            } catch (const core::InputError& e) {
                r.fail(v, key, e.what());
            }
        } else if (key == "clientId") {
            c.clientId = r.text(v, key);
            if (c.clientId.size() > 65535) r.fail(v, key, "longer than 65535 bytes");
        } else if (key == "username") {
            c.username = r.text(v, key);
        } else if (key == "password") {
            c.password = r.text(v, key);
        } else if (key == "protocol") {
            const std::string p = r.text(v, key);
            if (p == "3.1.1") c.protocol = 4;
            else if (p == "5") c.protocol = 5;
            else r.fail(v, key, "'" + p + "': \"3.1.1\" or \"5\"");
        } else if (key == "keepAlive") {
            c.keepAlive = r.integer(v, key, 5, 65535);
        } else if (key == "reconnect") {
            r.expect(v, core::JsonValue::Kind::Object, key);
            for (const auto& [k, x] : v.object) {
                if (k == "min") c.reconnectMin = r.number(x, "reconnect.min", 0.01, 3600);
                else if (k == "max") c.reconnectMax = r.number(x, "reconnect.max", 0.01, 3600);
                else r.unknown(x, "reconnect." + k, "min, max");
            }
            if (c.reconnectMax < c.reconnectMin) r.fail(v, key, "max is below min");
        } else if (key == "tls") {
            r.expect(v, core::JsonValue::Kind::Object, key);
            for (const auto& [k, x] : v.object) {
                if (k == "caFile") c.caFile = r.text(x, "tls.caFile");
                else if (k == "certFile") c.certFile = r.text(x, "tls.certFile");
                else if (k == "keyFile") c.keyFile = r.text(x, "tls.keyFile");
                else r.unknown(x, "tls." + k, "caFile, certFile, keyFile");
            }
            if (c.caFile.empty()) r.fail(v, key, "TLS needs \"caFile\" (the CA certificate that signed the broker's)");
            if (c.certFile.empty() != c.keyFile.empty()) r.fail(v, key, "certFile and keyFile go together");
        } else if (key == "messages") {
            r.expect(v, core::JsonValue::Kind::Object, key);
            for (const auto& [k, x] : v.object) {
                if (k == "topics") {
                    r.expect(x, core::JsonValue::Kind::Array, "messages.topics");
                    for (std::size_t i = 0; i < x.array.size(); ++i)
                        readTopic(r, x.array[i], "messages.topics[" + std::to_string(i) + "]", c);
                } else if (k == "textField") {
                    c.textField = r.text(x, "messages.textField");
                    if (c.textField.empty()) r.fail(x, "messages.textField", "empty (leave it out to read the whole payload)");
                } else if (k == "priorityField") {
                    c.priorityField = r.text(x, "messages.priorityField");
                } else if (k == "queue") {
                    c.queueCapacity = static_cast<std::size_t>(r.integer(x, "messages.queue", 1, 1000));
                } else if (k == "maxTextBytes") {
                    c.maxTextBytes = static_cast<std::size_t>(r.integer(x, "messages.maxTextBytes", 1, 100000));
                } else {
                    r.unknown(x, "messages." + k, "topics, textField, priorityField, queue, maxTextBytes");
                }
            }
        } else if (key == "publish") {
            r.expect(v, core::JsonValue::Kind::Object, key);
            for (const auto& [k, x] : v.object) {
                if (k == "rate") c.publishRate = r.number(x, "publish.rate", 0, 1000);
                else r.unknown(x, "publish." + k, "rate");
            }
        } else {
            r.unknown(v, key, "broker, clientId, username, password, protocol, keepAlive, reconnect, tls, messages, publish");
        }
    }
    validateMqttConfig(c);
    return c;
}

MqttConfig loadMqttConfig(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw core::InputError(path, 0, "", "cannot open the MQTT configuration file");
    std::ostringstream text;
    text << in.rdbuf();
    return parseMqttConfig(text.str(), path);
}

void validateMqttConfig(const MqttConfig& c)
{
    const std::string& src = c.source;
    if (c.host.empty()) throw core::InputError(src, 0, "broker", "no broker host");
    if (c.port < 1 || c.port > 65535) throw core::InputError(src, 0, "broker", "port " + std::to_string(c.port) + " is not from 1 to 65535");
    for (const std::string* f : {&c.caFile, &c.certFile, &c.keyFile})
        if (!f->empty() && ::access(f->c_str(), R_OK) != 0)
            throw core::InputError(src, 0, "tls", "cannot read '" + *f + "' (TLS files must exist and be readable)");
    if (!c.password.empty() && c.username.empty()) throw core::InputError(src, 0, "password", "a password needs a username");
    for (const auto& t : c.topics)
        if (const std::string why = topicFilterProblem(t.filter); !why.empty())
            throw core::InputError(src, 0, "messages.topics", "'" + t.filter + "': " + why);
}

} // namespace armadillo::mqtt
