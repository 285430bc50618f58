#include "Cli/ReaderIo.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <iostream>
#include "Access/Chords.h"
#include <poll.h>
#include <termios.h>
#include <unistd.h>

namespace armadillo::cli {

std::vector<OptionSpec> readerIoOptionSpecs()
{
    return {
        {"--speak", "", "speak every prompt, answer, feedback and status (speech-dispatcher, else espeak-ng)"},
        {"--speech", "BACKEND", "speak through: auto, speechd, espeak, capture:FILE (a line per utterance; tests)"},
        {"--rate", "N", "speech rate -100 (slow) .. 0 (the voice's own) .. 100 (fast); '>' and '<' lines change it"},
        {"--brlapi", "", "write prompts and feedback to the braille display (brltty's BrlAPI); its keys answer"},
        {"--braille-display", "SPEC", "brlapi, brlapi:HOST (e.g. localhost:1) or capture:FILE (a line per write; tests)"},
    };
}

ReaderIo::ReaderIo(const CommandLine& cl, bool armOnly) : armOnly_(armOnly)
{
    std::string why;
    // speech-dispatcher and brltty are sockets: one that goes away must be an error the
    // backends see (EPIPE), not SIGPIPE ending the reader's session.
    if (cl.has("--speak") || cl.has("--speech") || cl.has("--brlapi") || cl.has("--braille-display")) std::signal(SIGPIPE, SIG_IGN);
    if (cl.has("--speak") || cl.has("--speech")) {
        const std::string spec = cl.value("--speech", "auto");
        speech_ = access::makeSpeech(spec, why);
        if (!speech_) {
            if (why.rfind("unknown", 0) == 0) throw UsageError("--speech: " + why);
            throw core::IoError("cannot speak: " + why);
        }
        rate_ = static_cast<int>(cl.integer("--rate", 0, -100, 100));
        if (cl.has("--rate")) speech_->setRate(rate_);
    } else if (cl.has("--rate")) {
        throw UsageError("--rate sets the speech rate: use it with --speak");
    }
    if (cl.has("--brlapi") || cl.has("--braille-display")) {
        const std::string spec = cl.value("--braille-display", "brlapi");
        display_ = access::makeBrailleDisplay(spec, why);
        if (!display_) {
            if (why.rfind("unknown", 0) == 0) throw UsageError("--braille-display: " + why);
            throw core::IoError("no braille display: " + why);
        }
    }
}

struct ReaderIo::SavedTerminal {
    termios before {};
};

ReaderIo::~ReaderIo()
{
    if (saved_) ::tcsetattr(STDIN_FILENO, TCSANOW, &saved_->before);
}

bool ReaderIo::enableChordKeys()
{
    if (::isatty(STDIN_FILENO) != 1) return false;
    auto saved = std::make_unique<SavedTerminal>();
    if (::tcgetattr(STDIN_FILENO, &saved->before) != 0) return false;
    termios raw = saved->before;
    raw.c_lflag &= static_cast<tcflag_t>(~(ICANON | ECHO));
    raw.c_cc[VMIN] = 1;
    raw.c_cc[VTIME] = 0;
    if (::tcsetattr(STDIN_FILENO, TCSANOW, &raw) != 0) return false;
    saved_ = std::move(saved);
    chordKeys_ = true;
    return true;
}

/// One key in raw Perkins mode; true when `line` holds something for readLine() to return.
bool ReaderIo::takeChordKey(char c, std::string& line)
{
    const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (std::string("sdfjkl").find(lower) != std::string::npos) {
        if (keysCell_.find(lower) == std::string::npos) keysCell_ += lower;
        return false;
    }
    if (c == ' ' || c == '\r' || c == '\n') {
        if (!keysCell_.empty()) {
            std::string letter, why;
            const bool ok = access::chordsToLetters(keysCell_, letter, why);
            keysLine_ += (keysLine_.empty() ? "" : " ") + keysCell_;
            keysCell_.clear();
            speak(ok ? letter : "dots " + why, true);
            if (display_) display_->write(keysLine_);
            if (c == ' ') return false;
        }
        if (keysLine_.empty()) return false;
        line = keysLine_;
        keysLine_.clear();
        return true;
    }
    if (c == 0x7F || c == '\b') {   // Backspace: the last dot, else the last cell
        if (!keysCell_.empty()) keysCell_.pop_back();
        else if (const auto sp = keysLine_.find_last_of(' '); sp != std::string::npos) keysLine_.erase(sp);
        else keysLine_.clear();
        return false;
    }
    if (std::string("?-!<>").find(c) != std::string::npos) {
        line = std::string(1, c);
        return true;
    }
    return false;   // any other key: nothing
}

void ReaderIo::speak(const std::string& text, bool interrupt)
{
    if (speech_) speech_->say(text, interrupt);
}

void ReaderIo::status(const std::string& text)
{
    if (!armOnly_) std::cerr << text << "\n" << std::flush;
    speak(text, false);
    if (display_) display_->write(text);
}

void ReaderIo::note(const std::string& text)
{
    if (!armOnly_) std::cerr << "  " << text << "\n" << std::flush;
    speak(text, false);
    if (display_) display_->write(text);
}

void ReaderIo::prompt(const std::string& text, const std::string& brief)
{
    if (!armOnly_) std::cerr << "? " << text << "\n" << std::flush;
    speak(text, true);
    if (display_) display_->write(brief.empty() ? text : brief);
}

std::string ReaderIo::readLine()
{
    for (;;) {
        std::string line;
        bool got = false;
        if (const auto nl = pending_.find('\n'); nl != std::string::npos) {
            line = pending_.substr(0, nl);
            pending_.erase(0, nl + 1);
            got = true;
        } else if (const auto dnl = displayLine_.find('\n'); dnl != std::string::npos) {
            line = displayLine_.substr(0, dnl);
            displayLine_.erase(0, dnl + 1);
            got = true;
        } else if (closed_ && !pending_.empty()) {   // a last line without a newline still counts
            pending_ += '\n';
            continue;
        } else if (closed_ && !display_) {
            throw AnswersEnded();
        }
        if (got) {
            const auto b = line.find_first_not_of(" \t\r");
            line = b == std::string::npos ? "" : line.substr(b, line.find_last_not_of(" \t\r") - b + 1);
            if (line == "!") {
                if (speech_) speech_->stop();
                continue;
            }
            if (line == ">" || line == "<") {
                rate_ = std::clamp(rate_ + (line == ">" ? 20 : -20), -100, 100);
                if (speech_) {
                    speech_->setRate(rate_);
                    speech_->say("rate " + std::to_string(rate_), true);
                }
                continue;
            }
            if (display_) display_->write(line);   // the answer, as typed, on the display
            return line;
        }
        if (interrupted()) throw core::IoError("interrupted");
        if (extra_)
            if (std::string x = extra_(); !x.empty()) {
                pending_ += x + "\n";
                continue;
            }
        pollfd p[2] {{closed_ ? -1 : STDIN_FILENO, POLLIN, 0}, {display_ ? display_->fd() : -1, POLLIN, 0}};
        if (::poll(p, 2, 100) <= 0) continue;
        if (p[0].revents) {
            char buf[512];
            const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
            if (n > 0 && chordKeys_) {
                for (ssize_t i = 0; i < n; ++i) {
                    std::string keyLine;
                    if (takeChordKey(buf[i], keyLine)) pending_ += keyLine + "\n";
                }
            } else if (n > 0) {
                pending_.append(buf, static_cast<std::size_t>(n));
            } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
                closed_ = true;
            }
        }
        if (p[1].revents && display_)
            for (std::string k; !(k = display_->readKey()).empty();) {
                if (k == "\b") {
                    if (!displayLine_.empty()) displayLine_.pop_back();
                } else {
                    displayLine_ += k;
                }
            }
        if (display_ && (display_->lost() || (p[1].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0))
            throw core::IoError("the braille display (" + display_->name() + ") went away");
    }
}

std::string ReaderIo::askYesNo(const std::string& question)
{
    prompt(question);
    std::string a = readLine();
    std::transform(a.begin(), a.end(), a.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (a == "y" || a == "yes") return "y";
    if (a == "n" || a == "no") return "n";
    if (a == "r" || a == "?" || a == "repeat") return "r";
    note("answer y (felt) or n (not felt); r shows it again");
    return "";
}

} // namespace armadillo::cli
