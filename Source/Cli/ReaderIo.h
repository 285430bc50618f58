#pragma once
// The reader's side of the guided command-line procedures (touch-profile, braille training):
// prompts, statuses and answers, written on stderr and read from stdin one line at a time, so
// a screen reader, a braille display or a script can follow them. Prompts that want an answer
// start with "? ". Waiting for a line polls stdin, so Ctrl-C (SIGINT) ends the wait.
#include "Cli/CommandLine.h"
#include <string>
#include <vector>

namespace armadillo::cli {

/// Options every reader-facing procedure accepts (none yet beyond the defaults).
std::vector<OptionSpec> readerIoOptionSpecs();

class ReaderIo {
public:
    explicit ReaderIo(const CommandLine& cl);
    /// A state change ("now a comfortable level…"): one line on stderr.
    void status(const std::string& text);
    /// A remark that needs no answer, indented.
    void note(const std::string& text);
    /// Writes "? question" and reads one line: "y" or "n" (also yes/no, any case), "r" (repeat),
    /// or "" for anything else. InputError when stdin ends first.
    std::string askYesNo(const std::string& question);
    /// Writes "? prompt" and reads one line as typed (trimmed). InputError when stdin ends.
    std::string askLine(const std::string& prompt);

private:
    std::string readLine();
    std::string pending_;
    bool closed_ = false;
};

} // namespace armadillo::cli
