#pragma once
// A refreshable braille display (issue 26): the prompt, the answer typed and the feedback are
// written to it, and its own keys answer. JUCE-free; used from the front end's own thread.
// Backends:
//   brlapi  — brltty's BrlAPI (libbrlapi, loaded at run time with dlopen("libbrlapi.so.0.8") so
//             the program runs where it is not installed; declarations as in /usr/include/brlapi.h
//             and brlapi_keycodes.h of brltty 6.5). Tty mode on the default tty: text written
//             with brlapi_writeText (brltty's text table turns it into dots); keys typed on the
//             display's braille keyboard arrive as characters, Enter submits.
//   capture — appends each write to a file as a line "write: TEXT" (tests).
#include <memory>
#include <string>

namespace armadillo::access {

class BrailleDisplay {
public:
    virtual ~BrailleDisplay() = default;
    /// Shows `text` (cut to the display's width by the display).
    virtual void write(const std::string& text) = 0;
    /// A key typed on the display, without waiting: a character (UTF-8), "\n" for Enter,
    /// "\b" for Backspace, "" when none (or a key this program does not use).
    virtual std::string readKey() = 0;
    /// The file descriptor to poll for keys (−1 when there is none).
    virtual int fd() const = 0;
    /// True once the display's connection is gone (the server closed it, an error).
    virtual bool lost() const { return false; }
    virtual std::string name() const = 0;
};

/// `spec`: brlapi (host from $BRLAPI_HOST, else the local brltty), brlapi:HOST (e.g. ":0",
/// "localhost:1"), capture:FILE, none (nullptr). On failure nullptr and the reason in `why`.
std::unique_ptr<BrailleDisplay> makeBrailleDisplay(const std::string& spec, std::string& why);

} // namespace armadillo::access
