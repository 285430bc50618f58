#pragma once
// Option parsing and error reporting shared by every `armadillo` subcommand, so that all of them
// answer --help, refuse bad usage with exit 2, bad input with 3 and I/O failure with 4.
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::cli {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct OptionSpec {
    std::string name;        ///< "--in"
    std::string valueName;   ///< "FILE"; empty = a flag without value
    std::string help;
    bool required = false;
};

class CommandLine {
public:
    CommandLine(std::string command, std::string synopsis, std::string description, std::vector<OptionSpec> options);

    /// Parses args (after the subcommand name). Returns false when --help was asked (and printed).
    /// Throws UsageError for unknown options, missing values or missing required options.
    bool parse(const std::vector<std::string>& args);

    bool has(std::string_view name) const;
    std::string value(std::string_view name, const std::string& fallback = "") const;
    /// Every value of an option that may be given more than once, in order.
    std::vector<std::string> values(std::string_view name) const;
    double number(std::string_view name, double fallback) const;               ///< UsageError if not a number
    long integer(std::string_view name, long fallback, long min, long max) const;
    std::string helpText() const;

private:
    const OptionSpec* find(std::string_view name) const;
    std::string command_, synopsis_, description_;
    std::vector<OptionSpec> options_;
    std::vector<std::pair<std::string, std::string>> values_;
};

/// Refuses an output file that cannot be written, before any work starts: IoError (exit 4) naming
/// the option and the path when its folder does not exist or is not writable, or when the path
/// is a folder; UsageError for an empty path.
void checkOutputPath(const std::string& option, const std::string& path);
/// Refuses (UsageError) two outputs given the same file: {option, path} pairs, empty paths skipped.
void checkDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& outputs);

/// Runs a subcommand body, mapping exceptions to exit codes and messages on stderr:
/// UsageError → 2, InputError → 3, IoError → 4, anything else → 1.
int guarded(const std::string& command, const std::function<int()>& body);

/// Set by SIGINT/SIGTERM once installInterruptHandlers() ran; long-running commands poll it.
bool interrupted() noexcept;
void installInterruptHandlers();

} // namespace armadillo::cli
