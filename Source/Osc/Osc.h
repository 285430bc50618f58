#pragma once
// A small OSC 1.0 codec (opensoundcontrol.org spec 1.0): messages and bundles, argument types
// i f s b (the 1.0 core) plus h d t S c T F N I. Encoding writes into a caller's buffer (no
// allocation: usable on the control thread). Decoding never trusts sizes, refuses anything
// malformed with a reason, and limits bundle nesting. Fuzz-tested.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::osc {

struct OscArg {
    char type = 'f';
    std::int32_t i = 0;         ///< i, c (as code point)
    float f = 0.0f;             ///< f
    double d = 0.0;             ///< d
    std::int64_t h = 0;         ///< h, t (time tag bits)
    std::string_view bytes;     ///< s, S (without terminator), b (blob data)

    static OscArg int32(std::int32_t v) { OscArg a; a.type = 'i'; a.i = v; return a; }
    static OscArg float32(float v) { OscArg a; a.type = 'f'; a.f = v; return a; }
    static OscArg float64(double v) { OscArg a; a.type = 'd'; a.d = v; return a; }
    static OscArg string(std::string_view v) { OscArg a; a.type = 's'; a.bytes = v; return a; }
    static OscArg blob(std::string_view v) { OscArg a; a.type = 'b'; a.bytes = v; return a; }
    /// Numeric value of i f d h (and T=1, F=0); false for other types.
    bool asNumber(double& out) const noexcept;
};

inline constexpr int kOscMaxArgs = 64;
inline constexpr int kOscMaxBundleDepth = 8;

struct OscMessage {
    std::string_view address;   ///< starts with '/'
    std::string_view types;     ///< type tags without the leading ','
    OscArg args[kOscMaxArgs];
    int count = 0;
    std::uint64_t timeTag = 1;  ///< the innermost enclosing bundle's time tag; 1 = "immediately" (also for bare messages)
};

/// Seconds since 1900 (NTP epoch) of an OSC time tag (32.32 fixed point).
inline double oscTimeTagSeconds(std::uint64_t tag) noexcept
{
    return static_cast<double>(tag >> 32) + static_cast<double>(tag & 0xFFFFFFFFu) / 4294967296.0;
}

/// The allocation-free form of the decoder's callback (a std::function may allocate).
using OscMessageSink = void (*)(void* context, const OscMessage& message);

/// Encodes one message into out; returns its size, or 0 when it does not fit or an argument is
/// invalid (address without '/', string with a NUL, unknown type).
std::size_t encodeOscMessage(std::string_view address, const OscArg* args, std::size_t count,
                             std::uint8_t* out, std::size_t capacity) noexcept;
std::vector<std::uint8_t> encodeOscMessage(std::string_view address, const std::vector<OscArg>& args);
/// A bundle of already-encoded elements (messages or bundles) with a 64-bit time tag (1 = now).
std::vector<std::uint8_t> encodeOscBundle(std::uint64_t timeTag, const std::vector<std::vector<std::uint8_t>>& elements);

/// Decodes a packet (message or bundle), calling onMessage for every message in order. Returns
/// false with a reason for malformed input; messages decoded before the fault have been delivered.
bool decodeOscPacket(const std::uint8_t* data, std::size_t size, const std::function<void(const OscMessage&)>& onMessage,
                     std::string* error = nullptr);
/// The same without allocation: the reason is a static string (nullptr when none).
bool decodeOscPacket(const std::uint8_t* data, std::size_t size, OscMessageSink sink, void* context, const char** error) noexcept;

} // namespace armadillo::osc
