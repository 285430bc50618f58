#include "Mqtt/MessageInbox.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Mqtt/MqttClient.h"
#include <cmath>

namespace armadillo::mqtt {

namespace {

/// Length of the UTF-8 sequence at s[i] (RFC 3629: no overlongs, no surrogates, ≤ U+10FFFF), 0 if invalid.
std::size_t utf8Length(const std::string& s, std::size_t i)
{
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    if (c < 0x80) return 1;
    std::size_t n = 0;
    unsigned cp = 0;
    if (c >= 0xC2 && c <= 0xDF) n = 2, cp = c & 0x1Fu;
    else if (c >= 0xE0 && c <= 0xEF) n = 3, cp = c & 0x0Fu;
    else if (c >= 0xF0 && c <= 0xF4) n = 4, cp = c & 0x07u;
    else return 0;
    if (i + n > s.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((b(i + k) & 0xC0u) != 0x80u) return 0;
        cp = (cp << 6) | (b(i + k) & 0x3Fu);
    }
    if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return n;
}

/// Checks UTF-8, turns line breaks and tabs into spaces, collapses runs of spaces, trims.
bool cleanText(const std::string& in, std::string& out, std::string& why)
{
    out.clear();
    out.reserve(in.size());
    for (std::size_t i = 0; i < in.size();) {
        const std::size_t n = utf8Length(in, i);
        if (n == 0) {
            why = "invalid UTF-8 at byte " + std::to_string(i + 1);
            return false;
        }
        const unsigned char c = static_cast<unsigned char>(in[i]);
        if (n == 1 && (c < 0x20 || c == 0x7F)) {
            if (c != '\n' && c != '\r' && c != '\t') {
                why = "control character " + std::to_string(c) + " at byte " + std::to_string(i + 1);
                return false;
            }
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else if (n == 1 && c == ' ') {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out.append(in, i, n);
        }
        i += n;
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    if (out.empty()) {
        why = "no text (empty or only spaces)";
        return false;
    }
    return true;
}

const armadillo::core::JsonValue* findPath(const armadillo::core::JsonValue& root, const std::string& path)
{
    const armadillo::core::JsonValue* v = &root;
    std::size_t start = 0;
    while (v) {
        const std::size_t dot = path.find('.', start);
        if (v->kind != armadillo::core::JsonValue::Kind::Object) return nullptr;
        v = v->find(std::string_view(path).substr(start, dot == std::string::npos ? std::string::npos : dot - start));
        if (dot == std::string::npos) return v;
        start = dot + 1;
    }
    return nullptr;
}

} // namespace

bool messageText(const std::string& payload, const MqttConfig& config, std::string& text, int& priority, std::string& why)
{
    priority = 0;
    if (config.textField.empty() && config.priorityField.empty()) return cleanText(payload, text, why);
    armadillo::core::JsonValue root;
    try {
        root = armadillo::core::parseJson(payload, "payload");
    } catch (const core::InputError& e) {
        why = std::string("not JSON (") + e.what() + ")";
        return false;
    }
    if (!config.priorityField.empty()) {
        if (const armadillo::core::JsonValue* p = findPath(root, config.priorityField)) {
            if (p->kind != armadillo::core::JsonValue::Kind::Number || !std::isfinite(p->number)) {
                why = "field \"" + config.priorityField + "\" is not a number";
                return false;
            }
            priority = p->number >= 1.0 ? 1 : 0;
        }
    }
    if (config.textField.empty()) return cleanText(payload, text, why);
    const armadillo::core::JsonValue* field = findPath(root, config.textField);
    if (!field) {
        why = "no field \"" + config.textField + "\" in the JSON payload";
        return false;
    }
    if (field->kind != armadillo::core::JsonValue::Kind::String) {
        why = "field \"" + config.textField + "\" is " + armadillo::core::JsonValue::kindName(field->kind) + ", not a string";
        return false;
    }
    return cleanText(field->string, text, why);
}

MessageInbox::MessageInbox(const MqttConfig& config) : config_(config) { stats_.capacity = config.queueCapacity; }

void MessageInbox::refuse(const std::string& source, const std::string& why)
{
    ++stats_.refused;
    stats_.lastRefusal = "message on '" + source + "' refused: " + why;
}

bool MessageInbox::offer(const ReceivedMessage& message)
{
    bool urgent = false;
    for (const auto& t : config_.topics)
        if (t.urgent && topicMatches(t.filter, message.topic)) urgent = true;
    std::string text, why;
    int priority = 0;
    // Too long is judged on the payload first so a 1 MB payload is not parsed at all.
    if (message.payload.size() > std::max<std::size_t>(config_.maxTextBytes * 4, 4096)) {
        std::lock_guard lock(mutex_);
        ++stats_.offered;
        refuse(message.topic, std::to_string(message.payload.size()) + " bytes, longer than a message can be (" +
                                  std::to_string(config_.maxTextBytes) + " bytes of text, messages.maxTextBytes)");
        return false;
    }
    const bool ok = messageText(message.payload, config_, text, priority, why);
    std::lock_guard lock(mutex_);
    ++stats_.offered;
    if (!ok) {
        refuse(message.topic, why);
        return false;
    }
    return queue(std::move(text), message.topic, urgent || priority >= 1);
}

bool MessageInbox::offerText(const std::string& raw, const std::string& source, int priority)
{
    std::string text, why;
    const bool ok = cleanText(raw, text, why);
    std::lock_guard lock(mutex_);
    ++stats_.offered;
    if (!ok) {
        refuse(source, why);
        return false;
    }
    return queue(std::move(text), source, priority >= 1);
}

bool MessageInbox::queue(std::string text, const std::string& source, bool urgent)
{
    if (text.size() > config_.maxTextBytes) {
        refuse(source, std::to_string(text.size()) + " bytes of text, more than messages.maxTextBytes (" + std::to_string(config_.maxTextBytes) + ")");
        return false;
    }
    InboxMessage m {nextId_++, std::move(text), source, urgent};
    if (waiting_.size() >= config_.queueCapacity) {
        waiting_.pop_front();
        ++stats_.droppedOldest;
    }
    waiting_.push_back(m);
    recent_.push_back(std::move(m));
    if (recent_.size() > 50) recent_.pop_front();
    ++stats_.accepted;
    return true;
}

bool MessageInbox::pop(InboxMessage& out)
{
    std::lock_guard lock(mutex_);
    if (waiting_.empty()) return false;
    auto it = waiting_.begin();
    for (auto u = waiting_.begin(); u != waiting_.end(); ++u)
        if (u->urgent) {
            it = u;
            break;
        }
    out = std::move(*it);
    waiting_.erase(it);
    ++stats_.taken;
    return true;
}

bool MessageInbox::urgentWaiting() const
{
    std::lock_guard lock(mutex_);
    for (const auto& m : waiting_)
        if (m.urgent) return true;
    return false;
}

InboxStats MessageInbox::stats() const
{
    std::lock_guard lock(mutex_);
    InboxStats s = stats_;
    s.waiting = waiting_.size();
    return s;
}

std::vector<InboxMessage> MessageInbox::recent(std::size_t count) const
{
    std::lock_guard lock(mutex_);
    const std::size_t n = std::min(count, recent_.size());
    return {recent_.end() - static_cast<std::ptrdiff_t>(n), recent_.end()};
}

} // namespace armadillo::mqtt
