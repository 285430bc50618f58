#pragma once
// ZIG SIM's TCP option writes each tick's payload straight onto the connection, without any
// framing (ZIGSIMPlus NetworkAdapter.swift sendTCP: conn.send(content: data), the data of
// ServiceManager.getData: one JSON object, or one OSC bundle). OscStreamSplitter cuts such a
// byte stream back into those units: JSON objects by their balanced braces (strings and escapes
// respected), OSC bundles by walking their size-prefixed elements up to the next "#bundle" or the
// end of what has arrived (the app writes whole bundles). Bytes that are neither are handed on as
// one unit (the merger counts and lists them). Reserved buffers: no heap after construction.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace armadillo::osc {

class OscStreamSplitter {
public:
    using Sink = void (*)(void* context, const std::uint8_t* unit, std::size_t size);
    explicit OscStreamSplitter(std::size_t capacity = 1 << 18);
    /// Appends bytes and hands every complete unit to sink. A stream that grows past the capacity
    /// without a complete unit is dropped (counted) and the splitter starts afresh.
    void feed(const std::uint8_t* data, std::size_t size, Sink sink, void* context);
    void reset() noexcept;
    std::uint64_t overflows() const noexcept { return overflows_; }
    std::size_t pending() const noexcept { return size_; }

private:
    std::size_t jsonEnd() const noexcept;     // bytes of the leading JSON object, 0 when incomplete
    std::size_t bundleEnd(std::size_t from, bool& complete) const noexcept;
    void consume(std::size_t n) noexcept;
    std::vector<std::uint8_t> buf_, scratch_;
    std::size_t size_ = 0;
    std::uint8_t header_[16] {};   // the latest bundle's "#bundle" and time tag: elements that follow it belong to it
    bool haveHeader_ = false;
    std::uint64_t overflows_ = 0;
};

} // namespace armadillo::osc
