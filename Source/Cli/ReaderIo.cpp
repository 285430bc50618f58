#include "Cli/ReaderIo.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <iostream>
#include <poll.h>
#include <unistd.h>

namespace armadillo::cli {

std::vector<OptionSpec> readerIoOptionSpecs() { return {}; }

ReaderIo::ReaderIo(const CommandLine&) {}

void ReaderIo::status(const std::string& text) { std::cerr << text << "\n" << std::flush; }

void ReaderIo::note(const std::string& text) { std::cerr << "  " << text << "\n" << std::flush; }

std::string ReaderIo::readLine()
{
    for (;;) {
        if (const auto nl = pending_.find('\n'); nl != std::string::npos) {
            std::string line = pending_.substr(0, nl);
            pending_.erase(0, nl + 1);
            const auto b = line.find_first_not_of(" \t\r");
            if (b == std::string::npos) return "";
            return line.substr(b, line.find_last_not_of(" \t\r") - b + 1);
        }
        if (closed_) {
            if (!pending_.empty()) {   // a last line without a newline still counts
                pending_ += '\n';
                continue;
            }
            throw InputError("stdin", 0, "", "the answers ended before the procedure was complete; nothing written");
        }
        if (interrupted()) throw IoError("interrupted; nothing written");
        pollfd p {STDIN_FILENO, POLLIN, 0};
        if (::poll(&p, 1, 100) <= 0) continue;
        char buf[512];
        const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
        if (n > 0) pending_.append(buf, static_cast<std::size_t>(n));
        else if (n == 0 || (errno != EINTR && errno != EAGAIN)) closed_ = true;
    }
}

std::string ReaderIo::askYesNo(const std::string& question)
{
    std::cerr << "? " << question << "\n" << std::flush;
    std::string a = readLine();
    std::transform(a.begin(), a.end(), a.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (a == "y" || a == "yes") return "y";
    if (a == "n" || a == "no") return "n";
    if (a == "r" || a == "repeat") return "r";
    note("answer y (felt) or n (not felt); r shows it again");
    return "";
}

std::string ReaderIo::askLine(const std::string& prompt)
{
    std::cerr << "? " << prompt << "\n" << std::flush;
    return readLine();
}

} // namespace armadillo::cli
