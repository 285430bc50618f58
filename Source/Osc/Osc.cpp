#include "Osc/Osc.h"
#include <cstring>

namespace armadillo::osc {

bool OscArg::asNumber(double& out) const noexcept
{
    switch (type) {
    case 'i': out = i; return true;
    case 'f': out = static_cast<double>(f); return true;
    case 'd': out = d; return true;
    case 'h': out = static_cast<double>(h); return true;
    case 'T': out = 1.0; return true;
    case 'F': out = 0.0; return true;
    default: return false;
    }
}

namespace {

constexpr std::size_t pad4(std::size_t n) noexcept { return (n + 3) & ~std::size_t(3); }

class Writer {
public:
    Writer(std::uint8_t* out, std::size_t capacity) : out_(out), cap_(capacity) {}
    bool ok() const noexcept { return ok_; }
    std::size_t size() const noexcept { return size_; }
    void raw(const void* p, std::size_t n) noexcept
    {
        if (!ok_ || n > cap_ - size_) {
            ok_ = false;
            return;
        }
        std::memcpy(out_ + size_, p, n);
        size_ += n;
    }
    void zeros(std::size_t n) noexcept
    {
        static const std::uint8_t z[4] {};
        raw(z, n);
    }
    void paddedString(std::string_view s) noexcept   // s + NUL, padded to 4
    {
        raw(s.data(), s.size());
        zeros(pad4(s.size() + 1) - s.size());
    }
    void u32(std::uint32_t v) noexcept
    {
        const std::uint8_t b[4] {std::uint8_t(v >> 24), std::uint8_t(v >> 16), std::uint8_t(v >> 8), std::uint8_t(v)};
        raw(b, 4);
    }
    void u64(std::uint64_t v) noexcept
    {
        u32(static_cast<std::uint32_t>(v >> 32));
        u32(static_cast<std::uint32_t>(v));
    }

private:
    std::uint8_t* out_;
    std::size_t cap_;
    std::size_t size_ = 0;
    bool ok_ = true;
};

std::uint32_t readU32(const std::uint8_t* p) noexcept
{
    return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | std::uint32_t(p[3]);
}
std::uint64_t readU64(const std::uint8_t* p) noexcept { return (std::uint64_t(readU32(p)) << 32) | readU32(p + 4); }

/// An OSC-string at p (NUL-terminated, padded to 4) within [p, end); returns its padded length or 0.
std::size_t readString(const std::uint8_t* p, const std::uint8_t* end, std::string_view& out) noexcept
{
    const std::size_t avail = static_cast<std::size_t>(end - p);
    const void* nul = std::memchr(p, 0, avail);
    if (!nul) return 0;
    const std::size_t len = static_cast<std::size_t>(static_cast<const std::uint8_t*>(nul) - p);
    const std::size_t padded = pad4(len + 1);
    if (padded > avail) return 0;
    for (std::size_t i = len; i < padded; ++i)
        if (p[i] != 0) return 0;
    out = std::string_view(reinterpret_cast<const char*>(p), len);
    return padded;
}

bool fail(const char** error, const char* why) noexcept
{
    if (error) *error = why;
    return false;
}

bool decodeMessage(const std::uint8_t* data, std::size_t size, OscMessageSink onMessage, void* context, const char** error,
                   std::uint64_t timeTag) noexcept
{
    const std::uint8_t* p = data;
    const std::uint8_t* end = data + size;
    OscMessage m;
    m.timeTag = timeTag;
    std::size_t n = readString(p, end, m.address);
    if (n == 0) return fail(error, "address is not a padded, NUL-terminated string");
    if (m.address.empty() || m.address[0] != '/') return fail(error, "address does not start with '/'");
    p += n;
    if (p == end) {   // no type tag string (pre-1.0 senders): no arguments
        onMessage(context, m);
        return true;
    }
    std::string_view tags;
    n = readString(p, end, tags);
    if (n == 0 || tags.empty() || tags[0] != ',') return fail(error, "type tag string missing or malformed");
    p += n;
    m.types = tags.substr(1);
    for (const char t : m.types) {
        if (t == '[' || t == ']') continue;   // arrays: their elements are decoded as plain arguments
        if (m.count >= kOscMaxArgs) return fail(error, "too many arguments");
        OscArg& a = m.args[m.count];
        a.type = t;
        const std::size_t left = static_cast<std::size_t>(end - p);
        switch (t) {
        case 'i':
        case 'c':
        case 'r':
        case 'm':
            if (left < 4) return fail(error, "truncated 32-bit argument");
            a.i = static_cast<std::int32_t>(readU32(p));
            p += 4;
            break;
        case 'f': {
            if (left < 4) return fail(error, "truncated float argument");
            const std::uint32_t bits = readU32(p);
            std::memcpy(&a.f, &bits, 4);
            p += 4;
            break;
        }
        case 'h':
        case 't':
            if (left < 8) return fail(error, "truncated 64-bit argument");
            a.h = static_cast<std::int64_t>(readU64(p));
            p += 8;
            break;
        case 'd': {
            if (left < 8) return fail(error, "truncated double argument");
            const std::uint64_t bits = readU64(p);
            std::memcpy(&a.d, &bits, 8);
            p += 8;
            break;
        }
        case 's':
        case 'S':
            n = readString(p, end, a.bytes);
            if (n == 0) return fail(error, "string argument is not padded and NUL-terminated");
            p += n;
            break;
        case 'b': {
            if (left < 4) return fail(error, "truncated blob size");
            const std::uint32_t len = readU32(p);
            if (len > left - 4 || pad4(len) > left - 4) return fail(error, "blob larger than the packet");
            a.bytes = std::string_view(reinterpret_cast<const char*>(p + 4), len);
            p += 4 + pad4(len);
            break;
        }
        case 'T':
        case 'F':
        case 'N':
        case 'I': break;
        default: return fail(error, "unknown argument type tag");
        }
        ++m.count;
    }
    if (p != end) return fail(error, "bytes left over after the arguments");
    onMessage(context, m);
    return true;
}

bool decodeAny(const std::uint8_t* data, std::size_t size, OscMessageSink onMessage, void* context, const char** error, int depth,
               std::uint64_t timeTag) noexcept
{
    if (size == 0) return fail(error, "empty packet");
    if (size % 4 != 0) return fail(error, "packet size is not a multiple of 4");
    if (data[0] == '/') return decodeMessage(data, size, onMessage, context, error, timeTag);
    if (data[0] != '#') return fail(error, "neither a message ('/') nor a bundle ('#bundle')");
    if (size < 16 || std::memcmp(data, "#bundle\0", 8) != 0) return fail(error, "malformed bundle header");
    if (depth >= kOscMaxBundleDepth) return fail(error, "bundles nested too deeply");
    const std::uint64_t tag = readU64(data + 8);
    std::size_t pos = 16;   // "#bundle\0" + time tag
    while (pos < size) {
        if (size - pos < 4) return fail(error, "truncated bundle element size");
        const std::uint32_t len = readU32(data + pos);
        pos += 4;
        if (len == 0 || len > size - pos || len % 4 != 0) return fail(error, "bundle element size out of range");
        if (!decodeAny(data + pos, len, onMessage, context, error, depth + 1, tag)) return false;
        pos += len;
    }
    return true;
}

} // namespace

std::size_t encodeOscMessage(std::string_view address, const OscArg* args, std::size_t count, std::uint8_t* out,
                             std::size_t capacity) noexcept
{
    if (address.empty() || address[0] != '/' || address.find('\0') != std::string_view::npos) return 0;
    Writer w(out, capacity);
    w.paddedString(address);
    char tags[kOscMaxArgs + 2];
    if (count > static_cast<std::size_t>(kOscMaxArgs)) return 0;
    tags[0] = ',';
    for (std::size_t i = 0; i < count; ++i) tags[i + 1] = args[i].type;
    w.paddedString(std::string_view(tags, count + 1));
    for (std::size_t i = 0; i < count; ++i) {
        const OscArg& a = args[i];
        switch (a.type) {
        case 'i':
        case 'c':
        case 'r':
        case 'm': w.u32(static_cast<std::uint32_t>(a.i)); break;
        case 'f': {
            std::uint32_t bits;
            std::memcpy(&bits, &a.f, 4);
            w.u32(bits);
            break;
        }
        case 'h':
        case 't': w.u64(static_cast<std::uint64_t>(a.h)); break;
        case 'd': {
            std::uint64_t bits;
            std::memcpy(&bits, &a.d, 8);
            w.u64(bits);
            break;
        }
        case 's':
        case 'S':
            if (a.bytes.find('\0') != std::string_view::npos) return 0;
            w.paddedString(a.bytes);
            break;
        case 'b':
            if (a.bytes.size() > 0x7FFFFFFFu) return 0;
            w.u32(static_cast<std::uint32_t>(a.bytes.size()));
            w.raw(a.bytes.data(), a.bytes.size());
            w.zeros(pad4(a.bytes.size()) - a.bytes.size());
            break;
        case 'T':
        case 'F':
        case 'N':
        case 'I': break;
        default: return 0;
        }
    }
    return w.ok() ? w.size() : 0;
}

std::vector<std::uint8_t> encodeOscMessage(std::string_view address, const std::vector<OscArg>& args)
{
    std::size_t need = pad4(address.size() + 1) + pad4(args.size() + 2);
    for (const auto& a : args) need += 8 + pad4(a.bytes.size() + 1);
    std::vector<std::uint8_t> out(need);
    out.resize(encodeOscMessage(address, args.data(), args.size(), out.data(), out.size()));
    return out;
}

std::vector<std::uint8_t> encodeOscBundle(std::uint64_t timeTag, const std::vector<std::vector<std::uint8_t>>& elements)
{
    std::vector<std::uint8_t> out {'#', 'b', 'u', 'n', 'd', 'l', 'e', 0};
    auto u32 = [&](std::uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
    };
    u32(static_cast<std::uint32_t>(timeTag >> 32));
    u32(static_cast<std::uint32_t>(timeTag));
    for (const auto& e : elements) {
        u32(static_cast<std::uint32_t>(e.size()));
        out.insert(out.end(), e.begin(), e.end());
    }
    return out;
}

bool decodeOscPacket(const std::uint8_t* data, std::size_t size, const std::function<void(const OscMessage&)>& onMessage,
                     std::string* error)
{
    const char* why = nullptr;
    auto sink = [](void* c, const OscMessage& m) { (*static_cast<const std::function<void(const OscMessage&)>*>(c))(m); };
    const bool ok = decodeOscPacket(data, size, sink, const_cast<std::function<void(const OscMessage&)>*>(&onMessage), &why);
    if (!ok && error) *error = why ? why : "malformed packet";
    return ok;
}

bool decodeOscPacket(const std::uint8_t* data, std::size_t size, OscMessageSink sink, void* context, const char** error) noexcept
{
    if (!data) return fail(error, "no data");
    return decodeAny(data, size, sink, context, error, 0, 1);
}

} // namespace armadillo::osc
