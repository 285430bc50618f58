#pragma once
// Self-voicing (issue 26): what a reader who cannot see the screen hears. JUCE-free, called from
// the front end's own (non-audio) thread only: every backend may block briefly or start a
// process. Backends:
//   speechd  — speech-dispatcher through libspeechd (what Orca uses), loaded at run time with
//              dlopen("libspeechd.so.2") so the program runs where it is not installed;
//              declarations as in /usr/include/speech-dispatcher/libspeechd.h (0.11).
//   espeak   — the espeak-ng program, one child process per utterance (stopped to interrupt).
//   capture  — appends each utterance to a file, one line "say: TEXT" / "stop" (tests).
// makeSpeech("auto") tries speechd, then espeak.
#include <memory>
#include <string>

namespace armadillo::access {

class Speech {
public:
    virtual ~Speech() = default;
    /// Speaks `text`. interrupt = true cuts off what is being said first (a new prompt);
    /// false queues it after (where the backend can queue; espeak interrupts always).
    virtual void say(const std::string& text, bool interrupt) = 0;
    /// Stops speaking now.
    virtual void stop() = 0;
    /// Rate −100 (slowest) … 0 (the voice's default) … +100 (fastest).
    virtual void setRate(int rate) = 0;
    virtual std::string name() const = 0;
};

/// `spec`: auto, speechd, espeak, capture:FILE, none (nullptr). On failure returns nullptr and
/// says why in `why` (no speech-dispatcher running, espeak-ng not installed, …).
std::unique_ptr<Speech> makeSpeech(const std::string& spec, std::string& why);

} // namespace armadillo::access
