#pragma once
// The reader's side of the guided command-line procedures (touch-profile, adaptive braille
// training): prompts, statuses, feedback and answers, for a reader who may not see the screen.
//   • written on stderr, one line each (prompts that want an answer start with "? "), unless
//     --arm-only (then nothing is written but errors: the arm says everything);
//   • spoken (--speak / --speech BACKEND, --rate N): a prompt interrupts what is being said,
//     feedback and statuses are queued after it; speaking happens on this (the main) thread;
//   • written to a braille display (--brlapi / --braille-display SPEC), whose keys also answer.
// Answers are lines from stdin or the display. Lines that are commands, not answers:
//   "!" stop speaking, ">" faster, "<" slower (rate ± 20). "?" (repeat) and "-" (skip) are
//   returned to the procedure, which knows what to repeat.
#include "Access/BrailleDisplay.h"
#include "Access/Speech.h"
#include "Cli/CommandLine.h"
#include "Core/Errors.h"
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::cli {

/// Options of every reader-facing procedure: --speak, --speech, --rate, --brlapi, --braille-display.
std::vector<OptionSpec> readerIoOptionSpecs();

/// readLine()'s "the answers ended" (standard input closed, no display to answer from): an
/// InputError for a procedure that needs every answer, and a normal end for one that can stop
/// early and keep what was answered (the adaptive training).
struct AnswersEnded : core::InputError {
    AnswersEnded() : core::InputError("stdin", 0, "", "the answers ended before the procedure was complete") {}
};

class ReaderIo {
public:
    /// Opens the speech and display backends asked for; UsageError for a bad spec, IoError
    /// when one that was asked for cannot be opened (the reader must know, not guess).
    explicit ReaderIo(const CommandLine& cl, bool armOnly = false);
    /// A state change ("now a comfortable level…").
    void status(const std::string& text);
    /// Feedback or a remark, indented on the screen; spoken after what is being said.
    void note(const std::string& text);
    /// "? text": spoken at once (interrupting), shown on the display as `brief` (or text).
    void prompt(const std::string& text, const std::string& brief = {});
    /// prompt(question), then one line: "y" or "n" (also yes/no, any case), "r"/"?" (repeat),
    /// or "" for anything else. AnswersEnded (an InputError) when the answers end first.
    std::string askYesNo(const std::string& question);
    /// One answer line as typed (trimmed), commands handled. AnswersEnded when the answers end;
    /// IoError("interrupted") after SIGINT/SIGTERM.
    std::string readLine();
    /// Perkins keys on a terminal (stdin a tty): raw mode, no echo. S D F J K L add dots 3 2 1 4 5 6
    /// to the cell being typed, Space ends the cell (its letter is spoken), Space on an empty cell
    /// or Enter submits the answer, Backspace takes back a dot or the last cell; ? - ! > < act at
    /// once. readLine() then returns the cells as a line of chord groups ("fd fk"). The terminal
    /// is restored by the destructor. Returns false (nothing changed) when stdin is not a tty.
    bool enableChordKeys();
    ~ReaderIo();
    /// Another source of answer lines, asked while waiting (every 0.1 s): "" = nothing. The
    /// adaptive training's arm gestures come in this way ("?" repeat, "-" skip).
    void setExtraInput(std::function<std::string()> source) { extra_ = std::move(source); }
    bool speaking() const noexcept { return speech_ != nullptr; }
    bool hasDisplay() const noexcept { return display_ != nullptr; }

private:
    void speak(const std::string& text, bool interrupt);
    std::unique_ptr<access::Speech> speech_;
    std::unique_ptr<access::BrailleDisplay> display_;
    int rate_ = 0;
    bool armOnly_ = false;
    std::string pending_, displayLine_;
    bool closed_ = false;
    bool chordKeys_ = false;
    std::function<std::string()> extra_;
    std::string keysCell_, keysLine_;   // raw Perkins mode: the cell being typed, the cells typed
    struct SavedTerminal;
    std::unique_ptr<SavedTerminal> saved_;
    bool takeChordKey(char c, std::string& line);
};

} // namespace armadillo::cli
