#include "Cli/CommandLine.h"
#include "Core/Errors.h"
#include "Core/Types.h"
#include <atomic>
#include <charconv>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <unistd.h>
#include <iostream>

namespace armadillo::cli {

CommandLine::CommandLine(std::string command, std::string synopsis, std::string description, std::vector<OptionSpec> options)
    : command_(std::move(command)), synopsis_(std::move(synopsis)), description_(std::move(description)),
      options_(std::move(options))
{
}

const OptionSpec* CommandLine::find(std::string_view name) const
{
    for (const auto& o : options_)
        if (o.name == name) return &o;
    return nullptr;
}

bool CommandLine::parse(const std::vector<std::string>& args)
{
    for (std::size_t i = 0; i < args.size(); ++i) {
        std::string arg = args[i];
        if (arg == "--help" || arg == "-h") {
            std::cout << helpText();
            return false;
        }
        std::string inlineValue;
        bool hasInline = false;
        if (const auto eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
            inlineValue = arg.substr(eq + 1);
            arg = arg.substr(0, eq);
            hasInline = true;
        }
        const OptionSpec* spec = find(arg);
        if (!spec) throw UsageError("unknown " + std::string(arg.rfind("-", 0) == 0 ? "option" : "argument") + " '" + arg + "'");
        if (spec->valueName.empty()) {
            if (hasInline) throw UsageError(arg + " takes no value");
            values_.emplace_back(arg, "");
            continue;
        }
        if (!hasInline) {
            if (i + 1 >= args.size()) throw UsageError(arg + " needs a value (" + spec->valueName + ")");
            inlineValue = args[++i];
        }
        values_.emplace_back(arg, inlineValue);
    }
    for (const auto& o : options_)
        if (o.required && !has(o.name)) throw UsageError("missing required option " + o.name + " " + o.valueName);
    return true;
}

bool CommandLine::has(std::string_view name) const
{
    for (const auto& [k, v] : values_)
        if (k == name) return true;
    return false;
}

std::string CommandLine::value(std::string_view name, const std::string& fallback) const
{
    for (auto it = values_.rbegin(); it != values_.rend(); ++it)
        if (it->first == name) return it->second;
    return fallback;
}

std::vector<std::string> CommandLine::values(std::string_view name) const
{
    std::vector<std::string> out;
    for (const auto& [k, v] : values_)
        if (k == name) out.push_back(v);
    return out;
}

double CommandLine::number(std::string_view name, double fallback) const
{
    if (!has(name)) return fallback;
    const std::string s = value(name);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
        throw UsageError(std::string(name) + " expects a number, not '" + s + "'");
    return v;
}

long CommandLine::integer(std::string_view name, long fallback, long min, long max) const
{
    if (!has(name)) return fallback;
    const std::string s = value(name);
    long v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size())
        throw UsageError(std::string(name) + " expects a whole number, not '" + s + "'");
    if (v < min || v > max)
        throw UsageError(std::string(name) + " must lie in " + std::to_string(min) + ".." + std::to_string(max));
    return v;
}

std::string CommandLine::helpText() const
{
    std::string s = "usage: armadillo " + command_ + " " + synopsis_ + "\n\n" + description_ + "\n\noptions:\n";
    for (const auto& o : options_) {
        std::string left = "  " + o.name + (o.valueName.empty() ? "" : " " + o.valueName);
        if (left.size() < 26) left.resize(26, ' ');
        else left += "\n" + std::string(26, ' ');
        std::string help = o.help;   // continuation lines line up under the first
        for (std::size_t at = help.find('\n'); at != std::string::npos; at = help.find('\n', at + 27))
            help.insert(at + 1, std::string(26, ' '));
        s += left + help + (o.required ? " (required)" : "") + "\n";
    }
    s += "  --help                  this text\n";
    return s;
}

void checkOutputPath(const std::string& option, const std::string& path)
{
    namespace fs = std::filesystem;
    if (path.empty()) throw UsageError(option + " needs a file name");
    std::error_code ec;
    const fs::path target = fs::absolute(path, ec);
    if (ec) throw core::IoError(option + ": cannot write '" + path + "': " + ec.message());
    if (fs::is_directory(target, ec)) throw core::IoError(option + ": cannot write '" + path + "': it is a folder");
    const fs::path dir = target.parent_path();
    if (!fs::is_directory(dir, ec))
        throw core::IoError(option + ": cannot write '" + path + "': the folder '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
        throw core::IoError(option + ": cannot write '" + path + "': no permission to write into '" + dir.string() + "'");
}

void checkDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& outputs)
{
    namespace fs = std::filesystem;
    for (std::size_t i = 0; i < outputs.size(); ++i)
        for (std::size_t j = i + 1; j < outputs.size(); ++j) {
            if (outputs[i].second.empty() || outputs[j].second.empty()) continue;
            std::error_code a, b;
            const fs::path p = fs::weakly_canonical(outputs[i].second, a), q = fs::weakly_canonical(outputs[j].second, b);
            if (!a && !b && p == q)
                throw UsageError(outputs[i].first + " and " + outputs[j].first + " name the same file '" + outputs[i].second + "'");
        }
}

int guarded(const std::string& command, const std::function<int()>& body)
{
    try {
        return body();
    } catch (const UsageError& e) {
        std::cerr << "armadillo " << command << ": " << e.what() << "\n(see 'armadillo " << command << " --help')\n";
        return core::kExitUsage;
    } catch (const core::InputError& e) {
        std::cerr << "armadillo " << command << ": bad input: " << e.what() << "\n";
        return core::kExitBadInput;
    } catch (const core::IoError& e) {
        std::cerr << "armadillo " << command << ": " << e.what() << "\n";
        return core::kExitIo;
    } catch (const std::exception& e) {
        std::cerr << "armadillo " << command << ": error: " << e.what() << "\n";
        return core::kExitFailure;
    }
}

namespace {
std::atomic<bool> gInterrupted {false};
extern "C" void onSignal(int) { gInterrupted.store(true); }
} // namespace

bool interrupted() noexcept { return gInterrupted.load(); }

void installInterruptHandlers()
{
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}

} // namespace armadillo::cli
