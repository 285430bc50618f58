#pragma once
// Self-voicing and a braille display for the standalone app and the plugin's editor (issue 26).
// JUCE 7.0.5 has no screen-reader bridge on Linux, so the app speaks for itself: every
// announcement of the panels (prompts, answers, feedback, status changes: plugin::announce in
// Accessibility.h) is said through the core's Speech (speech-dispatcher, else espeak-ng) and
// written to a refreshable braille display through the core's BrailleDisplay (BrlAPI). JUCE-free.
//
// Threads: say()/repeat()/stop()/setRate() are called from the message thread (never the audio
// thread) and only queue; one worker thread of this class talks to the backends (which may
// block or start a process) and polls the display's keys, handed back by takeKeys().
#include "Access/BrailleDisplay.h"
#include "Access/Speech.h"
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace armadillo::access {

class ReaderVoice {
public:
    ReaderVoice();
    ~ReaderVoice();
    ReaderVoice(const ReaderVoice&) = delete;
    ReaderVoice& operator=(const ReaderVoice&) = delete;

    /// Opens the backends (specs of access::makeSpeech / makeBrailleDisplay: auto, speechd,
    /// espeak, capture:FILE, none; brlapi, brlapi:HOST, capture:FILE, none), replacing the open
    /// ones. Returns "" or what could not be opened (the other one still works).
    std::string open(const std::string& speechSpec, const std::string& displaySpec);
    /// Closes both (what is queued is dropped).
    void close();
    bool speaking() const;     ///< a speech backend is open
    bool showing() const;      ///< a braille display is open

    /// Says `text` and shows it on the display. interrupt = cut off what is being said.
    void say(const std::string& text, bool interrupt = true);
    /// Says the last text again (the repeat key).
    void repeat();
    /// Stops speaking now (what is queued is dropped).
    void stop();
    /// −100 … +100 (0 = the voice's default).
    void setRate(int rate);
    int rate() const;
    std::string lastSaid() const;
    /// Keys typed on the braille display since the last call (Access/BrailleDisplay.h readKey:
    /// characters, "\n" Enter, "\b" Backspace).
    std::string takeKeys();
    /// Waits until the worker has handed everything queued to the backends (tests, shutdown).
    void waitIdle();

    /// Whether a screen reader or braille display seems to be in use: a process named orca,
    /// brltty or speech-dispatcher under `procDir`, or one of `sockets` exists. The app turns
    /// self-voicing on by default when this is true.
    static bool readerDetected(const std::string& procDir, const std::vector<std::string>& sockets);
    /// The places BrlAPI and speech-dispatcher listen on this system ($XDG_RUNTIME_DIR).
    static std::vector<std::string> defaultSockets();

private:
    struct Op {
        enum class Kind { Say, Stop, Rate } kind;
        std::string text;
        bool interrupt = true;
        int rate = 0;
    };
    void run();
    void dropQueuedSpeech();   ///< under mutex_

    mutable std::mutex mutex_;
    std::condition_variable wake_, idle_;
    std::deque<Op> ops_;
    bool busy_ = false, quit_ = false;
    std::unique_ptr<access::Speech> speech_;
    std::unique_ptr<access::BrailleDisplay> display_;
    std::string last_, keys_;
    int rate_ = 0;
    std::thread worker_;
};

} // namespace armadillo::access
