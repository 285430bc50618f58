#pragma once
// One fuzz target = one file fuzz_<name>.cpp with one ARMADILLO_FUZZ_TARGET(name) { … } body that
// feeds bytes to a parser's entry point (docs/SECURITY.md "Fuzzing"). The same body compiles two
// ways:
//  - with ARMADILLO_FUZZ_LIBFUZZER (the clang build of scripts/fuzz.sh): libFuzzer's
//    LLVMFuzzerTestOneInput, one executable per target;
//  - without (the ordinary test build): a function registered by name, which tests_fuzz_regressions
//    runs over every file of Tests/Fuzz/corpus/<name>/ and Tests/Fuzz/regressions/<name>/.
// Bad input is expected to be refused: the project's InputError and IoError and the standard
// exceptions a parser throws are caught here. What counts is what gets through: a crash, a
// sanitizer report, a hang, running out of memory.
#include "Core/Errors.h"
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::fuzz {

using Body = void (*)(const std::uint8_t* data, std::size_t size);

/// Runs `body`, swallowing the exceptions bad input may bring (and only exceptions).
inline void runGuarded(Body body, const std::uint8_t* data, std::size_t size)
{
    try {
        body(data, size);
    } catch (const core::InputError&) {
    } catch (const core::IoError&) {
    } catch (const std::exception&) {
    }
}

struct Target {
    const char* name;
    Body body;
};
/// The ordinary build's table of targets (tests_fuzz_regressions).
std::vector<Target>& registry();
inline bool registerTarget(const char* name, Body body)
{
    registry().push_back({name, body});
    return true;
}

/// The input as text (most parsers take a string_view).
inline std::string_view text(const std::uint8_t* data, std::size_t size)
{
    return {reinterpret_cast<const char*>(data), size};
}

/// Reads input bytes one field at a time (a byte that picks an option, then the rest).
class Bytes {
public:
    Bytes(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
    std::uint8_t byte() noexcept
    {
        if (n_ == 0) return 0;
        --n_;
        return *p_++;
    }
    const std::uint8_t* data() const noexcept { return p_; }
    std::size_t size() const noexcept { return n_; }
    std::string_view rest() const noexcept { return {reinterpret_cast<const char*>(p_), n_}; }

private:
    const std::uint8_t* p_;
    std::size_t n_;
};

/// Writes `data` to a file of this process's own (for parsers that only read paths) and returns
/// its path; the file is replaced on every call.
std::string scratchFile(const char* target, const char* extension, const std::uint8_t* data, std::size_t size);

} // namespace armadillo::fuzz

#ifdef ARMADILLO_FUZZ_LIBFUZZER
#define ARMADILLO_FUZZ_TARGET(name)                                                                \
    static void armadilloFuzzBody(const std::uint8_t* data, std::size_t size);                     \
    extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)              \
    {                                                                                              \
        armadillo::fuzz::runGuarded(armadilloFuzzBody, data, size);                                \
        return 0;                                                                                  \
    }                                                                                              \
    static void armadilloFuzzBody(const std::uint8_t* data, std::size_t size)
#else
#define ARMADILLO_FUZZ_TARGET(name)                                                                \
    static void armadilloFuzzBody_##name(const std::uint8_t* data, std::size_t size);              \
    [[maybe_unused]] static const bool armadilloFuzzRegistered_##name =                            \
        armadillo::fuzz::registerTarget(#name, armadilloFuzzBody_##name);                          \
    static void armadilloFuzzBody_##name(const std::uint8_t* data, std::size_t size)
#endif
